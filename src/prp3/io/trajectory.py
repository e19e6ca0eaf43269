"""``TRAJ.csv``: a platform motion of the data contract, read strictly and written back.

The file of ``docs/model.md``: a header row, then one row per sample of
:data:`POSITION_COLUMNS`, optionally all of :data:`DERIVATIVE_COLUMNS` (else
the derivatives are computed from the positions) and all of
:data:`LOAD_COLUMNS` (a time-varying wrench on the platform).
:func:`read_trajectory` reads it (a :class:`Trajectory`: the motion, the line
of each sample, how the derivatives were found), :func:`trajectory_table`
gives the columns :data:`TRAJECTORY_COLUMNS` of a motion (``prp3 forward``'s
``trajectory.csv``, written by :func:`prp3.io.tables.write_table_csv`).
:func:`trajectory_of` and :func:`column_group` serve the files that carry a
motion too (:mod:`prp3.io.measurements`, :mod:`prp3.io.forces`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from prp3.errors import InputFileError, SingularPoseError, TrajectoryError
from prp3.io.tables import Table, read_table
from prp3.model.motion import Motion, spline_derivatives
from prp3.path_validation import check_path
from prp3.validation import first_not_increasing

__all__ = [
    "DERIVATIVE_COLUMNS",
    "LOAD_COLUMNS",
    "POSITION_COLUMNS",
    "TRAJECTORY_COLUMNS",
    "Trajectory",
    "column_group",
    "read_trajectory",
    "trajectory_of",
    "trajectory_table",
]

#: Columns of a trajectory file that are always required (s, m, m, rad).
POSITION_COLUMNS: tuple[str, ...] = ("t", "x", "y", "phi")

#: Optional derivative columns of a trajectory file: all six or none.
DERIVATIVE_COLUMNS: tuple[str, ...] = ("dx", "dy", "dphi", "ddx", "ddy", "ddphi")

#: Optional load columns of a trajectory file (a wrench on the platform): all three or none.
LOAD_COLUMNS: tuple[str, ...] = ("fx", "fy", "mz")

#: Columns of a trajectory written by prp3 (``prp3 forward``'s ``trajectory.csv``).
TRAJECTORY_COLUMNS: tuple[str, ...] = POSITION_COLUMNS + DERIVATIVE_COLUMNS


FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


def column_group(
    path: Path, columns: Mapping[str, object], group: Sequence[str], what: str, line: int | None
) -> bool:
    """Whether the table's ``columns`` have the ``what`` columns ``group``: all of them or none.

    Some of them only is refused, naming the file (and ``line``, the header's
    line, when given) and the columns missing.
    """
    given = [name for name in group if name in columns]
    if given and len(given) != len(group):
        missing = [name for name in group if name not in columns]
        raise InputFileError(
            f"give all of the {what} columns {', '.join(group)} or none; "
            f"missing {', '.join(missing)}",
            file=path,
            line=line,
        )
    return bool(given)


@dataclass(frozen=True)
class Trajectory:
    """A platform motion read from a trajectory file.

    Attributes
    ----------
    path : Path
        The file it was read from.
    motion : Motion
        ``N >= 2`` samples, in the file's row order.
    lines : ndarray of int, shape (N,)
        Line number in the file (1-based, header included) of each sample,
        so that a message about sample ``k`` can name ``path:lines[k]``.
    note : str or None
        ``None`` when the file gives the derivatives; otherwise how they were
        computed from the positions (for a warning to the user).
    """

    path: Path
    motion: Motion
    lines: IntArray
    note: str | None


def read_trajectory(path: str | Path, *, crossing: bool = True) -> Trajectory:
    r"""Read a trajectory file ``TRAJ.csv`` of the command line's data contract.

    The file has a header row naming its columns, in any order, then one row
    per sample (SI units, rad).  The columns are either ``t, x, y, phi``
    (positions only) or those and all of ``dx, dy, dphi, ddx, ddy, ddphi``;
    optionally all of ``fx, fy, mz``, a time-varying wrench of the environment
    on the platform (force at ``G``, fixed frame, N; moment about ``z0``, N·m),
    carried as :attr:`Motion.load`.
    Blank lines are ignored.  With positions only, the velocities and
    accelerations are computed by :func:`differentiate_positions` (a quintic
    interpolating spline) and :attr:`Trajectory.note` says so.

    Each row is the state of the platform at its time: the rates given need
    not integrate to the steps between samples (a static grid of poses with
    zero rates, or measured data, is read as it is).  With ``crossing`` (the
    default: the 3-PRP) a motion whose orientation passes a singular
    orientation ``φ = π/3 mod π`` between two samples is refused
    (:func:`prp3.path_validation.check_path`, naming both lines); a family
    robot has singularities of its own, refused as its legs follow the path
    from sample to sample (``crossing=False``: ``docs/family.md``).

    Raises
    ------
    InputFileError
        Unreadable or empty file; an unknown, misspelled, duplicate or missing
        column, or only some of the derivative columns (names the file, the
        header line and the columns); a row of the wrong length, a non-numeric
        or non-finite cell (names file, line and column).
    TrajectoryError
        Fewer than 2 samples, a time that does not increase, or derivatives
        computed from the positions that overflow (names the file and the line).
    SingularPoseError
        With ``crossing``: a singular orientation passed between two samples.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> file = pathlib.Path(tempfile.mkdtemp()) / "traj.csv"
    >>> _ = file.write_text("t,x,y,phi\n" + "".join(f"{k / 10},0,{k / 100},0\n" for k in range(8)))
    >>> trajectory = read_trajectory(file)
    >>> trajectory.motion.samples, trajectory.lines[:3].tolist()
    (8, [2, 3, 4])
    >>> trajectory.motion.velocity[4].round(12).tolist()
    [0.0, 0.1, 0.0]
    >>> trajectory.note is not None
    True
    """
    path = Path(path)
    optional = DERIVATIVE_COLUMNS + LOAD_COLUMNS
    table = read_table(path, POSITION_COLUMNS, optional, "trajectory")
    return trajectory_of(path, table, crossing=crossing)


def trajectory_of(path: Path, table: Table, *, crossing: bool = True) -> Trajectory:
    """The motion of a table with the columns of a trajectory file (see :func:`read_trajectory`).

    ``table`` is the table :func:`prp3.io.tables.read_table` read from ``path``
    (with the columns of a trajectory file, and maybe others); the refusals,
    and ``crossing``, are those of :func:`read_trajectory`.
    """
    columns = table.columns
    loads = column_group(path, columns, LOAD_COLUMNS, "load", table.header_line)
    given = column_group(path, columns, DERIVATIVE_COLUMNS, "derivative", table.header_line)
    t = columns["t"]
    lines = table.lines
    if len(t) < 2:
        raise TrajectoryError(
            f"a trajectory needs at least 2 samples, got {len(t)}", file=path, line=int(lines[0])
        )
    k = first_not_increasing(t)
    if k is not None:
        raise TrajectoryError(
            f"time must increase: t = {float(t[k])!r} follows t = {float(t[k - 1])!r} on line "
            f"{int(lines[k - 1])}",
            file=path,
            line=int(lines[k]),
        )
    pose = np.stack([columns[name] for name in ("x", "y", "phi")], axis=-1)
    note: str | None = None
    if given:
        velocity = np.stack([columns[name] for name in DERIVATIVE_COLUMNS[:3]], axis=-1)
        acceleration = np.stack([columns[name] for name in DERIVATIVE_COLUMNS[3:]], axis=-1)
    else:
        with np.errstate(all="ignore"):  # an overflow is reported below, naming the line
            velocity, acceleration, degree = spline_derivatives(t, pose)
        for name, values in (("velocity", velocity), ("acceleration", acceleration)):
            bad = ~np.isfinite(values)
            if bad.any():
                k, axis = np.argwhere(bad)[0].tolist()
                raise TrajectoryError(
                    f"the {name} of {POSITION_COLUMNS[1 + axis]} computed from the positions "
                    f"is not finite ({float(values[k, axis])!r}): positions too large or time "
                    "steps too small; give the derivative columns",
                    file=path,
                    line=int(lines[k]),
                )
        note = (
            f"{path}: positions only; velocities and accelerations computed as the 1st and "
            f"2nd derivatives of a degree-{degree} interpolating spline through the samples "
            f"(scipy make_interp_spline{', not-a-knot ends' if degree > 1 else ''}); accurate "
            "for smooth, finely sampled motions, less so near the first and last samples"
        )
    try:
        load = np.stack([columns[name] for name in LOAD_COLUMNS], axis=-1) if loads else None
        motion = Motion(t=t, pose=pose, velocity=velocity, acceleration=acceleration, load=load)
        if crossing:  # between two samples: no singular orientation of the 3-PRP crossed
            check_path(motion.t, motion.pose, lines=lines, subject=None)
    except (TrajectoryError, SingularPoseError) as error:  # SingularPoseError: check_path's
        line = int(lines[error.sample]) if error.sample is not None else None
        raise error.located(file=path, line=line) from None
    return Trajectory(path=path, motion=motion, lines=lines, note=note)


def trajectory_table(motion: Motion) -> dict[str, FloatArray]:
    """The columns :data:`TRAJECTORY_COLUMNS` of a batch motion, as named arrays ``(N,)``.

    >>> from prp3.model.motion import paper_motion
    >>> table = trajectory_table(paper_motion("vertical", 3))
    >>> list(table), table["y"].tolist()
    (['t', 'x', 'y', 'phi', 'dx', 'dy', 'dphi', 'ddx', 'ddy', 'ddphi'], [0.0, 0.025, 0.05])
    """
    arrays = (motion.pose, motion.velocity, motion.acceleration)
    table: dict[str, FloatArray] = {"t": motion.t}
    for k, name in enumerate(TRAJECTORY_COLUMNS[1:]):
        table[name] = arrays[k // 3][..., k % 3]
    return table
