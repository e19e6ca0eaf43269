"""The forces table: actuator force histories for forward dynamics (``prp3 forward``).

:func:`read_forces` reads a table of :data:`FORCE_COLUMNS` (optionally with a
trajectory file's load columns, :data:`prp3.io.trajectory.LOAD_COLUMNS`) or a
whole ``results.csv`` (its columns: :mod:`prp3.io.results`), into a
:class:`ForceInput`: the forces, and for a ``results.csv`` the motion they
were planned for.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from prp3.analysis.force_histories import ActuatorForces
from prp3.errors import InputFileError, Prp3Error
from prp3.io.results import FRICTION_COLUMNS, RESULT_COLUMNS
from prp3.io.tables import read_table
from prp3.io.trajectory import LOAD_COLUMNS, column_group
from prp3.validation import LEGS

__all__ = ["FORCE_COLUMNS", "ForceInput", "read_forces"]

#: Columns of a force history file.
FORCE_COLUMNS: tuple[str, ...] = ("t", "f10_A", "f10_B", "f10_C")

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class ForceInput:
    """A force file read by :func:`read_forces`.

    Attributes
    ----------
    path : Path
        The file.
    forces : ActuatorForces
        Its force samples.
    first_pose, first_rates : ndarray (3,) or None
        ``(x, y, phi)`` and ``dlambda10`` of the first row of a ``results.csv``;
        ``None`` for a force table.
    planned_pose : ndarray (N, 3) or None
        ``(x, y, phi)`` of every row of a ``results.csv``: the motion the forces
        were planned for (at the times ``forces.t``); ``None`` for a force table.
    lines : ndarray of int (N,) or None
        The file line of each force sample (``None``: not read from a file).
    """

    path: Path
    forces: ActuatorForces
    first_pose: FloatArray | None
    first_rates: FloatArray | None
    planned_pose: FloatArray | None = None
    lines: NDArray[np.int64] | None = None

    @property
    def results(self) -> bool:
        """Whether the file is a ``results.csv`` (all contract columns)."""
        return self.first_pose is not None


def read_forces(path: str | Path) -> ForceInput:
    """Read ``t,f10_A,f10_B,f10_C`` or a complete ``results.csv``.

    Either may add the load columns ``fx, fy, mz`` (all three or none): the
    time-varying wrench of the environment on the platform, as in a
    trajectory file (:attr:`ActuatorForces.load`, interpolated like the forces).

    Raises
    ------
    InputFileError
        A malformed file, unknown columns, or some but not all of the
        ``results.csv`` columns (names the file and the missing columns).
    TrajectoryError
        Fewer than 2 rows or times that do not increase.
    """
    others = [name for name in RESULT_COLUMNS if name not in FORCE_COLUMNS]
    table = read_table(
        Path(path), FORCE_COLUMNS, [*others, *FRICTION_COLUMNS, *LOAD_COLUMNS], "forces"
    )
    columns = table.columns
    loads = column_group(Path(path), columns, LOAD_COLUMNS, "load", None)
    extra = [name for name in others if name in columns]
    if extra and len(extra) != len(others):
        missing = [name for name in others if name not in columns]
        raise InputFileError(
            f"give either the columns {','.join(FORCE_COLUMNS)} or all the columns of a "
            f"results.csv; missing {', '.join(missing[:6])}"
            + (f" and {len(missing) - 6} more" if len(missing) > 6 else ""),
            file=path,
        )
    t = columns["t"]
    f10 = np.stack([columns[f"f10_{leg}"] for leg in LEGS], axis=-1)
    load = np.stack([columns[name] for name in LOAD_COLUMNS], axis=-1) if loads else None
    try:
        forces = ActuatorForces(t=t, f10=f10, load=load)
    except Prp3Error as error:
        k = error.sample
        line, when = (int(table.lines[k]), float(t[k])) if k is not None else (None, None)
        raise error.located(file=path, line=line, time=when) from None
    if not extra:
        return ForceInput(Path(path), forces, None, None, lines=table.lines)
    planned = np.stack([columns["x"], columns["y"], columns["phi"]], axis=-1)
    rates = np.array([columns[f"dlambda10_{leg}"][0] for leg in LEGS])
    return ForceInput(Path(path), forces, planned[0].copy(), rates, planned, table.lines)
