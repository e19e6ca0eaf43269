"""The file formats of prp3, in one place: CSV tables, ``TRAJ.csv``, ``results.csv``, forces.

* :func:`write_table_csv` / :func:`read_table_csv`: numeric CSV tables with a
  header row of column names, full-precision numbers (``repr(float)``),
  written atomically, read strictly (known columns, numbers only; every error
  names the file, the line and the column) and with bounds
  (:mod:`prp3.files`).
* ``TRAJ.csv`` of the data contract (``docs/model.md``; :func:`read_trajectory`, :func:`trajectory_table`): a platform
  motion, columns :data:`POSITION_COLUMNS` and optionally
  :data:`DERIVATIVE_COLUMNS`.
* ``results.csv`` (:data:`RESULT_COLUMNS`, :func:`results_table`): the
  kinematics and complete inverse dynamics of a run.
* the forces table (:data:`FORCE_COLUMNS`, :func:`read_forces`): actuator
  force histories for ``prp3 forward``, or a whole ``results.csv``.

The files themselves (bounded reads, atomic and staged writes) are
:mod:`prp3.files`; its names are re-exported here.

>>> import tempfile, pathlib
>>> folder = pathlib.Path(tempfile.mkdtemp())
>>> write_table_csv(folder / "a.csv", {"t": np.array([0.0, 0.1]), "x": np.array([1.0, 2.0])})
>>> print((folder / "a.csv").read_text(), end="")
t,x
0.0,1.0
0.1,2.0
>>> read_table_csv(folder / "a.csv", required=("t", "x"))["x"].tolist()
[1.0, 2.0]
"""

from __future__ import annotations

import csv
import math
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .dynamics import InverseDynamics
from .errors import (
    InputFileError,
    OutputFileError,
    ParameterError,
    Prp3Error,
    SingularPoseError,
    TrajectoryError,
)
from .files import (
    MANIFEST_NAME,
    StagedOutput,
    atomic_path,
    atomic_writer,
    check_inputs_kept,
    check_output_directory,
    read_manifest,
    read_text_lines,
    staged_output,
)
from .forward import ActuatorForces
from .geometry import LEGS
from .kinematics import Kinematics
from .motion import Motion, differentiate_positions, spline_derivatives
from .validation import check_path

__all__ = [
    "DERIVATIVE_COLUMNS",
    "FORCE_COLUMNS",
    "FRICTION_COLUMNS",
    "LOAD_COLUMNS",
    "LOAD_RESULT_COLUMNS",
    "MANIFEST_NAME",
    "MEASURED_FORCE_COLUMNS",
    "OUTPUT_QUANTITIES",
    "PER_LEG_COLUMNS",
    "POSITION_COLUMNS",
    "RESULT_COLUMNS",
    "TRAJECTORY_COLUMNS",
    "ForceInput",
    "Measurements",
    "OutputQuantity",
    "StagedOutput",
    "Trajectory",
    "atomic_path",
    "atomic_writer",
    "check_inputs_kept",
    "check_output_directory",
    "differentiate_positions",
    "format_float",
    "format_floats",
    "output_quantity",
    "parquet_available",
    "read_forces",
    "read_manifest",
    "read_measurements",
    "read_table_csv",
    "read_trajectory",
    "result_columns",
    "results_table",
    "staged_output",
    "trajectory_table",
    "write_table_csv",
    "write_table_parquet",
]

#: Columns of a trajectory file that are always required (s, m, m, rad).
POSITION_COLUMNS: tuple[str, ...] = ("t", "x", "y", "phi")

#: Optional derivative columns of a trajectory file: all six or none.
DERIVATIVE_COLUMNS: tuple[str, ...] = ("dx", "dy", "dphi", "ddx", "ddy", "ddphi")

#: Optional load columns of a trajectory file (a wrench on the platform): all three or none.
LOAD_COLUMNS: tuple[str, ...] = ("fx", "fy", "mz")

#: Columns of a trajectory written by prp3 (``prp3 forward``'s ``trajectory.csv``).
TRAJECTORY_COLUMNS: tuple[str, ...] = POSITION_COLUMNS + DERIVATIVE_COLUMNS

#: Columns of a force history file.
FORCE_COLUMNS: tuple[str, ...] = ("t", "f10_A", "f10_B", "f10_C")

#: Rows written per block by :func:`write_table_csv` (and per progress report).
_ROWS_PER_BLOCK = 20_000

#: Rows per block when Arrow makes the text (bounds the memory of the texts).
_ARROW_ROWS_PER_BLOCK = 100_000

#: Rows parsed per block by :func:`read_table_csv`.
_READ_BLOCK = 65_536

ProgressCallback = Callable[[int, int], None]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


def format_float(value: float) -> str:
    """Format a float with full precision: ``repr``, the shortest text that reads back exactly.

    >>> format_float(0.1), format_float(2.0), format_float(-1e-20)
    ('0.1', '2.0', '-1e-20')
    """
    return repr(float(value))


def write_table_csv(
    path: str | Path,
    table: Mapping[str, FloatArray],
    *,
    progress: ProgressCallback | None = None,
) -> None:
    """Write named columns ``(N,)`` (or scalars) as CSV, full precision, atomically.

    Every number is written as ``repr(float)`` (:func:`format_float`), the
    shortest text that reads back to the same float.  With pyarrow installed
    the texts are made by Arrow's shortest round-trip conversion, laid out as
    ``repr`` lays them out (:func:`format_floats`), and written by Arrow's CSV
    writer: byte for byte the same file, about 3 times faster.  ``progress(rows_done,
    rows)`` is called after each block of rows when given.
    """
    names = list(table)
    columns = [np.atleast_1d(np.asarray(table[name], dtype=np.float64)) for name in names]
    if columns and len(columns[0]) and _pyarrow() is not None:
        with atomic_path(path) as temporary:
            _write_csv_arrow(temporary, names, columns, progress)
        return
    _write_csv_python(path, names, columns, progress)


def _write_csv_python(
    path: str | Path,
    names: list[str],
    columns: list[FloatArray],
    progress: ProgressCallback | None,
) -> None:
    """The CSV text by Python's ``repr``, row by row (no pyarrow needed)."""
    rows = len(columns[0]) if columns else 0
    row_format = ",".join(["%r"] * len(names)) + "\n"  # %r is repr(float), as format_float
    with atomic_writer(path) as stream:
        stream.write(",".join(names) + "\n")
        for start in range(0, rows if columns else 0, _ROWS_PER_BLOCK):
            stop = min(start + _ROWS_PER_BLOCK, rows)
            block = np.column_stack([column[start:stop] for column in columns]).tolist()
            stream.write("".join(row_format % tuple(row) for row in block))
            if progress is not None:
                progress(stop, rows)


def _pyarrow() -> Any:
    """The ``pyarrow`` module, or ``None`` when it is not installed (an optional extra)."""
    try:
        import pyarrow
        import pyarrow.compute
        import pyarrow.csv
    except ImportError:
        return None
    return pyarrow


#: ``repr`` writes ``|x|`` in positional notation from this double up (and 0)...
_POSITIONAL_FROM: float = 1e-4
#: ... to below this one; in scientific notation with 2 or 3 exponent digits otherwise.
_POSITIONAL_BELOW: float = 1e16
#: Scientific texts of ``|x|`` from here to ``_POSITIONAL_FROM`` have 1-digit exponents in Arrow.
_TWO_DIGIT_EXPONENT_BELOW: float = 1e-9


def _arrow_texts(column: FloatArray) -> Any:
    """``repr`` of every float of ``column`` (N,), as a ``pyarrow.StringArray``.

    Arrow casts a double to its shortest round-trip decimal digits (the digits
    ``repr`` gives: the shortest text that reads back, the closest one to the
    double when there are several) but lays them out its own way.  Which
    layout ``repr`` uses is decided from the value: positional notation exactly
    for ``1e-4 <= |x| < 1e16`` (a double below ``1e-4`` cannot have the
    shortest text ``0.0001``, which reads back to the double ``1e-4``;
    likewise at ``1e16``, exactly representable), scientific notation with at
    least two exponent digits otherwise.  So Arrow's text is kept where it has
    ``repr``'s notation: positional with a fraction, or scientific with a
    two-digit exponent (``|x| < 1e-9`` or ``|x| >= 1e16``).  The others are
    rewritten: zeros become ``0.0`` and ``-0.0``; positional integral values
    get ``repr``'s ``.0``; ``1e-9 <= |x| < 1e-4`` (Arrow writes ``0.0000123``
    or ``1.5e-8``) is moved to ``repr``'s ``1.23e-05`` and ``1.5e-08`` by
    regular expressions on the digits, each result checked against the only
    form it can have; anything else (Arrow's scientific texts from ``1e15`` to
    ``1e16``, non-finite numbers, a text that failed the check) is formatted
    by ``repr`` itself.  The tests hold the result to ``repr`` byte for byte.
    """
    pa = _pyarrow()
    pc = pa.compute
    size = column.size
    zero = column == 0.0
    zeros = pa.array(["0.0", "-0.0"], type=pa.string())
    if zero.all():  # a common column (x = 0, m10 = 0, ...): no conversion at all
        return pc.take(zeros, pa.array(np.signbit(column).astype(np.int8)))
    magnitude = np.abs(column)
    text = pc.cast(pa.array(column, type=pa.float64()), pa.string())
    scientific = np.asarray(pc.match_substring(text, "e"), dtype=bool)
    with np.errstate(invalid="ignore"):
        positional = (magnitude >= _POSITIONAL_FROM) & (magnitude < _POSITIONAL_BELOW)
        integral = column == np.trunc(column)
        small = (magnitude >= _TWO_DIGIT_EXPONENT_BELOW) & (magnitude < _POSITIONAL_FROM)
        two_digits = (magnitude < _TWO_DIGIT_EXPONENT_BELOW) | (magnitude >= _POSITIONAL_BELOW)
    kept = (positional & ~scientific & ~integral) | (scientific & two_digits & ~zero)
    if kept.all():
        return text
    indices: list[Any] = []
    replacements: list[Any] = []

    def replace(where: NDArray[np.bool_], texts: Any) -> None:
        indices.append(np.flatnonzero(where))
        replacements.append(texts)

    if zero.any():
        replace(zero, pc.take(zeros, pa.array(np.signbit(column[zero]).astype(np.int8))))
    whole = positional & ~scientific & integral
    if whole.any():
        replace(whole, pc.binary_join_element_wise(pc.filter(text, pa.array(whole)), ".0", ""))
    rest = ~(kept | zero | whole)
    if (small & rest).any():
        subset = small & rest
        moved = pc.filter(text, pa.array(subset))
        for zeros, exponent in (("0000", "05"), ("00000", "06"), ("000000", "07")):
            # 0.0000123 -> 1.23e-05, 0.00001 -> 1e-05 (the first digit after the zeros is 1-9)
            pattern = f"^(-?)0\\.{zeros}([1-9])"
            moved = pc.replace_substring_regex(moved, pattern + "$", f"\\1\\2e-{exponent}")
            moved = pc.replace_substring_regex(
                moved, pattern + "([0-9]+)$", f"\\1\\2.\\3e-{exponent}"
            )
        moved = pc.replace_substring_regex(moved, "e-([5-9])$", "e-0\\1")  # 1.5e-8 -> 1.5e-08
        good = np.asarray(
            pc.match_substring_regex(moved, "^-?[1-9](\\.[0-9]*[1-9])?e-0[5-9]$"), dtype=bool
        )
        positions = np.flatnonzero(subset)
        replace(np.isin(np.arange(size), positions[good]), pc.filter(moved, pa.array(good)))
        rest[positions[good]] = False
    if rest.any():
        replace(rest, pa.array([repr(value) for value in column[rest].tolist()], type=pa.string()))
    where = np.concatenate(indices)
    order = np.argsort(where, kind="stable")
    values = pc.take(pa.concat_arrays(replacements), pa.array(order))
    mask = np.zeros(size, dtype=bool)
    mask[where] = True
    return pc.replace_with_mask(text, pa.array(mask), values)


def format_floats(values: ArrayLike) -> list[str]:
    """``repr`` of every float of a 1-d array, the way :func:`write_table_csv` writes them.

    With pyarrow installed the texts come from Arrow's shortest round-trip
    conversion (see ``_arrow_texts``), else from ``repr``; they are the same.

    >>> format_floats([0.1, 2.0, -0.0, 1e-05, 5e-324, 1e300, 1234.5])
    ['0.1', '2.0', '-0.0', '1e-05', '5e-324', '1e+300', '1234.5']
    """
    column = np.atleast_1d(np.asarray(values, dtype=np.float64))
    if column.ndim != 1:
        raise ValueError(f"format_floats takes a 1-d array, got shape {column.shape}")
    if column.size == 0 or _pyarrow() is None:
        return [repr(value) for value in column.tolist()]
    return list(_arrow_texts(column).to_pylist())


def _write_csv_arrow(
    path: Path,
    names: list[str],
    columns: list[FloatArray],
    progress: ProgressCallback | None,
) -> None:
    """The CSV text of :func:`_write_csv_python`, made and written by Arrow, block by block."""
    pa = _pyarrow()
    rows = len(columns[0])
    schema = pa.schema([(name, pa.string()) for name in names])
    options = pa.csv.WriteOptions(include_header=False, quoting_style="none")
    with pa.OSFile(str(path), "wb") as sink:
        sink.write((",".join(names) + "\n").encode("utf-8"))
        with pa.csv.CSVWriter(sink, schema, write_options=options) as writer:
            for start in range(0, rows, _ARROW_ROWS_PER_BLOCK):
                stop = min(start + _ARROW_ROWS_PER_BLOCK, rows)
                texts = [_arrow_texts(column[start:stop]) for column in columns]
                writer.write_batch(pa.record_batch(texts, schema=schema))
                if progress is not None:
                    progress(stop, rows)


def parquet_available() -> bool:
    """Whether Parquet files can be written (pyarrow, the optional extra ``parquet``)."""
    return _pyarrow() is not None


def write_table_parquet(path: str | Path, table: Mapping[str, FloatArray]) -> None:
    """Write named columns ``(N,)`` as a Parquet file of float64 columns, atomically.

    The same columns, in the same order, as :func:`write_table_csv` writes;
    every value is the float64 itself (no text).  Needs pyarrow (the optional
    extra ``parquet``: ``pip install 'prp3[parquet]'``).

    Raises
    ------
    OutputFileError
        When pyarrow is not installed (before anything is written).
    """
    pa = _pyarrow()
    if pa is None:
        raise OutputFileError(
            "writing Parquet needs pyarrow, which is not installed: "
            "pip install 'prp3[parquet]', or write CSV",
            file=path,
        )
    import pyarrow.parquet as pq

    arrays = [pa.array(np.atleast_1d(np.asarray(table[name], dtype=np.float64))) for name in table]
    data = pa.Table.from_arrays(arrays, names=list(table))
    with atomic_path(path) as temporary:
        # no dictionary encoding: the doubles of a run are (nearly) all distinct, so the
        # dictionaries are built only to be dropped (2.4 times the time of the write)
        pq.write_table(data, str(temporary), use_dictionary=False)


def read_table_csv(
    path: str | Path,
    required: Sequence[str],
    optional: Sequence[str] = (),
    what: str = "table",
) -> dict[str, FloatArray]:
    """Read a numeric CSV table with a header row; return its columns by name.

    Parameters
    ----------
    path : str or Path
        The CSV file.
    required : sequence of str
        Columns that must be present.
    optional : sequence of str
        Columns that may be present; any other column is an error.
    what : str
        What the file is, for messages (e.g. ``"trajectory"``).

    Raises
    ------
    InputFileError
        Unreadable file, empty file, missing/unknown/duplicate column, a row
        of the wrong length, a non-numeric or non-finite cell (names file,
        line and column), or fewer than one data row.
    """
    return _read_table(Path(path), required, optional, what).columns


@dataclass(frozen=True)
class _Table:
    columns: dict[str, FloatArray]
    lines: IntArray  # (N,) line number of each data row in the file (1-based)
    header_line: int


def _records(path: Path, what: str) -> Iterator[tuple[int, list[str]]]:
    """``(first line, cells)`` of each non-blank CSV record of a bounded read of ``path``.

    The line is the file line where the record starts, also when a quoted
    cell spans several lines.
    """
    reader = csv.reader(read_text_lines(path, what))
    line = 0
    while True:
        start = line + 1
        try:
            row = next(reader)
        except StopIteration:
            return
        except csv.Error as error:  # e.g. a quoted cell longer than csv's field limit
            raise InputFileError(f"malformed CSV ({error})", file=path, line=start) from None
        line = reader.line_num
        if any(cell.strip() for cell in row):
            yield start, row


def _read_table(path: Path, required: Sequence[str], optional: Sequence[str], what: str) -> _Table:
    records = _records(path, what)
    first = next(records, None)
    if first is None:
        raise InputFileError(f"empty {what} file (expected a header row)", file=path)
    header_line, raw_header = first
    header = [cell.strip() for cell in raw_header]
    allowed = list(required) + list(optional)
    for name in header:
        if name not in allowed:
            raise InputFileError(
                f"unknown column {name[:40]!r} "
                f"(expected {', '.join(required)}"
                + (f", optionally {', '.join(optional)}" if optional else "")
                + ")",
                file=path,
                line=header_line,
                key=name,
            )
    seen: set[str] = set()
    for name in header:
        if name in seen:
            raise InputFileError(
                f"duplicate column {name!r}", file=path, line=header_line, key=name
            )
        seen.add(name)
    missing = [name for name in required if name not in seen]
    if missing:
        raise InputFileError(f"missing column(s) {', '.join(missing)}", file=path, line=header_line)
    width = len(header)
    blocks: list[FloatArray] = []
    numbers: list[int] = []
    block = np.empty((_READ_BLOCK, width))
    filled = 0
    for line, row in records:
        if len(row) != width:
            raise InputFileError(f"expected {width} values, got {len(row)}", file=path, line=line)
        for c, cell in enumerate(row):
            try:
                if "_" in cell or not cell.isascii():  # float() takes '1_0' and other digits
                    raise ValueError(cell)
                number = float(cell)
            except ValueError:
                raise InputFileError(
                    f"column {header[c]!r}: not a number: {cell.strip()[:40]!r}",
                    file=path,
                    line=line,
                    key=header[c],
                ) from None
            if not math.isfinite(number):
                raise InputFileError(
                    f"column {header[c]!r}: not a finite number: {cell.strip()!r}",
                    file=path,
                    line=line,
                    key=header[c],
                )
            block[filled, c] = number
        numbers.append(line)
        filled += 1
        if filled == _READ_BLOCK:
            blocks.append(block)
            block = np.empty((_READ_BLOCK, width))
            filled = 0
    blocks.append(block[:filled])
    if not numbers:
        raise InputFileError("no data rows after the header", file=path)
    values = np.concatenate(blocks) if len(blocks) > 1 else blocks[0]
    return _Table(
        columns={name: values[:, c].copy() for c, name in enumerate(header)},
        lines=np.array(numbers, dtype=np.int64),
        header_line=header_line,
    )


# ---------------------------------------------------------------- trajectories
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


def read_trajectory(path: str | Path) -> Trajectory:
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
    return _trajectory(path, _read_table(path, POSITION_COLUMNS, optional, "trajectory"))


def _trajectory(path: Path, table: _Table) -> Trajectory:
    """The motion of a table with the columns of a trajectory file (see :func:`read_trajectory`)."""
    columns = table.columns
    loads = [name for name in LOAD_COLUMNS if name in columns]
    if loads and len(loads) != len(LOAD_COLUMNS):
        missing = [name for name in LOAD_COLUMNS if name not in columns]
        raise InputFileError(
            f"give all of the load columns {', '.join(LOAD_COLUMNS)} or none; "
            f"missing {', '.join(missing)}",
            file=path,
            line=table.header_line,
        )
    given = [name for name in DERIVATIVE_COLUMNS if name in columns]
    if given and len(given) != len(DERIVATIVE_COLUMNS):
        missing = [name for name in DERIVATIVE_COLUMNS if name not in columns]
        raise InputFileError(
            f"give all of the derivative columns {', '.join(DERIVATIVE_COLUMNS)} or none; "
            f"missing {', '.join(missing)}",
            file=path,
            line=table.header_line,
        )
    t = columns["t"]
    lines = table.lines
    if len(t) < 2:
        raise TrajectoryError(
            f"a trajectory needs at least 2 samples, got {len(t)}", file=path, line=int(lines[0])
        )
    steps = np.diff(t)
    if (steps <= 0.0).any():
        k = int(np.argmax(steps <= 0.0)) + 1
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
        # between the samples: no singular orientation crossed, no step the given rates deny
        rates = (motion.velocity, motion.acceleration) if given else (None, None)
        check_path(motion.t, motion.pose, *rates, lines=lines, subject=None)
    except (TrajectoryError, SingularPoseError) as error:  # SingularPoseError: check_path's
        line = int(lines[error.sample]) if error.sample is not None else None
        raise error.located(file=path, line=line) from None
    return Trajectory(path=path, motion=motion, lines=lines, note=note)


#: Measured actuator forces of a measurement file (N).
MEASURED_FORCE_COLUMNS: tuple[str, ...] = ("f10_A", "f10_B", "f10_C")


@dataclass(frozen=True)
class Measurements:
    """A measured motion and its actuator forces, read by :func:`read_measurements`.

    Attributes
    ----------
    trajectory : Trajectory
        The motion (columns as a trajectory file's; derivatives computed when absent).
    f10 : ndarray, shape (N, 3)
        The measured forces ``f10_A, f10_B, f10_C`` (N).
    """

    trajectory: Trajectory
    f10: FloatArray


def read_measurements(path: str | Path) -> Measurements:
    r"""Read a measurement file: a trajectory file's columns plus ``f10_A, f10_B, f10_C``.

    The same strict reader and conventions as :func:`read_trajectory`
    (derivative columns optional, all six or none; load columns ``fx, fy, mz``
    optional, all three or none; time strictly increasing).

    Raises
    ------
    InputFileError, TrajectoryError
        As :func:`read_trajectory`; a missing force column is named.

    Examples
    --------
    >>> import tempfile, pathlib
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
    table = _read_table(
        path,
        POSITION_COLUMNS + MEASURED_FORCE_COLUMNS,
        DERIVATIVE_COLUMNS + LOAD_COLUMNS,
        "measurement",
    )
    f10 = np.stack([table.columns[name] for name in MEASURED_FORCE_COLUMNS], axis=-1)
    return Measurements(trajectory=_trajectory(path, table), f10=f10)


def trajectory_table(motion: Motion) -> dict[str, FloatArray]:
    """The columns :data:`TRAJECTORY_COLUMNS` of a batch motion, as named arrays ``(N,)``.

    >>> from prp3.motion import paper_motion
    >>> table = trajectory_table(paper_motion("vertical", 3))
    >>> list(table), table["y"].tolist()
    (['t', 'x', 'y', 'phi', 'dx', 'dy', 'dphi', 'ddx', 'ddy', 'ddphi'], [0.0, 0.025, 0.05])
    """
    arrays = (motion.pose, motion.velocity, motion.acceleration)
    table: dict[str, FloatArray] = {"t": motion.t}
    for k, name in enumerate(TRAJECTORY_COLUMNS[1:]):
        table[name] = arrays[k // 3][..., k % 3]
    return table


# ---------------------------------------------------------------- results.csv
@dataclass(frozen=True)
class OutputQuantity:
    """One quantity of ``results.csv``: the one place its name, unit and meaning are given.

    The columns of ``results.csv`` and Parquet (:data:`RESULT_COLUMNS`,
    :data:`FRICTION_COLUMNS`), the labels of the figures
    (:mod:`prp3.plotting.figures`) and the units of the run summary
    (:func:`prp3.runs.summary_text`) are derived from :data:`OUTPUT_QUANTITIES`.

    Attributes
    ----------
    name : str
        The column (``t``) or, for a per-leg quantity, the stem of its three
        columns ``name_A, name_B, name_C``.
    unit : str
        SI unit of the column.
    description : str
        Meaning and sign (``docs/model.md``, section *Quantities and signs*).
    per_leg : bool
        One column per leg A, B, C.
    symbol : str
        The paper's symbol (matplotlib mathtext), for labels.
    friction : bool
        Written only when the robot has ``[friction]`` (after the 46 columns).
    load : bool
        Written only when the motion has a time-varying load (a trajectory's
        ``fx, fy, mz``; the last columns).
    """

    name: str
    unit: str
    description: str
    per_leg: bool
    symbol: str
    friction: bool = False
    load: bool = False

    def columns(self) -> tuple[str, ...]:
        """Its columns: ``(name,)``, or ``name_A, name_B, name_C``.

        >>> OUTPUT_QUANTITIES["f10"].columns()
        ('f10_A', 'f10_B', 'f10_C')
        """
        return tuple(f"{self.name}_{leg}" for leg in LEGS) if self.per_leg else (self.name,)


def _quantities(*items: OutputQuantity) -> dict[str, OutputQuantity]:
    return {item.name: item for item in items}


#: Every output quantity of ``results.csv``, in the order of its columns.
OUTPUT_QUANTITIES: dict[str, OutputQuantity] = _quantities(
    OutputQuantity("t", "s", "time", False, "t"),
    OutputQuantity("x", "m", "x of the platform centre G, fixed frame", False, "x"),
    OutputQuantity("y", "m", "y of the platform centre G, fixed frame", False, "y"),
    OutputQuantity("phi", "rad", "orientation of the platform", False, "\\varphi"),
    OutputQuantity("lambda10", "m", "actuator displacement", True, "\\lambda_{10}"),
    OutputQuantity("dlambda10", "m/s", "actuator velocity", True, "\\dot\\lambda_{10}"),
    OutputQuantity("ddlambda10", "m/s²", "actuator acceleration", True, "\\ddot\\lambda_{10}"),
    OutputQuantity("lambda32", "m", "slide of the platform along link 2", True, "\\lambda_{32}"),
    OutputQuantity("dlambda32", "m/s", "its rate", True, "\\dot\\lambda_{32}"),
    OutputQuantity("ddlambda32", "m/s²", "its second rate", True, "\\ddot\\lambda_{32}"),
    OutputQuantity(
        "f10", "N", "force of actuator i on its piston along +e_i, through P_i", True, "f_{10}"
    ),
    OutputQuantity("p10", "W", "input power of actuator i, f10·dlambda10", True, "p_{10}"),
    OutputQuantity(
        "f21y", "N", "force of piston i on link 2 at P_i, along n_i", True, "f_{21y}"
    ),
    OutputQuantity(
        "f21z", "N", "force of piston i on link 2 at P_i, along e_i", True, "f_{21z}"
    ),
    OutputQuantity(
        "n10", "N", "reaction of the base guide on piston i, along n_i", True, "n_{10}"
    ),
    OutputQuantity(
        "m10", "N·m", "moment of that reaction about z0, taken about P_i", True, "m_{10}"
    ),
    OutputQuantity(
        "n32", "N", "reaction of link 2 on the platform, along d⊥_i", True, "n_{32}"
    ),
    OutputQuantity(
        "m32", "N·m", "moment of that reaction about z0, taken about P_i", True, "m_{32}"
    ),
    OutputQuantity(
        "fric10", "N", "friction force of the guide on piston i, along e_i", True,
        "f_{10}^{fr}", friction=True,
    ),
    OutputQuantity(
        "fric21", "N·m", "friction moment of piston i on link 2 about z0", True,
        "m_{21}^{fr}", friction=True,
    ),
    OutputQuantity(
        "fric32", "N", "friction force of link 2 on the platform, along d_i", True,
        "f_{32}^{fr}", friction=True,
    ),
    OutputQuantity(
        "fx", "N", "time-varying force of the environment on the platform at G, along x0",
        False, "f_x", load=True,
    ),
    OutputQuantity(
        "fy", "N", "time-varying force of the environment on the platform at G, along y0",
        False, "f_y", load=True,
    ),
    OutputQuantity(
        "mz", "N·m", "time-varying moment of the environment on the platform about z0",
        False, "m_z", load=True,
    ),
)  # fmt: skip

#: Per-leg quantities of the 46 columns, in the contract's order.
PER_LEG_COLUMNS: tuple[str, ...] = tuple(
    q.name for q in OUTPUT_QUANTITIES.values() if q.per_leg and not q.friction
)

#: Every column of ``results.csv``, in order.
RESULT_COLUMNS: tuple[str, ...] = tuple(
    q.name for q in OUTPUT_QUANTITIES.values() if not q.per_leg and not q.load
) + tuple(f"{quantity}_{leg}" for leg in LEGS for quantity in PER_LEG_COLUMNS)


#: The 9 columns after the 46 when the robot has ``[friction]``, legs A, B, C in order.
FRICTION_COLUMNS: tuple[str, ...] = tuple(
    f"{q.name}_{leg}" for leg in LEGS for q in OUTPUT_QUANTITIES.values() if q.friction
)


#: The 3 last columns when the motion has a time-varying load (the trajectory's ``fx, fy, mz``).
LOAD_RESULT_COLUMNS: tuple[str, ...] = tuple(q.name for q in OUTPUT_QUANTITIES.values() if q.load)


def output_quantity(column: str) -> OutputQuantity:
    """The quantity of a ``results.csv`` column (``f10_A`` or ``f10``).

    >>> q = output_quantity("m32_B")
    >>> q.name, q.unit
    ('m32', 'N·m')
    """
    stem, _, leg = column.rpartition("_")
    if stem in OUTPUT_QUANTITIES and leg in LEGS and OUTPUT_QUANTITIES[stem].per_leg:
        return OUTPUT_QUANTITIES[stem]
    if column in OUTPUT_QUANTITIES:
        return OUTPUT_QUANTITIES[column]
    raise ParameterError(f"{column!r} is not a column of results.csv")


def result_columns(friction: bool, load: bool = False) -> tuple[str, ...]:
    """The columns of ``results.csv``: the 46, the 9 friction columns with ``friction``,
    then ``fx, fy, mz`` with a time-varying ``load`` (a trajectory's load columns).

    >>> len(result_columns(True)), result_columns(True)[46:49]
    (55, ('fric10_A', 'fric21_A', 'fric32_A'))
    >>> result_columns(False, load=True)[46:]
    ('fx', 'fy', 'mz')
    """
    return (
        RESULT_COLUMNS
        + (FRICTION_COLUMNS if friction else ())
        + (LOAD_RESULT_COLUMNS if load else ())
    )


def results_table(kin: Kinematics, dyn: InverseDynamics) -> dict[str, NDArray[np.float64]]:
    """Every column of ``results.csv`` as a named array ``(N,)`` (or ``()``), in order.

    >>> from prp3 import Robot, inverse_dynamics, paper_motion
    >>> table = results_table(*inverse_dynamics(Robot(), paper_motion("vertical", samples=4)))
    >>> len(table), list(table)[:6], list(table)[-1], table["f10_A"].shape
    (46, ['t', 'x', 'y', 'phi', 'lambda10_A', 'dlambda10_A'], 'm32_C', (4,))
    """
    motion, geo = kin.motion, kin.geometry
    per_leg: dict[str, FloatArray | None] = {
        "lambda10": geo.lambda10,
        "dlambda10": kin.dlambda10,
        "ddlambda10": kin.ddlambda10,
        "lambda32": geo.lambda32,
        "dlambda32": kin.dlambda32,
        "ddlambda32": kin.ddlambda32,
        "f10": dyn.f10,
        "p10": dyn.p10,
        "f21y": dyn.f21y,
        "f21z": dyn.f21z,
        "n10": dyn.n10,
        "m10": dyn.m10,
        "n32": dyn.n32,
        "m32": dyn.m32,
        "fric10": dyn.fric10,
        "fric21": dyn.fric21,
        "fric32": dyn.fric32,
    }
    single = {
        "t": motion.t,
        "x": motion.pose[..., 0],
        "y": motion.pose[..., 1],
        "phi": motion.pose[..., 2],
    }
    table: dict[str, NDArray[np.float64]] = {}
    for quantity in OUTPUT_QUANTITIES.values():
        if not quantity.per_leg and not quantity.load:
            table[quantity.name] = single[quantity.name]
    friction = all(per_leg[q.name] is not None for q in OUTPUT_QUANTITIES.values() if q.friction)
    for group in (False, True) if friction else (False,):
        for j, leg in enumerate(LEGS):
            for quantity in OUTPUT_QUANTITIES.values():
                values = per_leg.get(quantity.name)
                if quantity.per_leg and quantity.friction == group and values is not None:
                    table[f"{quantity.name}_{leg}"] = values[..., j]
    if motion.load is not None:  # the time-varying load of the motion, last
        for k, name in enumerate(LOAD_RESULT_COLUMNS):
            table[name] = motion.load[..., k]
    return table


# ---------------------------------------------------------------- forces table
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
    """

    path: Path
    forces: ActuatorForces
    first_pose: FloatArray | None
    first_rates: FloatArray | None
    planned_pose: FloatArray | None = None

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
    table = _read_table(
        Path(path), FORCE_COLUMNS, [*others, *FRICTION_COLUMNS, *LOAD_COLUMNS], "forces"
    )
    columns = table.columns
    loads = [name for name in LOAD_COLUMNS if name in columns]
    if loads and len(loads) != len(LOAD_COLUMNS):
        missing = [name for name in LOAD_COLUMNS if name not in columns]
        raise InputFileError(
            f"give all of the load columns {', '.join(LOAD_COLUMNS)} or none; "
            f"missing {', '.join(missing)}",
            file=path,
        )
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
        line = int(table.lines[error.sample]) if error.sample is not None else None
        raise error.located(file=path, line=line) from None
    if not extra:
        return ForceInput(Path(path), forces, None, None)
    planned = np.stack([columns["x"], columns["y"], columns["phi"]], axis=-1)
    rates = np.array([columns[f"dlambda10_{leg}"][0] for leg in LEGS])
    return ForceInput(Path(path), forces, planned[0].copy(), rates, planned)
