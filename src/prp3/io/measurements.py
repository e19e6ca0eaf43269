"""Measurement files: a measured motion and its actuator forces, for identification.

A trajectory file's columns (:mod:`prp3.io.trajectory`: positions, optionally
the derivatives and the load) plus the measured forces
:data:`MEASURED_FORCE_COLUMNS`, read by :func:`read_measurements` into
:class:`Measurements` (``prp3 identify``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from prp3.io.tables import read_table
from prp3.io.trajectory import (
    DERIVATIVE_COLUMNS,
    LOAD_COLUMNS,
    POSITION_COLUMNS,
    Trajectory,
    trajectory_of,
)

__all__ = ["MEASURED_EFFORT_COLUMNS", "MEASURED_FORCE_COLUMNS", "Measurements", "read_measurements"]

FloatArray = NDArray[np.float64]

#: Measured actuator forces of a measurement file (N).
MEASURED_FORCE_COLUMNS: tuple[str, ...] = ("f10_A", "f10_B", "f10_C")

#: Measured actuator efforts of a family robot's measurement file (N or N·m, docs/family.md).
MEASURED_EFFORT_COLUMNS: tuple[str, ...] = ("tau_A", "tau_B", "tau_C")


@dataclass(frozen=True)
class Measurements:
    """A measured motion and its actuator forces, read by :func:`read_measurements`.

    Attributes
    ----------
    trajectory : Trajectory
        The motion (columns as a trajectory file's; derivatives computed when absent).
    f10 : ndarray, shape (N, 3)
        The measured forces ``f10_A, f10_B, f10_C`` (N), or the columns read
        in their place (a family robot's efforts ``tau_A, tau_B, tau_C``).
    """

    trajectory: Trajectory
    f10: FloatArray


def read_measurements(
    path: str | Path,
    efforts: Sequence[str] = MEASURED_FORCE_COLUMNS,
    *,
    crossing: bool = True,
) -> Measurements:
    r"""Read a measurement file: a trajectory file's columns plus ``f10_A, f10_B, f10_C``.

    The same strict reader and conventions as :func:`read_trajectory`
    (derivative columns optional, all six or none; load columns ``fx, fy, mz``
    optional, all three or none; time strictly increasing).  ``efforts`` are
    the measured columns (:data:`MEASURED_EFFORT_COLUMNS` for a family robot,
    which reads with ``crossing=False``: its own singularities are refused
    along its path, as :func:`prp3.io.trajectory.read_trajectory`'s ``crossing``).

    Raises
    ------
    InputFileError, TrajectoryError
        As :func:`read_trajectory`; a missing force column is named.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from prp3.errors import InputFileError
    >>> file = pathlib.Path(tempfile.mkdtemp()) / "m.csv"
    >>> rows = "".join(f"{k / 10},0,{k / 100},0,1,2,3\n" for k in range(8))
    >>> _ = file.write_text("t,x,y,phi,f10_A,f10_B,f10_C\n" + rows)
    >>> read_measurements(file).f10[0].tolist()
    [1.0, 2.0, 3.0]
    >>> _ = file.write_text("t,x,y,phi,f10_A,f10_B\n0,0,0,0,1,2\n")
    >>> try:
    ...     read_measurements(file)
    ... except InputFileError as error:
    ...     print(str(error).split(": ", 1)[1])
    missing column(s) f10_C
    """
    path = Path(path)
    table = read_table(
        path,
        POSITION_COLUMNS + tuple(efforts),
        DERIVATIVE_COLUMNS + LOAD_COLUMNS,
        "measurement",
    )
    f10 = np.stack([table.columns[name] for name in efforts], axis=-1)
    return Measurements(trajectory=trajectory_of(path, table, crossing=crossing), f10=f10)
