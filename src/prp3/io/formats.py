"""The file formats of prp3, in one place: CSV tables, ``TRAJ.csv``, forces, measurements.

* :func:`write_table_csv` / :func:`read_table_csv`: numeric CSV tables with a
  header row of column names, full-precision numbers (the shortest text that
  reads back to the same float: Arrow's CSV writer, or ``repr``), written
  atomically; read by ``numpy.loadtxt``, strictly (known columns, numbers only;
  every error names the file, the line and the column) and with bounds
  (:func:`prp3.files.read_text_lines`: size, line length, UTF-8; ``\n``,
  ``\r\n`` and old Mac ``\r`` line ends).
* ``TRAJ.csv`` of the data contract (``docs/model.md``; :func:`read_trajectory`,
  :func:`trajectory_table`): a platform motion, columns :data:`POSITION_COLUMNS`
  and optionally :data:`DERIVATIVE_COLUMNS`.
* ``results.csv``: written by :func:`write_table_csv` (or
  :func:`write_table_parquet`) from :func:`prp3.io.results.results_table`, whose
  module holds the registry of its columns.
* the forces table (:data:`FORCE_COLUMNS`, :func:`read_forces`): actuator
  force histories for ``prp3 forward``, or a whole ``results.csv``.

The files themselves (bounded reads, atomic and staged writes) are
:mod:`prp3.files`; its names are re-exported here.

>>> import tempfile, pathlib
>>> folder = pathlib.Path(tempfile.mkdtemp())
>>> write_table_csv(folder / "a.csv", {"t": np.array([0.5, 0.1]), "x": np.array([1.5, 2.25])})
>>> print((folder / "a.csv").read_text(), end="")
t,x
0.5,1.5
0.1,2.25
>>> read_table_csv(folder / "a.csv", required=("t", "x"))["x"].tolist()
[1.5, 2.25]
"""

from __future__ import annotations

import csv
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.analysis.force_histories import ActuatorForces
from prp3.errors import (
    InputFileError,
    OutputFileError,
    Prp3Error,
    SingularPoseError,
    TrajectoryError,
)
from prp3.files import (
    MAX_LINE_BYTES,
    atomic_path,
    atomic_writer,
    check_inputs_kept,
    check_output_directory,
    read_text_lines,
)
from prp3.io.results import FRICTION_COLUMNS, RESULT_COLUMNS
from prp3.model.motion import Motion, differentiate_positions, spline_derivatives
from prp3.path_validation import check_path
from prp3.staged_files import MANIFEST_NAME, StagedOutput, read_manifest, staged_output
from prp3.validation import LEGS

__all__ = [
    "DERIVATIVE_COLUMNS",
    "FORCE_COLUMNS",
    "LOAD_COLUMNS",
    "MANIFEST_NAME",
    "MEASURED_FORCE_COLUMNS",
    "POSITION_COLUMNS",
    "TRAJECTORY_COLUMNS",
    "ForceInput",
    "Measurements",
    "StagedOutput",
    "Trajectory",
    "atomic_path",
    "atomic_writer",
    "check_inputs_kept",
    "check_output_directory",
    "differentiate_positions",
    "format_float",
    "format_floats",
    "parquet_available",
    "read_forces",
    "read_manifest",
    "read_measurements",
    "read_table_csv",
    "read_trajectory",
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

#: Data lines read per ``numpy.loadtxt`` call by :func:`read_table_csv` (bounds the texts held).
_READ_BLOCK = 4096

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

    Every number is written as the shortest decimal text that reads back to
    the very same float.  With pyarrow installed, Arrow's CSV writer writes the
    float64 columns itself (its shortest round-trip conversion: the digits of
    ``repr``, laid out its own way, e.g. ``2``, ``0.00001``, ``1e+16``); else
    Python writes ``repr`` of each float (``2.0``, ``1e-05``, ``1e+16``).  Both
    read back bit for bit (:func:`format_floats` gives the texts).
    ``progress(rows_done, rows)`` is called after each block of rows when given.
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


def format_floats(values: ArrayLike) -> list[str]:
    """The texts :func:`write_table_csv` writes for the floats of a 1-d array.

    With pyarrow installed, Arrow's shortest round-trip conversion (the one its
    CSV writer uses), else ``repr``: the same decimal numbers, each reading
    back to its float.

    >>> values = [0.1, 2.0, -0.0, 1e-05, 5e-324, 1e300, 1234.5]
    >>> [float(text) for text in format_floats(values)] == values
    True
    """
    column = np.atleast_1d(np.asarray(values, dtype=np.float64))
    if column.ndim != 1:
        raise ValueError(f"format_floats takes a 1-d array, got shape {column.shape}")
    pa = _pyarrow()
    if column.size == 0 or pa is None:
        return [repr(value) for value in column.tolist()]
    return list(pa.compute.cast(pa.array(column, type=pa.float64()), pa.string()).to_pylist())


def _write_csv_arrow(
    path: Path,
    names: list[str],
    columns: list[FloatArray],
    progress: ProgressCallback | None,
) -> None:
    """The float64 columns written by Arrow's CSV writer, block by block, after the header."""
    pa = _pyarrow()
    rows = len(columns[0])
    schema = pa.schema([(name, pa.float64()) for name in names])
    options = pa.csv.WriteOptions(include_header=False, quoting_style="none")
    with pa.OSFile(str(path), "wb") as sink:
        sink.write((",".join(names) + "\n").encode("utf-8"))
        with pa.csv.CSVWriter(sink, schema, write_options=options) as writer:
            for start in range(0, rows, _ARROW_ROWS_PER_BLOCK):
                stop = min(start + _ARROW_ROWS_PER_BLOCK, rows)
                arrays = [pa.array(column[start:stop], type=pa.float64()) for column in columns]
                writer.write_batch(pa.record_batch(arrays, schema=schema))
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


def _is_blank(line: str) -> bool:
    """A line without a value: whitespace and commas only (a spreadsheet's empty row)."""
    return not line.strip(" \t\r\n,")


def _records(path: Path, lines: Iterator[str]) -> Iterator[tuple[int, str]]:
    """``(first line, text)`` of each non-blank CSV record of ``lines``.

    A record goes on over the next lines while a quoted cell is open (an odd
    number of ``"`` so far, as ``csv`` and ``numpy.loadtxt`` read quotes), so
    that its line is the file line where it starts; a record longer than a
    line may be (:data:`prp3.files.MAX_LINE_BYTES`) is refused.
    """
    record, start = "", 0
    for number, line in enumerate(lines, 1):
        if not record:
            start = number
        record += line
        if record.count('"') % 2:
            if len(record) > MAX_LINE_BYTES:
                raise InputFileError(
                    f"malformed CSV (a quoted cell still open after {MAX_LINE_BYTES} characters)",
                    file=path,
                    line=start,
                )
            continue
        if not _is_blank(record):
            yield start, record
        record = ""
    if record and not _is_blank(record):
        yield start, record


def _cells(line: str) -> list[str]:
    """The cells of one CSV record (quotes as ``numpy.loadtxt`` reads them: ``"``)."""
    return next(csv.reader([line.rstrip("\r\n")]), [])


def _parsed(lines: list[str], width: int, usecols: int | None = None) -> FloatArray | None:
    """``numpy.loadtxt`` of CSV lines, ``(len(lines), width)``; ``None`` if it refuses them."""
    try:
        values = np.loadtxt(
            lines, dtype=np.float64, delimiter=",", comments=None, quotechar='"',
            ndmin=2, usecols=usecols,
        )  # fmt: skip
    except ValueError:
        return None
    return values if usecols is not None or values.shape[1] == width else None


def _block(path: Path, header: list[str], lines: list[str], numbers: list[int]) -> FloatArray:
    """The numbers of a block of data lines, or the error naming the first bad cell.

    ``numpy.loadtxt`` reads the block; when it refuses it, the first line it
    refuses is found by bisection (each prefix read again) and the cell by
    reading that line's columns one at a time, so that what is refused is
    what ``numpy.loadtxt`` refuses.
    """
    width = len(header)
    values = _parsed(lines, width)
    if values is None:
        good, bad = 0, len(lines)  # lines[:good] are read, lines[:bad] are refused
        while bad - good > 1:
            middle = (good + bad) // 2
            good, bad = (
                (middle, bad) if _parsed(lines[:middle], width) is not None else (good, middle)
            )
        line, number = lines[bad - 1], numbers[bad - 1]
        cells = _cells(line)
        if len(cells) != width:
            raise InputFileError(
                f"expected {width} values, got {len(cells)}", file=path, line=number
            )
        c = next((c for c in range(width) if _parsed([line], width, usecols=c) is None), None)
        if c is None:  # each cell alone is a number, the row is not (quotes misplaced)
            raise InputFileError("malformed CSV row", file=path, line=number)
        raise InputFileError(
            f"column {header[c]!r}: not a number: {cells[c].strip()[:40]!r}",
            file=path,
            line=number,
            key=header[c],
        )
    finite = np.isfinite(values)
    if not finite.all():
        row, c = (int(k) for k in np.argwhere(~finite)[0])
        raise InputFileError(
            f"column {header[c]!r}: not a finite number: {_cells(lines[row])[c].strip()[:40]!r}",
            file=path,
            line=numbers[row],
            key=header[c],
        )
    return values


def _read_table(path: Path, required: Sequence[str], optional: Sequence[str], what: str) -> _Table:
    records = _records(path, read_text_lines(path, what))  # bounded; \n, \r\n or \r line ends
    first = next(records, None)
    if first is None:
        raise InputFileError(f"empty {what} file (expected a header row)", file=path)
    header_line, header = first[0], [cell.strip() for cell in _cells(first[1])]
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
    blocks: list[FloatArray] = []
    numbers: list[int] = []
    pending: list[str] = []
    for number, record in records:
        pending.append(record)
        numbers.append(number)
        if len(pending) == _READ_BLOCK:
            blocks.append(_block(path, header, pending, numbers[-len(pending) :]))
            pending = []
    if pending:
        blocks.append(_block(path, header, pending, numbers[-len(pending) :]))
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
