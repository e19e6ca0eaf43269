"""Bad input, what was left of issue 33: a family robot's absurd ``[load]`` named in its own
file, the public readers of the spatial and family files fed hostile input, and hostile
values on the family and spatial commands (one line, exit 2, nothing written)."""

from __future__ import annotations

import re
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import prp3
import prp3.cli
from clitools import cli, one_line
from prp3.errors import Prp3Error

FORCES = "t,tau_A,tau_B,tau_C\n0.0,0.0,0.0,0.0\n0.5,0.0,0.0,0.0\n1.0,0.0,0.0,0.0\n"


@pytest.mark.parametrize(
    ("load", "key", "line"),
    [
        ("force = [1e12, 0.0]\nmoment = 0.0\n", "load.force", 4),
        ("force = [0.0, -1e308]\n", "load.force", 4),  # finite wrench: refused by the bound
        ("force = [1.7e308, -1.7e308]\n", "load.force", 4),  # |F| overflows: up front
        ("moment = 0.0\nforce = [0.0, 0.0]\n", None, None),
        ("force = [1.0, 0.0]\nmoment = 1e300\n", "load.moment", 5),
        ("moment = 1e300\nforce = [1.0, 0.0]\n", "load.moment", 4),
    ],
)
def test_an_absurd_family_load_names_the_robot_file_key_and_line(capsys, tmp_path, load, key, line):
    robot = tmp_path / "rrr.toml"
    robot.write_text(f'architecture = "3-RRR"\nactuated = 1\n[load]\n{load}', encoding="utf-8")
    (tmp_path / "zero.csv").write_text(FORCES, encoding="utf-8")
    status, _, err = cli(capsys, "forward", "--robot", robot, "--forces", tmp_path / "zero.csv",
                         "--samples", 3, "--output", tmp_path / "out")  # fmt: skip
    if key is None:  # no load: the zero efforts only let it fall, no refusal
        assert "beyond the bound" not in err and status in (0, 1), err
        return
    text = one_line(err)
    if "1.7e308" in load:  # refused up front, on reading the robot file (its wrench overflows)
        assert status == 2 and f"rrr.toml:{line}: robot: {key} = " in text, text
        assert "overflows float64" in text and "zero.csv" not in text
        return
    assert status == 2 and f"rrr.toml:{line}: {key} = " in text, text
    assert f"beyond the bound {prp3.MAX_ACCELERATION:g}" in text and "zero.csv" not in text
    assert not (tmp_path / "out").exists()


def test_an_absurd_family_load_is_refused_by_the_function_too():
    robot = prp3.FamilyRobot.from_mapping({"architecture": "3-RPR", "load": {"moment": -1e9}})
    with pytest.raises(prp3.ParameterError, match=r"load.moment = -1000000000.0 alone") as caught:
        prp3.family_forward_dynamics(robot, [0.0, 1.0], np.zeros((2, 3)), [0.0, 0.5],
                                     robot.home_poses[0], np.zeros(3))  # fmt: skip
    assert caught.value.key == "load.moment"


# ------------------------------------------------ the public readers fed hostile files
T = [0.1 * k for k in range(11)]
TRAJECTORY = "t,x,y,z,qw,qx,qy,qz\n" + "".join(f"{t!r},0,0,{0.08 + 0.001 * k!r},1,0,0,0\n"
                                               for k, t in enumerate(T))  # fmt: skip
EFFORTS = (
    "t,"
    + ",".join(f"tau_{i}" for i in range(1, 7))
    + "\n"
    + "".join(f"{t!r},1.5,-2.0,0.25,1e-3,3,4\n" for t in T)
)
MEASURED = (
    "t,x,y,z,qw,qx,qy,qz,"
    + ",".join(f"tau_{i}" for i in range(1, 7))
    + "\n"
    + "".join(f"{t!r},0,0,{0.08 + 0.001 * k!r},1,0,0,0,1,2,3,4,5,6\n" for k, t in enumerate(T))
)
SPATIAL_SPEC = ('spatial = "3-RPS"\ndesigns = 2\n[parameters]\nbase_radius = [0.1, 0.2]\n'
                '[task]\nmotions = ["heave"]\nsamples = 5\n')  # fmt: skip
FAMILY_SPEC = ('designs = 2\n[task]\nmotions = ["vertical"]\nsamples = 5\n[[study]]\n'
               'architecture = "3-RPR"\n[study.parameters]\n"link2.mass" = [0.5, 1.0]\n')  # fmt: skip


READERS: dict[str, tuple[str, str, Any]] = {
    # name: (file name, good text, call(path))
    "read_spatial_robot": ("robot.toml", 'architecture = "6-UPS"\n[platform]\nmass = 3.0\n',
                           prp3.read_spatial_robot),
    "read_robot_file": ("rrr.toml", 'architecture = "3-RRR"\nactuated = 2\n[load]\nmoment = 0.1\n',
                        prp3.read_robot_file),
    "read_spatial_trajectory": ("t.csv", TRAJECTORY, prp3.read_spatial_trajectory),
    "read_spatial_efforts": ("e.csv", EFFORTS,
                             lambda path: prp3.read_spatial_efforts(path, prp3.hexapod())),
    "read_spatial_measurements": ("m.csv", MEASURED,
                                  lambda path: prp3.read_spatial_measurements(path, 6)),
    "read_spatial_sweep_spec": ("s.toml", SPATIAL_SPEC, prp3.read_spatial_sweep_spec),
    "read_family_sweep_spec": ("f.toml", FAMILY_SPEC, prp3.read_family_sweep_spec),
    "read_spatial_mjcf": ("r.xml", "", prp3.read_spatial_mjcf),  # text: the fixture's export
}  # fmt: skip

NUMBER = re.compile(r"(?<![\w.])-?\d+(\.\d+)?(e[-+]?\d+)?(?![\w.])")
HOSTILE_NUMBERS = ["nan", "inf", "-inf", "1e308", "-1e308", "1e-320", "1e-300", "0", "-0.0",
                   "1e999", "0x10", "true", '"1.0"', "[]", "{}", "1_0"]  # fmt: skip


@pytest.fixture(scope="module")
def good_files(tmp_path_factory: pytest.TempPathFactory) -> dict[str, str]:
    folder = tmp_path_factory.mktemp("good")
    (folder / "robot.toml").write_text(READERS["read_spatial_robot"][1], encoding="utf-8")
    assert prp3.cli.main(["export", "mjcf", "--robot", str(folder / "robot.toml"),
                          "--output", str(folder / "r.xml")]) == 0  # fmt: skip
    texts = {name: text for name, (_, text, _) in READERS.items()}
    texts["read_spatial_mjcf"] = (folder / "r.xml").read_text(encoding="utf-8")
    return texts


def _spoiled(draw: st.DrawFn, text: str) -> bytes | None:
    """The good text spoiled one way; ``None`` for no file at all."""
    how = draw(st.sampled_from(["number", "truncate", "bytes", "empty", "missing", "junk",
                                "huge", "line"]))  # fmt: skip
    data = text.encode()
    if how == "number":
        spots = list(NUMBER.finditer(text))
        spot = spots[draw(st.integers(0, len(spots) - 1))]
        value = draw(st.sampled_from(HOSTILE_NUMBERS))
        return (text[: spot.start()] + value + text[spot.end() :]).encode()
    if how == "truncate":
        return data[: draw(st.integers(0, len(data) - 1))]
    if how == "bytes":
        at = draw(st.integers(0, len(data) - 1))
        return data[:at] + draw(st.binary(min_size=1, max_size=8)) + data[at + 1 :]
    if how == "line":  # a line repeated or dropped
        lines = text.splitlines(keepends=True)
        k = draw(st.integers(0, len(lines) - 1))
        kept = lines[:k] + lines[k + 1 :] if draw(st.booleans()) else lines[: k + 1] + lines[k:]
        return "".join(kept).encode()
    if how == "junk":
        return draw(st.binary(min_size=1, max_size=64))
    if how == "huge":  # beyond every reader's bound
        return data + b"#" * (11 * 2**20)
    return None if how == "missing" else b""


@pytest.mark.parametrize("name", list(READERS))
@settings(max_examples=40, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])  # fmt: skip
@given(data=st.data())
def test_a_spatial_or_family_reader_fed_a_spoiled_file_refuses_it_in_one_line(
    tmp_path, good_files, name, data
):
    file_name, _, read = READERS[name]
    path = tmp_path / f"{data.draw(st.integers(0, 10**9))}-{file_name}"
    spoiled = _spoiled(data.draw, good_files[name])
    if spoiled is not None:
        path.write_bytes(spoiled)
    try:
        read(path)
    except Prp3Error as error:
        assert "\n" not in str(error).strip(), str(error)
    finally:
        path.unlink(missing_ok=True)


@pytest.mark.parametrize("name", list(READERS))
@pytest.mark.parametrize("path", [None, 3, 2.5, b"x.toml", ["a"], {"a": 1}, "", "\0", "folder"])
def test_a_spatial_or_family_reader_refuses_a_path_that_is_none(tmp_path, good_files, name, path):
    read = READERS[name][2]
    if path == "folder":
        path = tmp_path
    with pytest.raises(Prp3Error) as caught:
        read(path)
    assert "\n" not in str(caught.value).strip()


@pytest.mark.parametrize("name", list(READERS))
def test_a_good_file_is_read(tmp_path, good_files, name):
    file_name, _, read = READERS[name]
    (tmp_path / file_name).write_text(good_files[name], encoding="utf-8")
    assert read(tmp_path / file_name) is not None
