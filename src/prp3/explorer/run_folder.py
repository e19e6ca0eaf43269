"""The explorer's runs: a folder of ``prp3 simulate`` results read, checked against the robot.

:func:`read_run` reads ``DIR/results.csv`` (else ``DIR/results.parquet``) of
the 3-PRP's columns, :func:`read_family_run` those of a family robot (the 64
of docs/family.md); :func:`run_motion` and :func:`family_run_motion` give the
platform motion of a run (pose, velocity, acceleration at every sample), from
its own columns, after checking that the run is the robot's.  No Bokeh.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from prp3.analysis.forward_kinematics import forward_acceleration, forward_velocity
from prp3.errors import InputFileError, Prp3Error
from prp3.io.results import FRICTION_COLUMNS, LOAD_RESULT_COLUMNS, RESULT_COLUMNS
from prp3.io.tables import read_table_csv
from prp3.mechanics.geometry import inverse_geometry
from prp3.model.motion import Motion
from prp3.model.robot import Robot
from prp3.validation import LEGS, first_not_increasing

if TYPE_CHECKING:
    from prp3.family import FamilyRobot

__all__ = [
    "RUN_MATCH_TOLERANCE",
    "Run",
    "broken_parquet",
    "family_run_motion",
    "read_family_run",
    "read_parquet_columns",
    "read_run",
    "run_motion",
]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Run:
    """The results of a ``prp3 simulate`` run (``DIR/results.csv`` or ``DIR/results.parquet``).

    Attributes
    ----------
    path : Path
        The results file read.
    table : dict of str to ndarray (N,)
        Its columns (the 46 of ``results.csv``, the friction and load columns when present).
    """

    path: Path
    table: dict[str, FloatArray] = field(repr=False)

    @property
    def samples(self) -> int:
        """Its number of samples."""
        return int(self.table["t"].size)


def read_run(directory: str | Path) -> Run:
    """Read the results of ``prp3 simulate --output DIR`` (CSV or Parquet).

    ``DIR/results.csv`` is read when present, else ``DIR/results.parquet``;
    the columns are those of the data contract (the 46, optionally the 9 of
    friction and ``fx, fy, mz``), every value finite, ``t`` strictly increasing.

    Raises
    ------
    InputFileError
        No such folder or no results file in it; a file that does not parse
        (names the file, line and column).
    """
    return _read_folder(directory, RESULT_COLUMNS, FRICTION_COLUMNS + LOAD_RESULT_COLUMNS)


def read_family_run(directory: str | Path) -> Run:
    """Read the results of ``prp3 simulate --robot FAMILY.toml --output DIR`` (CSV or Parquet).

    The 64 columns of the family form (:data:`prp3.family.FAMILY_COLUMNS`),
    every value finite, ``t`` strictly increasing; refused as :func:`read_run`
    refuses.
    """
    from prp3.family import FAMILY_COLUMNS

    return _read_folder(directory, FAMILY_COLUMNS, ())


def _read_folder(
    directory: str | Path, required: tuple[str, ...], optional: tuple[str, ...]
) -> Run:
    folder = Path(directory)
    if not folder.is_dir():
        raise InputFileError("not a folder of `prp3 simulate` results", file=folder)
    csv_path, parquet_path = folder / "results.csv", folder / "results.parquet"
    if csv_path.is_file():
        table = read_table_csv(csv_path, required, optional, what="results")
        path = csv_path
    elif parquet_path.is_file():
        table = read_parquet_columns(parquet_path, required, optional)
        path = parquet_path
    else:
        raise InputFileError(
            "no results.csv or results.parquet in it (the output of `prp3 simulate --output DIR`)",
            file=folder,
        )
    t = table["t"]
    k = first_not_increasing(t)
    if k is not None:
        raise InputFileError(
            f"t must be strictly increasing: t = {float(t[k])!r} follows {float(t[k - 1])!r}",
            file=path,
            sample=k,
            time=float(t[k]),
            key="t",
        )
    return Run(path=path, table=table)


def broken_parquet(path: Path, error: Exception) -> str:
    """Why pyarrow cannot read ``path``: cut short (``PAR1`` at its start, not at its end)."""
    try:
        data = path.read_bytes()
    except OSError:
        data = b""
    if data[:4] == b"PAR1" and data[-4:] != b"PAR1":
        return (
            f"truncated: a Parquet file cut short ({len(data)} bytes, without the footer that "
            "ends every Parquet file); run the command that wrote it again"
        )
    return f"not a Parquet file ({error})"[:300]


def read_parquet_columns(
    path: Path, required: tuple[str, ...], optional: tuple[str, ...] = ()
) -> dict[str, FloatArray]:
    """The float64 columns of the Parquet run file ``path``: every ``required`` one, any ``optional``.

    Raises
    ------
    InputFileError
        Not Parquet, an unknown or missing column, a value that is not a finite number
        (naming the column and sample), or no rows.
    """
    try:
        import pyarrow.parquet as pq
    except ImportError:  # pragma: no cover - pyarrow is in the test extra
        raise InputFileError(
            "reading Parquet needs pyarrow: pip install 'prp3[parquet]'", file=path
        ) from None
    try:
        data = pq.read_table(str(path))
    except Exception as error:  # pyarrow raises its own types for a broken file
        raise InputFileError(broken_parquet(path, error), file=path) from None
    names = list(data.column_names)
    allowed = set(required) | set(optional)
    for name in names:
        if name not in allowed:
            raise InputFileError(f"unknown column {name[:40]!r}", file=path, key=name)
    missing = [name for name in required if name not in names]
    if missing:
        raise InputFileError(f"missing column(s) {', '.join(missing)}", file=path)
    table: dict[str, FloatArray] = {}
    for name in names:
        try:
            column = np.asarray(data.column(name).to_numpy(), dtype=np.float64)
        except (TypeError, ValueError) as error:
            raise InputFileError(
                f"column {name!r}: not numbers ({error})"[:300], file=path, key=name
            ) from None
        bad = np.flatnonzero(~np.isfinite(column))
        if bad.size:
            raise InputFileError(
                f"column {name!r}: not a finite number: {float(column[bad[0]])!r}",
                file=path,
                key=name,
                sample=int(bad[0]),
            )
        table[name] = column
    if table["t"].size == 0:
        raise InputFileError("no data rows", file=path)
    return table


#: Largest difference between a run's ``lambda10`` and the robot's inverse geometry, per ``l0``
#: (and between a family run's ``q{k}`` and its robot's, in metres or radians).
RUN_MATCH_TOLERANCE: float = 1e-9


def run_motion(robot: Robot, run: Run) -> Motion:
    """The platform motion of a run: poses from its columns, rates by the forward kinematics.

    ``(ẋ, ẏ, φ̇) = J⁻¹·λ̇10`` and ``q̈ = J⁻¹·(λ̈10 − J̇·q̇)`` (eqs. 14, 17 solved for
    the platform, :func:`prp3.analysis.forward_kinematics.forward_velocity` and
    :func:`prp3.analysis.forward_kinematics.forward_acceleration`), with the run's load columns.
    ``robot`` must be the run's: its inverse geometry must give the run's
    ``lambda10`` (to ``1e-9·l0``), else an :class:`~prp3.errors.InputFileError`
    names the sample.
    """
    table = run.table
    pose = np.stack([table["x"], table["y"], table["phi"]], axis=-1)
    try:
        geo = inverse_geometry(robot, pose)
    except Prp3Error as error:
        raise error.located(file=run.path) from None
    lam = np.stack([table[f"lambda10_{leg}"] for leg in LEGS], axis=-1)
    gap = np.abs(geo.lambda10 - lam) > RUN_MATCH_TOLERANCE * robot.l0
    if gap.any():
        k, j = (int(v) for v in np.argwhere(gap)[0])
        raise InputFileError(
            f"lambda10_{LEGS[j]} = {float(lam[k, j])!r} m, but the robot's geometry gives "
            f"{float(geo.lambda10[k, j])!r} m: give the --robot of the run",
            file=run.path,
            sample=k,
            time=float(table["t"][k]),
            leg=LEGS[j],
        )
    rates = np.stack([table[f"dlambda10_{leg}"] for leg in LEGS], axis=-1)
    second = np.stack([table[f"ddlambda10_{leg}"] for leg in LEGS], axis=-1)
    velocity = forward_velocity(robot, pose, rates)
    acceleration = forward_acceleration(robot, pose, velocity, second)
    load = (
        np.stack([table[name] for name in LOAD_RESULT_COLUMNS], axis=-1)
        if all(name in table for name in LOAD_RESULT_COLUMNS)
        else None
    )
    return Motion(t=table["t"], pose=pose, velocity=velocity, acceleration=acceleration, load=load)


def family_run_motion(robot: FamilyRobot, run: Run) -> Motion:
    """The platform motion of a family run: poses from its columns, rates from its joints' own.

    Each leg's ``J`` at the run's poses (``(ẋ, ẏ, φ̇) = J·q̇``, docs/family.md §5,
    :func:`prp3.family.family_kinematics`) turns leg A's ``dq{k}`` into the
    platform's velocity and its ``ddq{k}`` into the acceleration,
    ``(ẍ, ÿ, φ̈) = J·q̈ + J̇·q̇`` (the relation the library solves for ``q̈``).
    ``robot`` must be the run's: its inverse geometry must give the run's
    ``q{k}`` of every leg (to ``1e-9``), else an :class:`~prp3.errors.InputFileError`
    names the sample.
    """
    from prp3.family import family_kinematics
    from prp3.family.mechanics import jacobian_rate

    table = run.table
    t = table["t"]
    pose = np.stack([table["x"], table["y"], table["phi"]], axis=-1)
    zeros = np.zeros_like(pose)
    try:
        kin = family_kinematics(robot, Motion(t=t, pose=pose, velocity=zeros, acceleration=zeros))
    except Prp3Error as error:
        raise error.located(file=run.path) from None

    def joints(name: str) -> FloatArray:  # (N, legs, joints)
        return np.stack(
            [np.stack([table[f"{name}{k}_{leg}"] for k in (1, 2, 3)], axis=-1) for leg in LEGS],
            axis=1,
        )

    q = joints("q")
    gap = np.abs(kin.q - q) > RUN_MATCH_TOLERANCE  # metres or radians
    if gap.any():
        n, j, k = (int(v) for v in np.argwhere(gap)[0])
        raise InputFileError(
            f"q{k + 1}_{LEGS[j]} = {float(q[n, j, k])!r}, but the {robot.architecture}'s geometry "
            f"gives {float(kin.q[n, j, k])!r}: give the --robot of the run",
            file=run.path,
            sample=n,
            time=float(t[n]),
            leg=LEGS[j],
        )
    dq, ddq = joints("dq"), joints("ddq")
    jac = kin.jacobian  # (N, legs, 3, 3)
    velocity = np.einsum("nij,nj->ni", jac[:, 0], dq[:, 0])
    bias = jacobian_rate(robot.types, kin.frames, jac, dq, velocity)
    acceleration = np.einsum("nij,nj->ni", jac[:, 0], ddq[:, 0]) + np.einsum(
        "nij,nj->ni", bias[:, 0], dq[:, 0]
    )
    return Motion(t=t, pose=pose, velocity=velocity, acceleration=acceleration)
