"""Files: atomic writes, strict numeric CSV tables and trajectory files.

Output files are written whole or not at all: the text goes to a temporary
file in the target directory, which is then renamed over the target
(``os.replace`` is atomic on POSIX and Windows).  A run that writes several
files stages them in a temporary directory and moves them in place only when
every one of them is complete (:func:`staged_output`).  CSV input is read
strictly: a header row of known column names, then numbers only; every error
names the file, the line and the column.  :func:`read_trajectory` reads the
``TRAJ.csv`` of the command line's data contract (``docs/model.md``).

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

import contextlib
import csv
import io
import json
import math
import os
import shutil
import stat
import tempfile
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .errors import InputFileError, OutputFileError, TrajectoryError
from .motion import Motion

__all__ = [
    "DERIVATIVE_COLUMNS",
    "FORCE_COLUMNS",
    "LOAD_COLUMNS",
    "MANIFEST_NAME",
    "POSITION_COLUMNS",
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
    "read_manifest",
    "read_measurements",
    "read_table_csv",
    "read_trajectory",
    "staged_output",
    "write_table_csv",
    "write_table_parquet",
]

#: Columns of a trajectory file that are always required (s, m, m, rad).
POSITION_COLUMNS: tuple[str, ...] = ("t", "x", "y", "phi")

#: Optional derivative columns of a trajectory file: all six or none.
DERIVATIVE_COLUMNS: tuple[str, ...] = ("dx", "dy", "dphi", "ddx", "ddy", "ddphi")

#: Optional load columns of a trajectory file (a wrench on the platform): all three or none.
LOAD_COLUMNS: tuple[str, ...] = ("fx", "fy", "mz")

#: Rows written per block by :func:`write_table_csv` (and per progress report).
_ROWS_PER_BLOCK = 20_000

#: Rows per block when Arrow makes the text (bounds the memory of the texts).
_ARROW_ROWS_PER_BLOCK = 100_000

ProgressCallback = Callable[[int, int], None]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


def format_float(value: float) -> str:
    """Format a float with full precision: ``repr``, the shortest text that reads back exactly.

    >>> format_float(0.1), format_float(2.0), format_float(-1e-20)
    ('0.1', '2.0', '-1e-20')
    """
    return repr(float(value))


def _file_mode() -> int:
    """Permissions of a new file under the current umask (``mkstemp`` gives 0600)."""
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


def _check_replaceable(path: Path) -> None:
    """Refuse a target that exists and is not a regular file (a rename would replace it).

    Renaming a finished file over ``/dev/null``, a named pipe or a directory
    would destroy it (or fail half-way through a group of files); symbolic
    links are followed for the test.
    """
    try:
        regular = not path.exists() or path.is_file()
    except OSError as error:  # e.g. a name too long for the file system
        raise OutputFileError(f"{path}: cannot write ({error.strerror})") from None
    if not regular:
        kind = "a directory" if path.is_dir() else "not a regular file"
        raise OutputFileError(f"{path}: cannot write: it exists and is {kind}")


@contextlib.contextmanager
def atomic_writer(path: str | Path, mode: str = "w") -> Iterator[IO[str]]:
    """Open ``path`` for writing so that it appears whole or not at all.

    The content goes to a temporary file beside ``path``; on success it is
    renamed over ``path``, on any exception it is deleted and ``path`` is left
    untouched.  The directory must exist.

    Raises
    ------
    OutputFileError
        If the directory does not exist or is not writable, or ``path`` exists
        and is not a regular file (a directory, a device, a pipe), which a
        rename would replace (names the path).
    """
    path = Path(path)
    _check_replaceable(path)
    try:
        handle, temporary = tempfile.mkstemp(
            prefix=f".{path.name}.", suffix=".tmp", dir=path.parent
        )
    except OSError as error:
        raise OutputFileError(f"{path}: cannot write ({error.strerror})") from None
    try:
        os.chmod(temporary, _file_mode())
        with os.fdopen(handle, mode, encoding="utf-8", newline="") as stream:
            yield stream
        os.replace(temporary, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        raise


@contextlib.contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """Give a temporary path beside ``path`` to write to; rename it over ``path`` on success.

    For writers that want a file name rather than a stream (``Figure.savefig``,
    an animation writer).  The temporary name ends with ``path``'s suffix so
    that writers which infer the format from it still work.  On any exception
    the temporary file is deleted and ``path`` is left untouched.

    Raises
    ------
    OutputFileError
        If the directory does not exist or is not writable (names the path).

    >>> import tempfile, pathlib
    >>> target = pathlib.Path(tempfile.mkdtemp()) / "note.txt"
    >>> with atomic_path(target) as temporary:
    ...     _ = temporary.write_text("done")
    >>> target.read_text(), sorted(p.name for p in target.parent.iterdir())
    ('done', ['note.txt'])
    """
    path = Path(path)
    _check_replaceable(path)
    try:
        handle, temporary = tempfile.mkstemp(
            prefix=f".{path.stem}.", suffix=f".tmp{path.suffix}", dir=path.parent
        )
    except OSError as error:
        raise OutputFileError(f"{path}: cannot write ({error.strerror})") from None
    os.close(handle)
    try:
        os.chmod(temporary, _file_mode())
        yield Path(temporary)
        os.replace(temporary, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        raise


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
            f"{path}: writing Parquet needs pyarrow, which is not installed: "
            "pip install 'prp3[parquet]', or write CSV"
        )
    import pyarrow.parquet as pq

    arrays = [pa.array(np.atleast_1d(np.asarray(table[name], dtype=np.float64))) for name in table]
    data = pa.Table.from_arrays(arrays, names=list(table))
    with atomic_path(path) as temporary:
        pq.write_table(data, str(temporary))


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


def _read_table(path: Path, required: Sequence[str], optional: Sequence[str], what: str) -> _Table:
    try:
        text = path.read_text(encoding="utf-8-sig")
    except OSError as error:
        raise InputFileError(f"{path}: cannot read {what} file ({error.strerror})") from None
    except UnicodeDecodeError:
        raise InputFileError(f"{path}: {what} file is not UTF-8 text") from None
    rows = [row for row in csv.reader(io.StringIO(text))]
    numbered = [(n + 1, row) for n, row in enumerate(rows) if any(cell.strip() for cell in row)]
    if not numbered:
        raise InputFileError(f"{path}: empty {what} file (expected a header row)")
    header_line, header = numbered[0]
    header = [cell.strip() for cell in header]
    allowed = list(required) + list(optional)
    for name in header:
        if name not in allowed:
            raise InputFileError(
                f"{path}:{header_line}: unknown column {name!r} "
                f"(expected {', '.join(required)}"
                + (f", optionally {', '.join(optional)}" if optional else "")
                + ")"
            )
    seen: set[str] = set()
    for name in header:
        if name in seen:
            raise InputFileError(f"{path}:{header_line}: duplicate column {name!r}")
        seen.add(name)
    missing = [name for name in required if name not in seen]
    if missing:
        raise InputFileError(f"{path}:{header_line}: missing column(s) {', '.join(missing)}")
    data = numbered[1:]
    if not data:
        raise InputFileError(f"{path}: no data rows after the header")
    values = np.empty((len(data), len(header)))
    for r, (line, row) in enumerate(data):
        if len(row) != len(header):
            raise InputFileError(f"{path}:{line}: expected {len(header)} values, got {len(row)}")
        for c, cell in enumerate(row):
            try:
                if "_" in cell or not cell.isascii():  # float() takes '1_0' and other digits
                    raise ValueError(cell)
                number = float(cell)
            except ValueError:
                raise InputFileError(
                    f"{path}:{line}: column {header[c]!r}: not a number: {cell.strip()!r}"
                ) from None
            if not math.isfinite(number):
                raise InputFileError(
                    f"{path}:{line}: column {header[c]!r}: not a finite number: {cell.strip()!r}"
                )
            values[r, c] = number
    return _Table(
        columns={name: values[:, c].copy() for c, name in enumerate(header)},
        lines=np.array([line for line, _ in data], dtype=np.int64),
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


def differentiate_positions(t: FloatArray, pose: FloatArray) -> tuple[FloatArray, FloatArray, int]:
    """Velocities and accelerations of sampled poses by an interpolating spline.

    Each of ``x, y, φ`` is interpolated by a spline of degree 5 (quintic) with
    the not-a-knot end conditions through all the samples
    (``scipy.interpolate.make_interp_spline(t, q, k=5)``); the velocity and
    acceleration are its first and second derivatives at the sample times.
    With fewer than 6 samples the degree drops to 3 (4 or 5 samples) or 1
    (2 or 3 samples; zero acceleration).  For a smooth motion sampled every
    millisecond the derivatives are accurate to about 1e-9 relative away from
    the ends; within a few samples of the ends the error is larger.

    Parameters
    ----------
    t : ndarray, shape (N,)
        Strictly increasing times (s), ``N >= 2``.
    pose : ndarray, shape (N, 3)
        ``(x, y, φ)`` (m, m, rad).

    Returns
    -------
    velocity, acceleration : ndarray, shape (N, 3)
        ``(ẋ, ẏ, φ̇)`` (m/s, rad/s) and ``(ẍ, ÿ, φ̈)`` (m/s², rad/s²).
    degree : int
        The spline degree used.

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 11)
    >>> pose = np.stack([t**2, 3.0 * t, np.zeros_like(t)], axis=-1)
    >>> velocity, acceleration, degree = differentiate_positions(t, pose)
    >>> degree, velocity[5].round(12).tolist(), acceleration[5].round(9).tolist()
    (5, [1.0, 3.0, 0.0], [2.0, 0.0, 0.0])
    """
    from scipy.interpolate import make_interp_spline

    samples = len(t)
    degree = 5 if samples >= 6 else 3 if samples >= 4 else 1
    spline = make_interp_spline(t, pose, k=degree, axis=0)
    velocity = np.asarray(spline(t, 1), dtype=np.float64)
    acceleration = np.asarray(spline(t, 2), dtype=np.float64)
    return velocity, acceleration, degree


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
            f"{path}:{table.header_line}: give all of the load columns "
            f"{', '.join(LOAD_COLUMNS)} or none; missing {', '.join(missing)}"
        )
    given = [name for name in DERIVATIVE_COLUMNS if name in columns]
    if given and len(given) != len(DERIVATIVE_COLUMNS):
        missing = [name for name in DERIVATIVE_COLUMNS if name not in columns]
        raise InputFileError(
            f"{path}:{table.header_line}: give all of the derivative columns "
            f"{', '.join(DERIVATIVE_COLUMNS)} or none; missing {', '.join(missing)}"
        )
    t = columns["t"]
    lines = table.lines
    if len(t) < 2:
        raise TrajectoryError(
            f"{path}: a trajectory needs at least 2 samples, got {len(t)} (line {int(lines[0])})"
        )
    steps = np.diff(t)
    if (steps <= 0.0).any():
        k = int(np.argmax(steps <= 0.0)) + 1
        raise TrajectoryError(
            f"{path}:{int(lines[k])}: time must increase: t = {float(t[k])!r} follows "
            f"t = {float(t[k - 1])!r} on line {int(lines[k - 1])}"
        )
    pose = np.stack([columns[name] for name in ("x", "y", "phi")], axis=-1)
    note: str | None = None
    if given:
        velocity = np.stack([columns[name] for name in DERIVATIVE_COLUMNS[:3]], axis=-1)
        acceleration = np.stack([columns[name] for name in DERIVATIVE_COLUMNS[3:]], axis=-1)
    else:
        with np.errstate(all="ignore"):  # an overflow is reported below, naming the line
            velocity, acceleration, degree = differentiate_positions(t, pose)
        for name, values in (("velocity", velocity), ("acceleration", acceleration)):
            bad = ~np.isfinite(values)
            if bad.any():
                k, axis = np.argwhere(bad)[0].tolist()
                raise TrajectoryError(
                    f"{path}:{int(lines[k])}: the {name} of {POSITION_COLUMNS[1 + axis]} "
                    f"computed from the positions is not finite ({float(values[k, axis])!r}): "
                    "positions too large or time steps too small; give the derivative columns"
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
    except TrajectoryError as error:
        raise TrajectoryError(f"{path}: {error}") from None
    return Trajectory(path=path, motion=motion, lines=lines, note=note)


#: Measured actuator forces of a measurement file (N).
FORCE_COLUMNS: tuple[str, ...] = ("f10_A", "f10_B", "f10_C")


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
    table = _read_table(path, POSITION_COLUMNS + FORCE_COLUMNS, DERIVATIVE_COLUMNS, "measurement")
    f10 = np.stack([table.columns[name] for name in FORCE_COLUMNS], axis=-1)
    return Measurements(trajectory=_trajectory(path, table), f10=f10)


# ---------------------------------------------------------------- output folders
def check_output_directory(directory: str | Path) -> None:
    """Refuse early an output directory that cannot be created or written to.

    The directory itself may be missing (it will be created with its
    parents); its nearest existing ancestor must be a writable directory.

    Raises
    ------
    OutputFileError
        Naming the directory and the reason.
    """
    directory = Path(directory)
    existing = directory
    try:
        while not existing.exists() and existing != existing.parent:
            existing = existing.parent
    except OSError as error:  # e.g. a name too long for the file system
        raise OutputFileError(
            f"{directory}: cannot create output directory ({error.strerror})"
        ) from None
    if not existing.is_dir():
        raise OutputFileError(
            f"{directory}: cannot create output directory ({existing} is not a directory)"
        )
    if not os.access(existing, os.W_OK | os.X_OK):
        raise OutputFileError(
            f"{directory}: cannot write output directory ({existing} is not writable)"
        )


def check_inputs_kept(
    directory: str | Path, names: Sequence[str], inputs: Sequence[str | Path | None]
) -> None:
    """Refuse a run whose output file ``directory/name`` is one of its input files.

    ``prp3 forward --forces out/results.csv --output out`` would otherwise
    replace the forces it read with its own results.

    Raises
    ------
    OutputFileError
        Naming the output file and the option it was read by.

    >>> import tempfile, pathlib
    >>> out = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (out / "results.csv").write_text("t")
    >>> try:
    ...     check_inputs_kept(out, ["results.csv"], [out / "results.csv"])
    ... except OutputFileError as error:
    ...     print(str(error).split(": ", 1)[1])
    the output would replace this input file; choose another output directory
    """
    for name in names:
        target = Path(directory) / name
        for given in inputs:
            with contextlib.suppress(OSError):  # a missing file is not the same file
                if given is not None and os.path.samefile(target, given):
                    raise OutputFileError(
                        f"{target}: the output would replace this input file; "
                        "choose another output directory"
                    )


#: The manifest a run leaves in its output directory: the files it wrote there.
MANIFEST_NAME: str = ".prp3-manifest.json"

#: Largest manifest read back (a longer file is not one prp3 wrote: it is ignored).
_MANIFEST_MAX_BYTES: int = 1 << 20


@dataclass
class StagedOutput:
    """Files of one run, written into a staging folder first (see :func:`staged_output`).

    Attributes
    ----------
    directory : Path
        The output directory the files end up in.
    staging : Path
        The temporary folder inside ``directory`` where they are written.
    names : list of str
        The file names asked for so far, in order.
    written : list of Path
        The final paths, filled in when the run succeeded.
    removed : list of Path
        Files an earlier run wrote into ``directory`` (listed in its manifest,
        unchanged since) that this run did not write again, and removed.
    kept : list of Path
        Files of an earlier run's manifest that were changed or replaced since
        (so they are not prp3's any more) and were left alone.
    """

    directory: Path
    staging: Path
    names: list[str] = field(default_factory=list)
    written: list[Path] = field(default_factory=list)
    removed: list[Path] = field(default_factory=list)
    kept: list[Path] = field(default_factory=list)

    def path(self, name: str) -> Path:
        """The staging path to write the output file ``name`` to."""
        if name in self.names or Path(name).name != name or name == MANIFEST_NAME:
            raise ValueError(f"output file name {name!r} is repeated or not a plain name")
        self.names.append(name)
        return self.staging / name


@contextlib.contextmanager
def staged_output(directory: str | Path) -> Iterator[StagedOutput]:
    """Write several output files so that they appear together or not at all.

    Creates ``directory`` (and its parents) when missing, and a temporary
    staging folder inside it.  Files are written to
    ``staged.path(name)``; when the block ends without an exception they are
    renamed into ``directory`` (replacing older files of the same name) and
    :attr:`StagedOutput.written` lists them.  On an exception the staging
    folder is deleted, folders this call created are removed again, and no
    file in ``directory`` changes.

    The directory keeps a manifest, :data:`MANIFEST_NAME`: the names, sizes
    and modification times of the files the last run wrote there.  A new run
    removes the files of the earlier manifest that it does not write again —
    only those still exactly as prp3 wrote them (same size and modification
    time, regular files); a file the user changed, replaced or added is never
    touched — and writes its own manifest.  :attr:`StagedOutput.removed`
    lists what was removed, :attr:`StagedOutput.kept` what was left alone.

    Raises
    ------
    OutputFileError
        If the directory cannot be created or written to (names it), or a file
        cannot be moved in (an older file of the same name is then restored,
        and nothing in ``directory`` changes).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "run"
    >>> with staged_output(out) as staged:
    ...     _ = staged.path("a.txt").write_text("a")
    >>> [path.name for path in staged.written], sorted(p.name for p in out.iterdir())
    (['a.txt'], ['.prp3-manifest.json', 'a.txt'])
    >>> with staged_output(out) as staged:          # a run that writes b.txt only
    ...     _ = staged.path("b.txt").write_text("b")
    >>> [path.name for path in staged.removed], sorted(p.name for p in out.iterdir())
    (['a.txt'], ['.prp3-manifest.json', 'b.txt'])
    """
    directory = Path(directory)
    created: list[Path] = []
    missing = directory
    try:
        while not missing.exists() and missing != missing.parent:
            created.append(missing)
            missing = missing.parent
        directory.mkdir(parents=True, exist_ok=True)
        staging = Path(tempfile.mkdtemp(prefix=".prp3-", suffix=".tmp", dir=directory))
    except OSError as error:
        _remove_empty(created)
        reason = error.strerror or type(error).__name__
        raise OutputFileError(f"{directory}: cannot write output directory ({reason})") from None
    staged = StagedOutput(directory=directory, staging=staging)
    try:
        yield staged
        _move_in(staged)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        _remove_empty(created)
        raise
    shutil.rmtree(staging, ignore_errors=True)


def _file_stamp(path: Path) -> dict[str, int] | None:
    """Size and modification time (ns) of a regular file (not a link); ``None`` otherwise."""
    try:
        info = os.lstat(path)
    except OSError:
        return None
    if not stat.S_ISREG(info.st_mode):
        return None
    return {"size": int(info.st_size), "mtime_ns": int(info.st_mtime_ns)}


def read_manifest(directory: str | Path) -> dict[str, dict[str, int]]:
    """The files the last run wrote into ``directory``: ``name -> {size, mtime_ns}``.

    An absent, unreadable, oversized or malformed manifest, and any entry that
    is not a plain file name with integer stamps, count as nothing written:
    prp3 then removes nothing.
    """
    path = Path(directory) / MANIFEST_NAME
    try:
        with open(path, "rb") as stream:
            data = stream.read(_MANIFEST_MAX_BYTES + 1)
        if len(data) > _MANIFEST_MAX_BYTES:
            return {}
        manifest = json.loads(data.decode("utf-8"))
    except (OSError, ValueError, RecursionError):
        return {}
    files = manifest.get("files") if isinstance(manifest, dict) else None
    if not isinstance(files, dict):
        return {}
    entries: dict[str, dict[str, int]] = {}
    for name, stamp in files.items():
        plain = isinstance(name, str) and name not in ("", ".", "..") and Path(name).name == name
        if (
            plain
            and name != MANIFEST_NAME
            and isinstance(stamp, dict)
            and all(type(stamp.get(key)) is int for key in ("size", "mtime_ns"))
        ):
            entries[name] = {"size": stamp["size"], "mtime_ns": stamp["mtime_ns"]}
    return entries


def _move_in(staged: StagedOutput) -> None:
    """Rename the staged files into the output directory: all of them, or none.

    Every target is checked first (an existing directory or special file of
    the same name is refused before anything moves).  Older files are
    hard-linked into the staging folder before they are replaced, so that a
    failure half-way (or an interrupt) puts them back and removes the new
    files already moved in.  The files of the earlier manifest that this run
    does not write again (and that are unchanged) are moved into the staging
    folder too, and the new manifest is moved in last.
    """
    names = [name for name in staged.names if (staged.staging / name).exists()]
    for name in names:
        _check_replaceable(staged.directory / name)
    stale: list[str] = []
    for name, stamp in read_manifest(staged.directory).items():
        if name in names:
            continue
        now = _file_stamp(staged.directory / name)
        if now == stamp:
            stale.append(name)
        elif now is not None or os.path.lexists(staged.directory / name):
            staged.kept.append(staged.directory / name)
    stamps = {name: _file_stamp(staged.staging / name) for name in names}
    manifest = {
        "about": "files prp3 wrote into this folder in its last run; the next run removes "
        "those it does not write again (when unchanged), nothing else",
        "files": {name: stamp for name, stamp in stamps.items() if stamp is not None},
    }
    try:
        (staged.staging / MANIFEST_NAME).write_text(json.dumps(manifest, indent=1) + "\n")
    except OSError as error:
        raise OutputFileError(
            f"{staged.directory / MANIFEST_NAME}: cannot write ({error.strerror})"
        ) from None
    previous = staged.staging / ".previous"
    previous.mkdir()
    old = staged.staging / ".removed"
    old.mkdir()
    backups: dict[str, Path] = {}
    moved: list[str] = []
    taken: list[str] = []
    target = staged.directory
    try:
        for name in [*names, MANIFEST_NAME]:
            target = staged.directory / name
            if os.path.lexists(target):
                with contextlib.suppress(OSError):  # no hard links here: no way back
                    os.link(target, previous / name, follow_symlinks=False)
                    backups[name] = previous / name
            os.replace(staged.staging / name, target)
            moved.append(name)
        for name in stale:
            target = staged.directory / name
            os.replace(target, old / name)
            taken.append(name)
    except BaseException as error:
        for name in reversed(taken):
            with contextlib.suppress(OSError):
                os.replace(old / name, staged.directory / name)
        for name in reversed(moved):
            with contextlib.suppress(OSError):
                if name in backups:
                    os.replace(backups[name], staged.directory / name)
                else:
                    os.unlink(staged.directory / name)
        if isinstance(error, OSError):
            raise OutputFileError(f"{target}: cannot write ({error.strerror})") from None
        raise
    staged.written.extend(staged.directory / name for name in names)
    staged.removed.extend(staged.directory / name for name in stale)


def _remove_empty(folders: Sequence[Path]) -> None:
    """Remove the folders (deepest first) that are empty; ignore the others."""
    for folder in folders:
        with contextlib.suppress(OSError):
            folder.rmdir()
