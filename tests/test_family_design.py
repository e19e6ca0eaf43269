"""Design studies across architectures (``[[study]]`` specs of docs/design.md).

The expected rows are rebuilt from the Newton–Euler route (an independent
solver) and the margins of docs/family.md §3; the model-form sweep is unchanged.
"""

from __future__ import annotations

import contextlib
import io
import math
import re
import runpy
import shlex
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

import prp3
import prp3.apps.cluster
import prp3.apps.sweep
from clitools import cli, one_line
from prp3.errors import Prp3Error
from prp3.family import FamilyRobot, family_inverse_dynamics
from prp3.family.design import (
    FAMILY_DESIGN_COLUMNS,
    evaluate_family_designs,
    family_design_rows,
    family_sweep_spec,
)
from prp3.model.motion import paper_motion
from sweeptools import interrupted_sweep


def _spec(studies: list[dict[str, object]], **extra: object) -> object:
    data = {"task": {"motions": ["vertical", "rotation"], "samples": 301}, "study": studies}
    return family_sweep_spec({**data, **extra})


@pytest.mark.parametrize("architecture", ["3-RRR", "3-RPR", "3-PPR"])
def test_a_row_is_the_newton_euler_solution(architecture: str) -> None:
    spec = _spec([{"architecture": architecture}], payload={"mass": 1.5, "com": [0.01, 0.0]})
    columns = evaluate_family_designs(spec.evaluator, family_design_rows(spec))  # type: ignore[attr-defined]
    assert str(columns["status"][0]) == "ok"
    robot = FamilyRobot.from_mapping({"architecture": architecture, "payload": {"mass": 1.5,
                                                                             "com": [0.01, 0.0]}})  # fmt: skip
    tau, force, energy = [], [], 0.0
    for name in ("vertical", "rotation"):
        motion = paper_motion(name, 301)
        solution = family_inverse_dynamics(robot, motion, method="newton-euler")
        tau.append(np.abs(solution.tau).max(axis=0))
        force.append(np.hypot(solution.force[..., 0], solution.force[..., 1]).max(axis=0))
        p = solution.power.sum(axis=-1)
        energy += float(np.sum((p[1:] + p[:-1]) / 2 * np.diff(motion.t)))
    peak_tau, peak_force = np.max(tau, axis=0), np.max(force, axis=0)
    for j, leg in enumerate("ABC"):
        assert columns[f"peak_tau_{leg}"][0] == pytest.approx(peak_tau[j], rel=1e-10)
        for k in (1, 2, 3):
            assert columns[f"peak_f{k}_{leg}"][0] == pytest.approx(peak_force[j, k - 1], rel=1e-10)
    assert columns["peak_joint_force"][0] == pytest.approx(peak_force.max(), rel=1e-10)
    assert columns["energy"][0] == pytest.approx(energy, rel=1e-9, abs=1e-9)


def test_margins_are_those_of_the_spec_table() -> None:
    """docs/family.md §3: 3-RRR 0.423/0.947 (vertical), 0.234/0.998 (rotation)."""
    spec = _spec([{"architecture": "3-RRR"}, {"architecture": "3-PPR"}])
    columns = evaluate_family_designs(spec.evaluator, family_design_rows(spec))  # type: ignore[attr-defined]
    assert round(float(columns["min_mu_leg"][0]), 3) == 0.234
    assert round(float(columns["min_mu_par"][0]), 3) == 0.947
    assert round(float(columns["min_mu_leg"][1]), 3) == 1.0
    assert round(float(columns["min_mu_par"][1]), 3) == 0.845


def test_statuses_of_designs_that_cannot_carry_the_task() -> None:
    spec = _spec(
        [
            {"architecture": "3-PRR", "actuated": 2},  # rotation crosses a parallel singularity
            {"architecture": "3-RRR", "parameters": {"leg.joint3.0": [0.02, 0.2]}},
        ],
        sampling="grid",
        designs=2,
    )
    rows = family_design_rows(spec)  # type: ignore[arg-type]
    assert rows == [(0, []), (1, [0.02]), (1, [0.2])]
    columns = evaluate_family_designs(spec.evaluator, rows)  # type: ignore[attr-defined]
    assert [str(s) for s in columns["status"]] == ["singular", "unreachable", "ok"]
    assert np.isnan(columns["peak_joint_force"][:2]).all()
    assert np.isnan(columns["leg.joint3.0"][0]) and columns["leg.joint3.0"][1] == 0.02
    # a singular home (3-RRR with link 2 along link 1 at home) is a row too
    invalid = _spec([{"architecture": "3-RRR", "parameters": {"leg.joint2.2": [0.0, math.pi / 2]}}],
                    sampling="grid", designs=2)  # fmt: skip
    columns = evaluate_family_designs(invalid.evaluator, family_design_rows(invalid))  # type: ignore[attr-defined, arg-type]
    assert [str(s) for s in columns["status"]] == ["invalid", "ok"]


TWICE = {"link1.mass": [1.0, 2.0], "link1": {"mass": [1.0, 3.0]}}


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"study": [{"architecture": "3-XYZ"}]}, "study[0].architecture must be one of"),
        ({"study": [{"architecture": "3-RRR", "link": {}}]}, "unknown key study[0].'link'"),
        ({"study": []}, "[[study]] must be a non-empty array"),
        ({"limits": {}}, "unknown key 'limits'"),
        (
            {"study": [{"architecture": "3-RRR", "parameters": {"link1.mass": [2.0, 1.0]}}]},
            "low must be below high",
        ),
        (
            {"study": [{"architecture": "3-RRR", "parameters": {"leg.nothing": [0.0, 1.0]}}]},
            "'leg.nothing' = 0.0",
        ),
        ({"optimize": {"objective": "peak_f10"}}, "unknown quantity 'peak_f10'"),
        (  # TOML "link1.mass" = ... and link1.mass = ...: two keys, one parameter
            {"study": [{"architecture": "3-RRR", "parameters": TWICE}]},
            "study[0].parameters 'link1.mass' is given twice",
        ),
    ],
)
def test_spec_errors_are_named(change: dict[str, object], message: str) -> None:
    data: dict[str, object] = {"study": [{"architecture": "3-RRR"}], **change}
    with pytest.raises(Prp3Error) as error:
        family_sweep_spec(data, source="s.toml")
    assert str(error.value).startswith("s.toml: ") and message in str(error.value)


SPEC = """\
designs = 3
sampling = "grid"
chunk = 2
[payload]
mass = 2.0
[task]
motions = ["vertical"]
samples = 41
[[study]]
architecture = "3-RRR"
[study.parameters]
"link2.mass" = [0.5, 1.0]
[[study]]
architecture = "3-PRR"
[optimize]
maxiter = 2
popsize = 2
"""


def test_cli_sweep_across_architectures(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, scheduler: str
) -> None:
    import pyarrow.parquet as pq

    spec = tmp_path / "study.toml"
    spec.write_text(SPEC)
    status, out, err = cli(capsys, "sweep", "--spec", spec, "-o", tmp_path / "s",
                           "--scheduler", scheduler, "--plots")  # fmt: skip
    assert status == 0, err
    table = pq.read_table(tmp_path / "s" / "designs.parquet").to_pydict()
    assert list(table)[:4] == ["architecture", "actuated", "link2.mass", "status"]
    assert list(table)[4:] == list(FAMILY_DESIGN_COLUMNS)
    assert table["architecture"] == ["3-RRR"] * 3 + ["3-PRR"]
    assert table["link2.mass"][:3] == [0.5, 0.75, 1.0] and math.isnan(table["link2.mass"][3])
    best = int(np.argmin(table["peak_joint_force"][:3]))
    assert f"least peak_joint_force {table['peak_joint_force'][best]:.6g}" in out
    assert (tmp_path / "s" / "family_designs.png").is_file()
    status, out, err = cli(capsys, "optimize", "--spec", spec, "-o", tmp_path / "o",
                           "--scheduler", scheduler)  # fmt: skip
    assert status == 0, err
    assert "3-RRR: peak_joint_force =" in out and "3-PRR: peak_joint_force =" in out
    best_robot = FamilyRobot.from_toml(tmp_path / "o" / "ROBOT.toml")
    assert best_robot.payload.mass == 2.0
    assert f"best: {best_robot.architecture}" in out


@pytest.mark.parametrize("option", [["--pareto", "a,b"], ["--sensitivity", "energy"]])
def test_cli_family_sweep_refuses_model_form_options(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, option: list[str]
) -> None:
    spec = tmp_path / "study.toml"
    spec.write_text(SPEC)
    status, _, err = cli(capsys, "sweep", "--spec", spec, "-o", tmp_path / "s", *option)
    assert status == 2 and option[0] in one_line(err)
    assert not (tmp_path / "s" / "designs.parquet").exists()


def test_model_form_specs_are_unchanged() -> None:
    from prp3.cli._family_analysis import family_spec_of

    example = Path(__file__).parent.parent / "docs" / "examples" / "synthesis.toml"
    assert family_spec_of(example) is None


# ---------------------------------------------------------------- docs/family_comparison.md
ROOT = Path(__file__).resolve().parents[1]
COMPARISON = ROOT / "docs" / "family_comparison.md"
MARKER = re.compile(r"^<!-- output of: (.+?) -->\n", re.M)


def _run_script(argv: list[str]) -> str:
    out = io.StringIO()
    saved = sys.argv
    sys.argv = [str(ROOT / argv[0]), *argv[1:]]
    try:
        with contextlib.redirect_stdout(out):
            runpy.run_path(str(ROOT / argv[0]), run_name="__main__")
    finally:
        sys.argv = saved
    return out.getvalue()


def _quoted() -> list[tuple[str, str]]:
    text = COMPARISON.read_text(encoding="utf-8")
    found = []
    for match in MARKER.finditer(text):
        body = text[match.end() :].split("\n\n", 1)[0] + "\n"
        found.append((match[1], body))
    return found


def test_the_comparison_page_quotes_its_script() -> None:
    quoted = _quoted()
    assert len(quoted) == 2
    for command, body in quoted:
        argv = shlex.split(command)
        assert argv[0] == "python" and argv[1] == "docs/examples/family_comparison.py"
        assert _run_script(argv[1:]) == body, command


def test_what_the_comparison_page_says_of_its_tables() -> None:
    (_, forces), (_, areas) = _quoted()
    rows = [line.split("|")[1:-1] for line in forces.splitlines()[2:]]
    assert len(rows) == 14  # seven architectures, two motions
    for row in rows:
        f1, f2, f3 = (float(row[k]) for k in (4, 5, 6))
        assert f1 > f2 > f3  # joint 1 carries the most, joint 3 the least
    by_name = {line.split("|")[1].strip(): line.split("|")[2:-1] for line in areas.splitlines()[2:]}
    reachable, regular = (float(v) for v in by_name["3-RPR"][:2])
    assert regular < 0.5 * reachable  # a parallel singularity runs through the window
    # the margins are those of docs/family.md §3 (3-RRR rotation 0.234 / 0.998)
    rrr = [row for row in rows if row[0].strip() == "3-RRR (1)" and row[1].strip() == "rotation"]
    assert [row[7].strip() for row in rrr] == ["0.234"] and [row[8].strip() for row in rrr] == [
        "0.998"
    ]


def test_the_spec_of_the_page_is_valid() -> None:
    text = COMPARISON.read_text(encoding="utf-8")
    block = text.split("```toml\n", 1)[1].split("```", 1)[0]
    spec = family_sweep_spec(tomllib.loads(block))
    assert [s.architecture for s in spec.studies] == ["3-RRR", "3-RPR", "3-PPR"]
    assert spec.studies[1].nominal["actuated"] == 2
    assert spec.optimize.constraints == (
        ("min_mu_par", 0.3, math.inf),
        ("regular_area", 0.05, math.inf),
    )


def test_cli_family_sweep_resumes_after_an_interruption_to_the_same_table(
    capsys: pytest.CaptureFixture[str],
    tmp_path: Path,
    scheduler: str,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The family sweep is the sweep of every robot: chunks kept as they are done, a run
    again after an interruption computes only the missing ones, and the file is the one an
    uninterrupted run writes; its rows are the spec's designs evaluated again here."""
    spec = tmp_path / "study.toml"
    spec.write_text(SPEC.replace("chunk = 2", "chunk = 1", 1))
    args = ("sweep", "--spec", spec, "--scheduler", scheduler)
    status, out, err = cli(capsys, *args, "-o", tmp_path / "whole")
    assert status == 0, err
    assert "4 of 4 chunks computed" in out
    whole = (tmp_path / "whole" / "designs.parquet").read_bytes()

    interrupted_sweep(capsys, monkeypatch, args, tmp_path / "cut")
    status, out, err = cli(capsys, *args, "-o", tmp_path / "cut")
    assert status == 0, err
    assert "2 of 4 chunks computed, 2 found done" in out
    assert (tmp_path / "cut" / "designs.parquet").read_bytes() == whole

    read = family_sweep_spec(tomllib.loads(spec.read_text()), base=tmp_path, source=str(spec))
    table = prp3.read_designs(tmp_path / "cut" / "designs.parquet")
    assert table.digest == read.digest()
    again = evaluate_family_designs(read.evaluator, family_design_rows(read))
    for name in read.evaluator.columns:
        np.testing.assert_array_equal(table.columns[name], again[name], err_msg=name)
    # another spec into the same folder is refused, --force replaces it
    spec.write_text(SPEC)
    status, _, err = cli(capsys, *args, "-o", tmp_path / "cut")
    assert status == 2 and "another sweep" in one_line(err)
    status, out, err = cli(capsys, *args, "-o", tmp_path / "cut", "--force")
    assert status == 0 and "2 of 2 chunks computed" in out, err


def test_the_family_spec_file_is_read_as_the_cli_reads_it(tmp_path: Path) -> None:
    spec = tmp_path / "study.toml"
    spec.write_text(SPEC)
    read = prp3.read_family_sweep_spec(spec)
    direct = family_sweep_spec(tomllib.loads(SPEC), base=tmp_path, source=str(spec))
    assert read.digest() == direct.digest() and read.count == 4
    np.testing.assert_array_equal(read.design_values(), direct.design_values())
    (tmp_path / "model.toml").write_text("designs = 2\n[parameters]\nl0 = [0.25, 0.35]\n")
    with pytest.raises(Prp3Error, match=r"model\.toml: not a family sweep spec"):
        prp3.read_family_sweep_spec(tmp_path / "model.toml")
    with pytest.raises(Prp3Error, match="path"):
        prp3.read_family_sweep_spec(None)  # type: ignore[arg-type]
