"""The worked synthesis of docs/design.md: a sweep and an optimisation of examples/synthesis.toml.

Runs, in the current folder,

    prp3 sweep --spec docs/examples/synthesis.toml --output study --workers 2 --plots
    prp3 optimize --spec docs/examples/synthesis.toml --output best --workers 2

and prints their summaries (without the times, which vary from run to run),
then the numbers the document's discussion quotes, each computed here from
the files the two commands wrote or by prp3's inverse dynamics; it draws
``synthesis_pareto.png`` (the sweep's Pareto front with the optimum marked)
into ``--figures`` (default ``docs/figures``).  ``tests/test_docs.py`` runs it
and compares its output with the document.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import re
from pathlib import Path

import numpy as np

import prp3
from prp3 import read_designs
from prp3.cli import main as prp3_main
from prp3.plotting import pareto_figure, save_figure

ROOT = Path(__file__).resolve().parents[2]
SPEC = ROOT / "docs" / "examples" / "synthesis.toml"
AREA = 0.02  # m², the spec's constraint


def _run(*argv: str) -> str:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        status = prp3_main(list(argv))
    assert status == 0, (argv, status)
    # the times vary from run to run: left out
    text = re.sub(r", [0-9.]+(e[+-]?\d+)? s\b", "", out.getvalue())
    return text


def _peak_f10(robot: prp3.Robot) -> float:
    return max(float(np.abs(prp3.inverse_dynamics(robot, prp3.paper_motion(name))[1].f10).max())
               for name in ("vertical", "rotation"))  # fmt: skip


def _stroke_needed(l0: float, name: str) -> tuple[float, float]:
    """Largest λ10 of leg A and of any leg along a paper motion, for a robot of size l0 (m)."""
    lam = prp3.inverse_dynamics(prp3.Robot(l0=l0), prp3.paper_motion(name))[0].geometry.lambda10
    return float(lam[:, 0].max()), float(lam.max())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--figures", type=Path, default=ROOT / "docs" / "figures")
    figures = parser.parse_args().figures
    spec = str(SPEC)
    print(_run("sweep", "--spec", spec, "--output", "study", "--workers", "2", "--plots"), end="")
    optimum = _run("optimize", "--spec", spec, "--output", "best", "--workers", "2")
    print(optimum, end="")

    best = float(re.search(r"best peak_f10 = (\S+)", optimum)[1])  # type: ignore[index]
    best_area = float(re.search(r"workspace_area = (\S+)", optimum)[1])  # type: ignore[index]
    evaluations = int(re.search(r"(\d+) designs", optimum)[1])  # type: ignore[index]
    table = read_designs("study/designs.parquet")
    columns, nominal = table.columns, table.nominal
    ok = np.asarray(columns["status"]) == "ok"
    # the design table's columns peak_f10_A, _B, _C; peak_f10 of the plot is their largest
    peak = np.max([np.asarray(columns[f"peak_f10_{leg}"], dtype=float) for leg in "ABC"], axis=0)
    area = np.asarray(columns["workspace_area"], dtype=float)
    feasible = ok & (area >= AREA)
    paper = _peak_f10(prp3.Robot())
    still = _peak_f10(prp3.Robot(gravity=(0.0, 0.0)))
    print("numbers of the discussion:")
    print(f"  paper's robot (the star): peak f10 = {paper:.2f} N; the optimum {best:.2f} N, "
          f"{100 * (1 - best / paper):.0f} % less")  # fmt: skip
    print(f"  best design of the sweep with workspace_area >= {AREA}: {peak[feasible].min():.2f} N "
          f"({int(feasible.sum())} such designs); prp3 optimize: {evaluations} evaluations")  # fmt: skip
    print(f"  the paper's robot without gravity: peak f10 = {still:.3f} N")
    for l0 in (0.2, 0.3, 0.4):
        lift, _ = _stroke_needed(l0, "vertical")
        _, turn = _stroke_needed(l0, "rotation")
        print(f"  l0 = {l0} m: largest lambda10_A of the lift {lift:.4f} m, "
              f"largest lambda10 of the rotation {turn:.4f} m = {turn / l0:.3f} l0")  # fmt: skip

    row = {"workspace_area": best_area} | {f"peak_f10_{leg}": best for leg in "ABC"}
    figure = pareto_figure(
        columns, "workspace_area", "peak_f10", maximize_x=True, nominal=nominal,
        marks={f"optimum of prp3 optimize (area >= {AREA} m²)": row},
        title=f"Peak actuator force against workspace area, {len(peak)} designs",
    )  # fmt: skip
    figures.mkdir(parents=True, exist_ok=True)
    save_figure(figure, figures / "synthesis_pareto.png")


if __name__ == "__main__":
    main()
