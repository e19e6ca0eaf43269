r"""The spatial trajectory file (docs/spatial.md §14): a platform motion read strictly.

A CSV table with a header row (any column order, SI units, rad): ``t, x, y, z``
(the platform origin ``p``), the orientation as either the unit quaternion
``qw, qx, qy, qz`` or ``roll, pitch, yaw`` (§3), and optionally all of the
twist and its derivative (§4): ``wx, wy, wz`` (``ω``, world frame, rad/s),
``vx, vy, vz`` (``v``, m/s), ``dwx, dwy, dwz`` (``α = dω/dt``, rad/s²) and
``ax, ay, az`` (``a = dv/dt``, m/s²).  Without them the rates are derived from
the poses: the positions and the orientation's coordinates (the roll, pitch
and yaw, or the quaternion's four components) are interpolated by the quintic
spline of the planar trajectory file (:func:`prp3.model.motion.spline_derivatives`)
and the twist is built from their derivatives as the library does —
:func:`prp3.spatial.motion.rpy_rates` for roll–pitch–yaw, ``ω = 2·vec(q̇·q̄)``
and ``α = 2·vec(q̈·q̄)`` (divided by ``|q|²``) for quaternions.
The file is read with the bounds of :func:`prp3.io.tables.read_table` (size,
line length, UTF-8, numbers only, every error naming the file, line and column).

>>> import tempfile, pathlib
>>> file = pathlib.Path(tempfile.mkdtemp()) / "traj.csv"
>>> rows = "".join(f"{k / 10},0,0,{0.08 + k / 1000},0,0,0\n" for k in range(8))
>>> _ = file.write_text("t,x,y,z,roll,pitch,yaw\n" + rows)
>>> trajectory = read_spatial_trajectory(file)
>>> len(trajectory.motion), trajectory.lines[:2].tolist(), trajectory.orientation
(8, [2, 3], 'rpy')
>>> trajectory.motion.velocity[3].round(12).tolist()
[0.0, 0.0, 0.01]
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from prp3.errors import InputFileError, TrajectoryError
from prp3.io.tables import read_table
from prp3.io.trajectory import column_group
from prp3.model.motion import spline_derivatives
from prp3.spatial.motion import PlatformMotion, check_rpy, rpy_rates
from prp3.spatial.rotations import quaternion_matrix, rpy_matrix
from prp3.validation import check_file_path, first_not_increasing

__all__ = [
    "QUATERNION_COLUMNS",
    "RATE_COLUMNS",
    "RPY_COLUMNS",
    "SPATIAL_POSITION_COLUMNS",
    "SpatialMeasurements",
    "SpatialTrajectory",
    "read_spatial_measurements",
    "read_spatial_trajectory",
]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: The columns every spatial trajectory file has (s, m, m, m).
SPATIAL_POSITION_COLUMNS: tuple[str, ...] = ("t", "x", "y", "z")

#: The orientation as a unit quaternion ``[w, x, y, z]`` (docs/spatial.md §3).
QUATERNION_COLUMNS: tuple[str, ...] = ("qw", "qx", "qy", "qz")

#: The orientation as roll, pitch, yaw (rad, ``R = Rot_z(yaw)·Rot_y(pitch)·Rot_x(roll)``).
RPY_COLUMNS: tuple[str, ...] = ("roll", "pitch", "yaw")

#: The optional twist and its derivative (docs/spatial.md §4): all twelve or none.
RATE_COLUMNS: tuple[str, ...] = (
    "wx", "wy", "wz", "vx", "vy", "vz", "dwx", "dwy", "dwz", "ax", "ay", "az",
)  # fmt: skip

#: A quaternion read is accepted when its norm is within this of 1 (docs/spatial.md §3).
QUATERNION_TOLERANCE: float = 1e-6


@dataclass(frozen=True)
class SpatialTrajectory:
    """A platform motion read from a spatial trajectory file.

    Attributes
    ----------
    path : Path
    motion : PlatformMotion
        ``N >= 2`` samples in the file's order.
    lines : (N,) int
        The file line (1-based, header counted) of each sample.
    orientation : {"quaternion", "rpy"}
        How the file gives the orientation.
    note : str or None
        ``None`` when the file gives the rates; otherwise how they were derived.
    """

    path: Path
    motion: PlatformMotion
    lines: IntArray
    orientation: str
    note: str | None


def _stack(columns: dict[str, FloatArray], names: tuple[str, ...]) -> FloatArray:
    return np.stack([columns[name] for name in names], axis=-1)


def _quaternion_rates(
    q: FloatArray, dq: FloatArray, ddq: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """``ω = 2·vec(q̇·q̄)/|q|²`` and ``α = 2·vec(q̈·q̄)/|q|²`` (world frame), ``(N, 3)`` each."""

    def vector_part(a: FloatArray, b: FloatArray) -> FloatArray:
        # vec(a ⊗ conj(b)) = −a_w·b_v + b_w·a_v − a_v × b_v
        return -a[:, :1] * b[:, 1:] + b[:, :1] * a[:, 1:] - np.cross(a[:, 1:], b[:, 1:])

    norm2 = np.einsum("ij,ij->i", q, q)[:, None]
    return 2.0 * vector_part(dq, q) / norm2, 2.0 * vector_part(ddq, q) / norm2


def read_spatial_trajectory(path: str | Path) -> SpatialTrajectory:
    """Read a spatial trajectory file (see the module's description).

    Raises
    ------
    InputFileError
        An unreadable or empty file, an unknown, duplicate or missing column, both or
        neither orientation, some of the rate columns only (names the file and the header
        line); a row of the wrong length, a non-numeric or non-finite cell (file, line,
        column).
    TrajectoryError
        Fewer than 2 samples, a time that does not increase, a quaternion whose norm is
        not within ``1e-6`` of 1, rates derived from the poses that overflow (names the
        file and the line).
    """
    return _read(check_file_path("path", path), ())[0]


@dataclass(frozen=True)
class SpatialMeasurements:
    """A spatial trajectory file with the measured actuator efforts (``prp3 identify``).

    Attributes
    ----------
    trajectory : SpatialTrajectory
    tau : (N, legs)
        The columns ``tau_1 .. tau_<legs>`` (N for a P joint, N·m for an R joint).
    """

    trajectory: SpatialTrajectory
    tau: FloatArray


def read_spatial_measurements(path: str | Path, actuators: int) -> SpatialMeasurements:
    """Read a spatial trajectory file that also has the columns ``tau_1 .. tau_<actuators>``.

    The columns of docs/spatial.md §14 read as :func:`read_spatial_trajectory`
    reads them, and the measured actuator efforts beside them (required).

    Raises
    ------
    InputFileError, TrajectoryError
        As :func:`read_spatial_trajectory`; a ``tau_i`` column missing (names it).
    """
    if isinstance(actuators, bool) or not isinstance(actuators, int) or not 1 <= actuators <= 6:
        raise TrajectoryError(f"actuators must be an integer 1..6, got {actuators!r}")
    names = tuple(f"tau_{i + 1}" for i in range(actuators))
    trajectory, columns = _read(check_file_path("path", path), names)
    return SpatialMeasurements(trajectory, np.stack([columns[name] for name in names], axis=-1))


def _orientations(
    path: Path, columns: dict[str, FloatArray], lines: IntArray, *, quaternion: bool
) -> tuple[FloatArray, FloatArray]:
    """The orientation columns of a trajectory file as the values its spline runs through
    (unit quaternions of one sign from sample to sample, or unwrapped roll, pitch, yaw) and
    the rotation matrices ``(N, 3, 3)``; a sample that is not a rotation is named by line."""
    if quaternion:
        q = _stack(columns, QUATERNION_COLUMNS)
        norm = np.sqrt(np.einsum("ij,ij->i", q, q))
        bad = ~(np.abs(norm - 1.0) <= QUATERNION_TOLERANCE)
        if bad.any():
            k = int(np.argmax(bad))
            raise TrajectoryError(
                f"qw, qx, qy, qz is not a unit quaternion (norm {float(norm[k]):.12g}; "
                f"accepted within {QUATERNION_TOLERANCE:g} of 1)",
                file=path,
                line=int(lines[k]),
            )
        q = q / norm[:, None]
        flip = np.cumprod(np.where(np.einsum("ij,ij->i", q[1:], q[:-1]) < 0.0, -1.0, 1.0))
        q[1:] *= flip[:, None]  # q and −q are one rotation: the spline follows one sign
        return q, quaternion_matrix(q)
    try:
        angles = check_rpy(_stack(columns, RPY_COLUMNS))
    except TrajectoryError as error:
        line = int(lines[error.sample]) if error.sample is not None else None
        raise error.located(file=path, line=line, subject=None) from None
    angles = np.unwrap(angles, axis=0)  # the spline sees no 2π jump
    return angles, rpy_matrix(angles)


def _read(path: Path, required: tuple[str, ...]) -> tuple[SpatialTrajectory, dict[str, FloatArray]]:
    """:func:`read_spatial_trajectory` of a file with the ``required`` columns too."""
    optional = QUATERNION_COLUMNS + RPY_COLUMNS + RATE_COLUMNS
    table = read_table(path, SPATIAL_POSITION_COLUMNS + required, optional, "trajectory")
    columns, lines, header = table.columns, table.lines, table.header_line
    quaternion = column_group(path, columns, QUATERNION_COLUMNS, "quaternion", header)
    rpy = column_group(path, columns, RPY_COLUMNS, "roll-pitch-yaw", header)
    if quaternion == rpy:
        raise InputFileError(
            "give the orientation as either the columns qw, qx, qy, qz or roll, pitch, yaw"
            + (", not both" if rpy else ""),
            file=path,
            line=header,
        )
    rates = column_group(path, columns, RATE_COLUMNS, "rate", header)
    t = columns["t"]
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
    position = _stack(columns, ("x", "y", "z"))
    angles, rotation = _orientations(path, columns, lines, quaternion=quaternion)
    note: str | None = None
    if rates:
        omega, velocity = _stack(columns, RATE_COLUMNS[0:3]), _stack(columns, RATE_COLUMNS[3:6])
        alpha, acceleration = _stack(columns, RATE_COLUMNS[6:9]), _stack(columns, RATE_COLUMNS[9:])
    else:
        with np.errstate(all="ignore"):  # an overflow is reported below, naming the line
            try:
                velocity, acceleration, degree = spline_derivatives(t, position)
            except TrajectoryError as error:  # steps lost against the span: the sample's line
                line = int(lines[error.sample]) if error.sample is not None else None
                raise error.located(file=path, line=line, sample=None) from None
            rate, second, _ = spline_derivatives(t, angles)
            if quaternion:
                omega, alpha = _quaternion_rates(angles, rate, second)
            else:
                omega, alpha = rpy_rates(angles, rate, second)
        derived = (("v", velocity), ("a", acceleration), ("omega", omega), ("alpha", alpha))
        for name, values in derived:
            bad = ~np.isfinite(values)
            if bad.any():
                k, axis = (int(v) for v in np.argwhere(bad)[0])
                raise TrajectoryError(
                    f"the {name}_{'xyz'[axis]} derived from the poses is not finite "
                    f"({float(values[k, axis])!r}): poses too large or time steps too small; "
                    f"give the rate columns {', '.join(RATE_COLUMNS)}",
                    file=path,
                    line=int(lines[k]),
                )
        what = "the quaternion's components" if quaternion else "roll, pitch, yaw"
        note = (
            f"{path}: poses only; the twist and its derivative derived from the 1st and 2nd "
            f"derivatives of a degree-{degree} interpolating spline through x, y, z and "
            f"{what} (docs/spatial.md §14); accurate for smooth, finely sampled motions, "
            "less so near the first and last samples"
        )
    try:
        motion = PlatformMotion.of(t, position, rotation, omega, velocity, alpha, acceleration)
    except TrajectoryError as error:
        line = int(lines[error.sample]) if error.sample is not None else None
        raise error.located(file=path, line=line, subject=None) from None
    orientation = "quaternion" if quaternion else "rpy"
    return SpatialTrajectory(path, motion, lines, orientation, note), columns
