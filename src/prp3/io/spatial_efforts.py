"""The efforts file of ``prp3 forward`` for a spatial robot (docs/spatial.md §18).

A CSV table with a header row: ``t`` (s, increasing) and ``tau_1 … tau_L`` (the
actuator efforts of the legs, N or N·m), or the ``results.csv`` of a ``prp3
simulate`` run of the same robot (the columns of §9, every one of them); any
other column is refused.  A ``results.csv`` also gives the motion the efforts
came from: its first row is the initial state (pose and twist from leg joint
values and rates, :func:`prp3.spatial.forward.state_from_joints`) and its rows
the planned motion the integrated one is compared with.

>>> import tempfile, pathlib
>>> from prp3.spatial.model import hexapod
>>> path = pathlib.Path(tempfile.mkdtemp()) / "efforts.csv"
>>> _ = path.write_text("t,tau_1,tau_2,tau_3,tau_4,tau_5,tau_6\\n0,1,1,1,1,1,1\\n1,2,2,2,2,2,2\\n")
>>> efforts = read_spatial_efforts(path, hexapod())
>>> efforts.tau.shape, efforts.planned is None
((2, 6), True)
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from prp3.errors import InputFileError, Prp3Error
from prp3.io.tables import read_table
from prp3.spatial.forward import state_from_joints
from prp3.spatial.model import SpatialRobot
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.outputs import spatial_inverse_dynamics, spatial_results_table
from prp3.validation import check_file_path, first_not_increasing

__all__ = ["SpatialEfforts", "read_spatial_efforts", "spatial_effort_columns"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class SpatialEfforts:
    """Efforts read from a file.

    Attributes
    ----------
    path : Path
    t : (M,) s
    tau : (M, legs) N or N·m
    lines : (M,) int, the file line of each row
    planned : PlatformMotion or None
        A ``results.csv``'s motion (poses and twists from its joint columns).
    """

    path: Path
    t: FloatArray
    tau: FloatArray
    lines: NDArray[np.int64]
    planned: PlatformMotion | None


def spatial_effort_columns(robot: SpatialRobot) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The required columns (``t, tau_1 … tau_L``) and the other columns of a ``results.csv``."""
    home = PlatformMotion.at_rest(robot.home_position, robot.home_rotation)
    names = tuple(spatial_results_table(spatial_inverse_dynamics(robot, home)))
    required = ("t", *(f"tau_{i + 1}" for i in range(len(robot.legs))))
    return required, tuple(name for name in names if name not in required)


def read_spatial_efforts(path: str | Path, robot: SpatialRobot) -> SpatialEfforts:
    """The efforts of ``path`` for ``robot``: ``t, tau_1 … tau_L`` or a ``results.csv`` (§9).

    Raises
    ------
    InputFileError
        A column missing or unknown, some but not all of a ``results.csv``'s columns,
        a cell that is not a finite number, fewer than 2 rows, a time that does not
        increase (each naming the file and line), joint values that give no pose.
    """
    file = check_file_path("path", path)
    required, others = spatial_effort_columns(robot)
    table = read_table(file, required, others, "efforts")
    columns = table.columns
    given = [name for name in others if name in columns]
    if given and len(given) != len(others):
        missing = [name for name in others if name not in columns]
        raise InputFileError(
            f"the file has {len(given)} of the {len(others)} columns of a results.csv of the "
            f"{robot.name} but not {', '.join(missing[:3])}{' …' if len(missing) > 3 else ''}: "
            f"give t, {', '.join(required[1:])} only, or the whole results.csv",
            file=file,
            line=table.header_line,
        )
    t = columns["t"]
    if t.size < 2:
        raise InputFileError(f"{t.size} row of efforts: at least 2 are needed", file=file)
    bad = first_not_increasing(t)
    if bad is not None:
        raise InputFileError(
            f"time must be strictly increasing; t = {t[bad]!r} s follows {t[bad - 1]!r} s",
            file=file,
            line=int(table.lines[bad]),
            key="t",
        )
    tau = np.stack([columns[name] for name in required[1:]], axis=-1)
    planned = None
    if given:
        leg = robot.legs[0]
        legs = range(1, len(robot.legs) + 1)
        q, dq = (
            np.stack(
                [np.stack([columns[f"{kind}_{i}_{c}"] for c in leg.coordinates], -1) for i in legs],
                axis=1,
            )
            for kind in ("q", "dq")
        )
        try:
            planned = state_from_joints(robot, t, q, dq)
        except Prp3Error as error:
            sample = error.sample
            line = int(table.lines[sample]) if sample is not None else None
            raise InputFileError(
                f"the joint values give no platform pose: {error.reason}", file=file, line=line
            ) from None
    return SpatialEfforts(file, t, tau, table.lines, planned)
