"""The worked identification of docs/identification.md, from the exciting motion to the estimate.

1. ``prp3 excite --output ex``: the exciting trajectory ``ex/trajectory.csv``;
2. the "true" robot ``true.toml`` (the document's table) driven along it:
   its actuator forces (``prp3 simulate --robot true.toml --trajectory
   ex/trajectory.csv``) plus Gaussian noise of 1 % of their peak
   (``numpy.random.default_rng(SEED)``), written next to the positions only as
   the measurement file ``m.csv``;
3. ``prp3 identify --measurements m.csv --output id``;
4. the estimates against the true base parameters, in standard deviations.

It prints what the document quotes (``tests/test_docs.py`` compares them) and
copies ``id/identification.png`` to ``--figures`` (default ``docs/figures``).
Run it in an empty folder: ``python docs/examples/identification.py``.
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import io
import shutil
from pathlib import Path

import numpy as np

import prp3
from prp3 import base_parameters, read_trajectory, standard_parameters, write_table_csv
from prp3.cli import main as prp3_main

ROOT = Path(__file__).resolve().parents[2]
SEED = 7
NOISE = 0.01  # of the peak force

TRUE_TOML = """\
[piston]
mass = 1.3
com = [0.01, 0.0]
[link]
mass = 0.6
com = [0.03, -0.01]
inertia = 8e-4
[platform]
mass = 3.4
inertia = 0.08
"""


def _run(*argv: str) -> str:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        status = prp3_main(list(argv))
    assert status == 0, (argv, status)
    return out.getvalue()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--figures", type=Path, default=ROOT / "docs" / "figures")
    figures = parser.parse_args().figures

    print("$ prp3 excite --output ex")
    print(_run("excite", "--output", "ex"), end="")

    Path("true.toml").write_text(TRUE_TOML, encoding="utf-8")
    true = prp3.Robot.from_toml("true.toml")
    motion = read_trajectory("ex/trajectory.csv").motion
    f10 = prp3.inverse_dynamics(true, motion)[1].f10
    peak = float(np.abs(f10).max())
    noise = NOISE * peak
    measured = f10 + noise * np.random.default_rng(SEED).normal(size=f10.shape)
    columns = {"t": motion.t, "x": motion.pose[:, 0], "y": motion.pose[:, 1],
               "phi": motion.pose[:, 2]}  # fmt: skip
    columns |= {f"f10_{leg}": measured[:, k] for k, leg in enumerate("ABC")}
    write_table_csv("m.csv", columns)
    print(f"$ # m.csv: the true robot's forces, peak |f10| = {peak:.2f} N, "
          f"plus noise of sigma = {noise:.4f} N (1 %), seed {SEED}")  # fmt: skip

    print("$ prp3 identify --measurements m.csv --output id")
    report = _run("identify", "--measurements", "m.csv", "--output", "id")
    print(report, end="")

    # the estimates (id/parameters.csv) against the true base parameters
    base = base_parameters(prp3.Robot())
    truth = dict(zip(base.labels, base.values(standard_parameters(true)), strict=True))
    print("$ # estimate - true, in standard deviations of the estimate")
    with open("id/parameters.csv", newline="", encoding="utf-8") as stream:
        for row in csv.DictReader(stream):
            exact, estimate, std = (
                truth[row["combination"]],
                float(row["estimate"]),
                float(row["std"]),
            )
            print(f"  {row['combination']:<10} true {exact:<8.4g} {(estimate - exact) / std:+.1f}")

    figures.mkdir(parents=True, exist_ok=True)
    shutil.copyfile("id/identification.png", figures / "identification.png")


if __name__ == "__main__":
    main()
