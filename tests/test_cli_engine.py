"""``--engine auto|numba|numpy`` of ``prp3 simulate`` (prp3.cli._engine, docs/cli.md *Engines*).

The rule of ``auto`` (numba from ``NUMBA_FROM`` samples of the route, numpy
below), the engine named in the summary, the same numbers from either engine
(to round-off, the kernel's own cross-engine tolerance), and the point of the
rule: a short run by default never imports numba (its start-up would be most
of the run).
"""

from __future__ import annotations

import csv
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from clitools import cli, one_line
from prp3.cli._engine import NUMBA_FROM, run_engine
from prp3.engines import select
from prp3.errors import Prp3Error

ROOT = Path(__file__).resolve().parent.parent


def _columns(path: Path) -> dict[str, np.ndarray]:
    with path.open(newline="") as stream:
        rows = list(csv.reader(stream))
    values = np.array(rows[1:], dtype=np.float64)
    return {name: values[:, k] for k, name in enumerate(rows[0])}


@pytest.mark.parametrize("route", ["3-PRP", "family"])
def test_auto_runs_numba_from_the_threshold_and_numpy_below(route: str) -> None:
    pytest.importorskip("numba")
    threshold = NUMBA_FROM[route]
    assert run_engine("auto", 2, route) == "numpy"
    if threshold is None:  # the 3-PRP: numpy in a command, whatever the run
        assert route == "3-PRP"
        assert run_engine("auto", 10**9, route) == "numpy"
    else:
        assert run_engine("auto", threshold - 1, route) == "numpy"
        assert run_engine("auto", threshold, route) == "numba"
        assert run_engine("auto", 10**9, route) == "numba"
    for choice in ("numba", "numpy"):  # an explicit engine, whatever the run
        assert run_engine(choice, 2, route) == choice
        assert run_engine(choice, 10**9, route) == choice


def test_auto_without_numba_runs_numpy_and_says_so_once(monkeypatch: pytest.MonkeyPatch) -> None:
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "numba" else real(name, *a)
    )
    monkeypatch.setattr(select, "_numba", None)
    monkeypatch.setattr(select, "_warned", False)
    with pytest.warns(select.EngineWarning, match="numba is not installed"):
        assert run_engine("auto", 10**9, "family") == "numpy"
    assert run_engine("auto", 10, "family") == "numpy"  # below: numpy, nothing to say
    with pytest.raises(Prp3Error, match='engine="numba" needs numba'):
        run_engine("numba", 10, "3-PRP")


@pytest.mark.parametrize("robot", [None, 'architecture = "3-RRR"\n'])
def test_both_engines_write_the_same_results_and_the_summary_names_the_engine(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, robot: str | None
) -> None:
    pytest.importorskip("numba")
    extra: list[str] = []
    if robot is not None:
        (tmp_path / "ROBOT.toml").write_text(robot, encoding="utf-8")
        extra = ["--robot", str(tmp_path / "ROBOT.toml")]
    tables = {}
    for engine in ("numba", "numpy", "auto"):
        folder = tmp_path / engine
        status, out, err = cli(
            capsys, "simulate", "--motion", "rotation", "--samples", "41", *extra,
            "--engine", engine, "--output", folder,
        )  # fmt: skip
        assert status == 0, err
        ran = "numpy" if engine == "auto" else engine  # 41 samples: below every threshold
        assert f"fast method ({ran} engine)" in out.splitlines()[0]
        tables[engine] = _columns(folder / "results.csv")
    assert list(tables["numba"]) == list(tables["numpy"])
    for name, values in tables["numpy"].items():
        scale = np.abs(values).max() + 1.0
        assert np.abs(tables["numba"][name] - values).max() <= 1e-12 * scale, name
        np.testing.assert_array_equal(tables["auto"][name], values)


def test_other_methods_name_no_engine(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    status, out, _ = cli(
        capsys, "simulate", "--motion", "vertical", "--samples", "5", "--method", "paper",
        "--output", tmp_path,
    )  # fmt: skip
    assert status == 0
    assert out.splitlines()[0].endswith("paper method")


def test_a_bad_engine_is_refused_in_one_line(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    status, _, err = cli(
        capsys, "simulate", "--motion", "vertical", "--engine", "cuda", "--output", tmp_path
    )
    assert status == 2
    assert one_line(err) == (
        "prp3 simulate: error: argument --engine: invalid choice: 'cuda' "
        "(choose from 'auto', 'numba', 'numpy')"
    )
    assert not (tmp_path / "results.csv").exists()


def test_the_default_short_run_does_not_start_numba(tmp_path: Path) -> None:
    # the reason for --engine auto: the README's first run stays as quick as without numba
    code = (
        "import sys\n"
        "from prp3.cli import main\n"
        f"status = main(['simulate', '--motion', 'vertical', '--output', {str(tmp_path)!r}])\n"
        "assert status == 0, status\n"
        "print('numba' in sys.modules)\n"
    )
    env = {k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=ROOT, check=True
    )
    assert done.stdout.strip().splitlines()[-1] == "False"
    assert (tmp_path / "results.csv").is_file()
