"""Draw the default hexapod during its tilt, with its joint forces: ``docs/figures/spatial_pose.png``.

The figure of docs/spatial.md §15: the robot at ``t = 0.75 s`` of ``prp3 simulate --motion
tilt`` (:func:`prp3.plotting.spatial_pose_figure` of sample 75 of 301, drawn
as a frame of ``--animate`` is), and the numbers its legend states.  Run ``python docs/examples/spatial_pose.py [--figures DIR]``
(default ``docs/figures``); ``tests/test_docs.py`` runs it and compares what it prints with
docs/spatial.md, ``tests/test_spatial_animation.py`` checks that the committed figure is the one
it draws.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
NAME = "spatial_pose.png"
SAMPLES, INDEX = 301, 75


def draw(folder: Path) -> tuple[Path, str]:
    """Write the figure into ``folder`` (atomically); return its path and the report."""
    from prp3 import hexapod, spatial_inverse_dynamics, spatial_motion, spatial_results_table
    from prp3.plotting import (
        force_scale,
        robot_size,
        save_figure,
        spatial_frame,
        spatial_pose_figure,
        spatial_samples,
    )

    robot = hexapod()
    motion = spatial_motion(robot, "tilt", SAMPLES)
    table = spatial_results_table(spatial_inverse_dynamics(robot, motion, "newton-euler"))
    figure = spatial_pose_figure(robot, table, index=INDEX, what="tilt motion")
    view = figure.axes[0]  # the 3-D axes: the view the figure is drawn from
    folder.mkdir(parents=True, exist_ok=True)
    path = save_figure(figure, folder / NAME)
    t, q, force = spatial_samples(robot, table)
    size = robot_size([spatial_frame(robot, q[INDEX], force[INDEX])])
    magnitude = np.linalg.norm(force, axis=-1)  # (N, legs, joints)
    # The tilt is symmetric: legs tie to round-off, so the first of the forces equal to 1e-9
    # (earliest sample, lowest leg, first joint) is named, whatever the last bits say.
    tied = np.round(magnitude / magnitude.max(), 9)
    k, leg, joint = np.unravel_index(int(np.argmax(tied)), tied.shape)
    here = tied[INDEX]
    h_leg, h_joint = np.unravel_index(int(np.argmax(here)), here.shape)
    labels = robot.legs[0].labels
    report = "\n".join(
        [
            f"{NAME}: the {robot.name} at t = {t[INDEX]:g} s of the tilt motion "
            f"({SAMPLES} samples), seen from elevation {view.elev:g}°, azimuth {view.azim:g}°",
            f"robot size {size:.3g} m; force arrows {force_scale(force, size):g} N per m",
            f"largest joint force of the run: {magnitude.max():.3g} N at {labels[joint]} of leg "
            f"{leg + 1}, t = {t[k]:g} s",
            f"largest at t = {t[INDEX]:g} s: {magnitude[INDEX].max():.3g} N at {labels[h_joint]} of leg "
            f"{h_leg + 1}",
        ]
    )
    return path, report


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--figures", type=Path, default=ROOT / "docs" / "figures")
    _, report = draw(parser.parse_args().figures)
    print(report)


if __name__ == "__main__":
    main()
