"""Family and spatial robots refuse parameters whose effects overflow float64 up front (issue 33).

Library: the dataclass raises a ParameterError naming the key.  CLI: one line, exit 2, the
robot file's key and its line named, no numpy "warning:" line.  A large but finite design is
accepted, and its results are those of the linearity of the dynamics in the payload's mass.
"""

from __future__ import annotations

import re
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from prp3.errors import ParameterError
from prp3.family.model import Body, FamilyRobot, PlatformBody
from prp3.model.parameters import Load, Payload

ROOT = Path(__file__).resolve().parents[1]

FAMILY_CASES = [
    ("payload.mass", {"payload": Payload(mass=1e308)}),
    ("payload.com", {"payload": Payload(mass=1.0, com=(1e200, 0.0))}),
    # one inertia of 1e308 is finite, and so is the robot's total: two whose sum is not
    (
        "payload.inertia",
        {"payload": Payload(inertia=1.7e308), "platform": PlatformBody(3.0, 1e308)},
    ),
    ("link1.mass", {"link1": Body(1e308, (0.1, 0.0), 0.0, name="link1")}),
    ("link2.inertia", {"link2": Body(0.75, (0.1, 0.0), 1e308, name="link2")}),
    (
        "platform.inertia",
        {"platform": PlatformBody(3.0, 1.7e308), "payload": Payload(inertia=1e308)},
    ),
    ("load.force", {"load": Load(force=(1.7e308, 1.7e308))}),  # |F| = 2.4e308
    ("gravity", {"gravity": (0.0, -1e308)}),
]


@pytest.mark.parametrize("architecture", ["3-RRR", "3-RPR", "3-PRR"])
@pytest.mark.parametrize(("key", "change"), FAMILY_CASES)
def test_family_robot_refuses_overflow(architecture: str, key: str, change: dict) -> None:
    base = FamilyRobot.default(architecture)
    with pytest.raises(ParameterError) as caught:
        replace(base, **change)
    assert caught.value.key == key
    assert "overflow" in caught.value.reason


def _cli(tmp_path: Path, *args: str) -> subprocess.CompletedProcess[str]:
    env = {"PYTHONPATH": str(ROOT / "src"), "PATH": "/usr/bin:/bin"}
    return subprocess.run(
        [sys.executable, "-m", "prp3", *args],
        cwd=tmp_path, capture_output=True, text=True, env=env, timeout=120, check=False,
    )  # fmt: skip


def _template(tmp_path: Path, architecture: str) -> list[str]:
    done = _cli(tmp_path, "robot", "--template", "--architecture", architecture)
    assert done.returncode == 0, done.stderr
    return done.stdout.splitlines()


def _set(lines: list[str], table: str | None, key: str, value: str) -> tuple[str, int]:
    """The file with ``key`` of ``[table]`` set to ``value``, and that line's number."""
    current: str | None = None
    for number, line in enumerate(lines, 1):
        header = re.match(r"\[(\w+)\]", line)
        if header:
            current = header.group(1)
        elif current == table and line.startswith(f"{key} ="):
            out = [*lines[: number - 1], f"{key} = {value}", *lines[number:]]
            return "\n".join(out) + "\n", number
    raise AssertionError(f"no {table}.{key} in the template")


CLI_CASES = [
    ("3-RRR", "payload", "mass", "1e308", "payload.mass", "vertical"),
    ("3-RRR", "payload", "com", "[1e200, 0.0]", "payload.com", "vertical"),
    ("3-RRR", "link2", "inertia", "1e308", "link2.inertia", "vertical"),  # three legs: 3e308
    ("3-RPR", "link2", "mass", "1e308", "link2.mass", "vertical"),
    ("3-RRR", None, "gravity", "[0.0, -1e308]", "gravity", "vertical"),
    ("6-UPS", "platform", "mass", "1e308", "platform.mass", "heave"),
    ("6-UPS", "rod", "inertia", "[[1e308, 0, 0], [0, 1e308, 0], [0, 0, 1e308]]",
     "rod.inertia", "heave"),
    ("6-UPS", "cylinder", "centre", "[1e200, 0, 0]", "cylinder.centre", "heave"),
    ("3-RUU", "forearm_body", "inertia", "[[1e308, 0, 0], [0, 1e308, 0], [0, 0, 1e308]]",
     "forearm_body.inertia", "heave"),
    ("3-RPS", None, "gravity", "[0.0, 0.0, -1.79e308]", "gravity", "heave"),
]  # fmt: skip


@pytest.mark.parametrize(("arch", "table", "key", "value", "named", "motion"), CLI_CASES)
def test_cli_names_the_robot_files_key_and_line(
    tmp_path: Path, arch: str, table: str | None, key: str, value: str, named: str, motion: str
) -> None:
    text, number = _set(_template(tmp_path, arch), table, key, value)
    (tmp_path / "r.toml").write_text(text, encoding="utf-8")
    done = _cli(tmp_path, "simulate", "--robot", "r.toml", "--motion", motion, "-o", "out")
    assert done.returncode == 2
    lines = done.stderr.splitlines()
    assert len(lines) == 1, done.stderr
    assert "warning:" not in done.stderr and "Traceback" not in done.stderr
    assert f"r.toml:{number}: " in lines[0] and named in lines[0], lines[0]
    assert "overflow" in lines[0]
    assert not (tmp_path / "out").exists()


def test_family_large_but_finite_payload_is_accepted_and_linear() -> None:
    """Inverse dynamics is linear in the payload's mass: ``τ(M) = τ(0) + M·(τ(1) − τ(0))``."""
    from prp3 import family_inverse_dynamics
    from prp3.model.motion import Motion

    base = FamilyRobot.default("3-RRR")
    motion = Motion.at_rest(np.asarray(base.home_poses[0], dtype=np.float64))
    tau = {
        m: np.asarray(family_inverse_dynamics(replace(base, payload=Payload(mass=m)), motion).tau)
        for m in (0.0, 1.0, 1e300)
    }
    expected = 1e300 * (tau[1.0] - tau[0.0])
    assert np.isfinite(tau[1e300]).all()
    np.testing.assert_allclose(tau[1e300], expected, rtol=1e-9)


def test_spatial_library_refuses_and_accepts() -> None:
    from prp3.spatial.model import Body as SpatialBody
    from prp3.spatial.model import hexapod

    robot = hexapod()
    big = SpatialBody(1e308, (0.0, 0.0, 0.0), robot.platform.inertia, "platform")
    with pytest.raises(ParameterError) as caught:
        replace(robot, platform=big)
    assert caught.value.key == "platform.mass"
    huge = SpatialBody(1.0, (0.0, 0.0, 0.0), np.diag([1e308, 1e308, 1e308]), "rod")
    with pytest.raises(ParameterError) as caught:  # six rods: their total inertia overflows
        replace(robot, legs=tuple(replace(leg, bodies=(leg.bodies[0], huge)) for leg in robot.legs))
    assert caught.value.key == "rod.inertia"
    with pytest.raises(ParameterError) as caught:
        replace(robot, gravity=(0.0, 0.0, -1e308))
    assert caught.value.key == "gravity"
    fine = SpatialBody(1e300, (0.0, 0.0, 0.0), np.diag([1e300, 1e300, 2e300]), "platform")
    accepted = replace(robot, platform=fine)
    assert accepted.platform.inertia[2][2] == 2e300


def test_spatial_inertia_near_overflow_is_checked_not_a_linalg_error() -> None:
    from prp3.spatial.model import Body as SpatialBody

    body = SpatialBody(1.0, (0.0, 0.0, 0.0), np.diag([1.7e308, 1.7e308, 1.7e308]), "rod")
    assert body.inertia[0][0] == 1.7e308
    with pytest.raises(ParameterError, match="principal moments"):
        SpatialBody(1.0, (0.0, 0.0, 0.0), np.diag([1e308, 1e307, 1.7e308]), "rod")


# --- efforts files whose cubic spline float64 cannot hold (issue 33's siblings) -------------

SPLINE_CASES = [
    ("0.5,1e308", "1,-1e308", "the slope overflows"),
    ("5e-324,1", "1e-323,0", "overflows"),
]


@pytest.mark.parametrize(("row1", "row2", "why"), SPLINE_CASES)
@pytest.mark.parametrize("arch", ["3-RRR", "6-UPS"])
def test_forward_refuses_efforts_their_spline_cannot_hold(
    tmp_path: Path, arch: str, row1: str, row2: str, why: str
) -> None:
    legs = 6 if arch == "6-UPS" else 3
    names = [f"tau_{k + 1}" for k in range(6)] if legs == 6 else ["tau_A", "tau_B", "tau_C"]
    pad = ",0" * (legs - 1)
    rows = ["t," + ",".join(names), "0" + ",0" * legs, row1 + pad, row2 + pad]
    (tmp_path / "E.csv").write_text("\n".join(rows) + "\n", encoding="utf-8")
    (tmp_path / "r.toml").write_text("\n".join(_template(tmp_path, arch)) + "\n")
    option = "--efforts" if legs == 6 else "--forces"
    done = _cli(tmp_path, "forward", "--robot", "r.toml", option, "E.csv", "-o", "out")
    assert done.returncode == 2, done.stderr
    lines = done.stderr.splitlines()
    assert len(lines) == 1 and "Traceback" not in done.stderr and "warning:" not in done.stderr
    assert "E.csv:2: sample 0, t = 0 s: " in lines[0] and why in lines[0], lines[0]  # its line
    assert not (tmp_path / "out").exists()


def test_checked_spline_accepts_what_float64_holds_and_matches_scipy() -> None:
    """Small steps and large values that fit: the spline is scipy's, to the bit; steps of
    1e-300 s with values of 1 are refused (its cubic coefficients ~ v/dt^3 overflow, where
    scipy would give inf silently)."""
    from scipy.interpolate import CubicSpline

    from prp3.validation import checked_spline

    rng = np.random.default_rng(3)
    for scale_t, scale_v in ((1e-100, 1.0), (1.0, 1e300), (1e-3, 1e-3)):
        t = np.cumsum(rng.uniform(0.5, 1.5, 6)) * scale_t
        v = rng.normal(size=(6, 3)) * scale_v
        ours, theirs = checked_spline("efforts", t, v), CubicSpline(t, v, axis=0)
        assert np.isfinite(ours.c).all()
        np.testing.assert_array_equal(ours.c, theirs.c)
    t = np.cumsum(rng.uniform(0.5, 1.5, 6)) * 1e-300
    with np.errstate(all="ignore"):
        assert not np.isfinite(CubicSpline(t, rng.normal(size=(6, 3)), axis=0).c).all()
    with pytest.raises(ParameterError, match="does not fit in float64"):
        checked_spline("efforts", t, rng.normal(size=(6, 3)))


def test_library_forward_refuses_subnormal_effort_steps() -> None:
    from prp3.family.forward import family_forward_dynamics

    robot = FamilyRobot.default("3-RRR")
    t = np.array([0.0, 5e-324, 1e-323])
    tau = np.array([[0.0, 0, 0], [1.0, 0, 0], [0.0, 0, 0]])
    pose = np.asarray(robot.home_poses[0], dtype=np.float64)
    with pytest.raises(ParameterError) as caught:
        family_forward_dynamics(robot, t, tau, t, pose, np.zeros(3))
    assert caught.value.key == "efforts" and caught.value.sample == 0


@pytest.mark.parametrize("arch", ["3-RRR", "3-PRP"])
def test_identify_names_the_measurements_line_of_an_overflowing_value(
    tmp_path: Path, arch: str
) -> None:
    t = np.linspace(0.0, 1.0, 50)
    columns = ("tau_A", "tau_B", "tau_C") if arch != "3-PRP" else ("f10_A", "f10_B", "f10_C")
    rows = [
        [v, 0.01 * np.sin(2 * np.pi * v), 0.01 * np.cos(2 * np.pi * v) - 0.01,
         0.05 * np.sin(4 * np.pi * v), 1.0, 2.0, 3.0]
        for v in t
    ]  # fmt: skip
    rows[10][4] = 1e308  # sample 10: line 12 of the file
    text = ",".join(("t", "x", "y", "phi", *columns)) + "\n"
    text += "".join(",".join(repr(float(v)) for v in row) + "\n" for row in rows)
    (tmp_path / "M.csv").write_text(text, encoding="utf-8")
    if arch == "3-PRP":  # the model form of docs/model.md
        (tmp_path / "r.toml").write_text(_cli(tmp_path, "robot", "--template").stdout)
    else:
        (tmp_path / "r.toml").write_text("\n".join(_template(tmp_path, arch)) + "\n")
    done = _cli(tmp_path, "identify", "--robot", "r.toml", "--measurements", "M.csv", "-o", "out")
    assert done.returncode == 2, done.stderr
    lines = [line for line in done.stderr.splitlines() if "warning: the derivatives" not in line]
    assert len(lines) == 1 and "Traceback" not in done.stderr, done.stderr
    assert "M.csv:12: " in lines[0] and "1e+308" in lines[0] and "overflow" in lines[0], lines
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(
    ("arch", "table", "key", "value", "motion"),
    [("3-RRR", "payload", "mass", "1e300", "vertical"), ("6-UPS", "platform", "mass", "1e300", "heave")],
)  # fmt: skip
def test_cli_accepts_a_large_but_finite_design(
    tmp_path: Path, arch: str, table: str, key: str, value: str, motion: str
) -> None:
    text, _ = _set(_template(tmp_path, arch), table, key, value)
    (tmp_path / "r.toml").write_text(text, encoding="utf-8")
    done = _cli(tmp_path, "simulate", "--robot", "r.toml", "--motion", motion, "-o", "out")
    assert done.returncode == 0, done.stderr
    assert "warning:" not in done.stderr
    table_ = np.genfromtxt(tmp_path / "out" / "results.csv", delimiter=",", names=True)
    values = np.array(table_.tolist(), dtype=np.float64)
    assert np.isfinite(values).all() and np.abs(values).max() > 1e299
