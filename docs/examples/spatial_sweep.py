"""The worked sweep of docs/spatial.md §21: three spatial architectures on the same heave.

Runs, in the current folder,

    prp3 sweep --spec docs/examples/spatial_sweep.toml --output spatial_study --workers 1

prints its summary (without the time, which varies from run to run), then per robot
the designs that carry the task and the one of least peak joint force, read from
``spatial_study/designs.parquet``, and that design's peak joint force rebuilt by
``prp3.spatial_inverse_dynamics``.  ``tests/test_docs.py`` runs it and compares its
output with the document.
"""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import numpy as np

import prp3
from prp3.cli import main as prp3_main

ROOT = Path(__file__).resolve().parents[2]
SPEC = ROOT / "docs" / "examples" / "spatial_sweep.toml"


def _run(*argv: str) -> str:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        status = prp3_main(list(argv))
    assert status == 0, (argv, status)
    return re.sub(r", [0-9.]+(e[+-]?\d+)? s\b", "", out.getvalue())


def main() -> None:
    print(_run("sweep", "--spec", str(SPEC), "--output", "spatial_study", "--workers", "1"), end="")
    table = prp3.read_designs("spatial_study/designs.parquet").columns
    robot, status = np.asarray(table["robot"]), np.asarray(table["status"])
    print("least peak_joint_force of each robot:")
    for name in dict.fromkeys(robot.tolist()):
        mine = robot == name
        ok = mine & (status == "ok")
        k = int(np.flatnonzero(ok)[np.argmin(table["peak_joint_force"][ok])])
        radius, mass = float(table["base_radius"][k]), float(table["platform.mass"][k])
        design = prp3.spatial_robot_from_mapping(
            {"architecture": name, "base_radius": radius, "platform": {"mass": mass}}
        ).robot
        motion = prp3.complete_motion(design, prp3.spatial_motion(design, "heave", 21))
        force = prp3.spatial_inverse_dynamics(design, motion).force
        rebuilt = float(np.linalg.norm(force, axis=-1).max())
        print(
            f"  {name}: {int(ok.sum())} of {int(mine.sum())} designs ok; base_radius {radius:.4f} m, "
            f"platform.mass {mass:.3f} kg: peak_joint_force {table['peak_joint_force'][k]:.4f} N "
            f"(rebuilt {rebuilt:.4f} N), peak_effort {table['peak_effort'][k]:.4f}, "
            f"min_mu_par {table['min_mu_par'][k]:.4g}"
        )


if __name__ == "__main__":
    main()
