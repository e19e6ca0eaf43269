"""Numeric tables on disk: CSV (written and read strictly) and Parquet.

* :func:`write_table_csv`: named columns of floats as CSV with a header row,
  every number the shortest text that reads back to the same float (Arrow's
  CSV writer, or ``repr``: :func:`format_floats`), written atomically
  (:func:`prp3.files.atomic_path`, :func:`prp3.files.atomic_writer`).
* :func:`read_table_csv`, :func:`read_table`: a numeric CSV table read by
  ``numpy.loadtxt`` in blocks, strictly (known columns, numbers only; every
  error names the file, the line and the column) and with bounds
  (:func:`prp3.files.read_text_lines`: size, line length, UTF-8; ``\n``,
  ``\r\n`` and old Mac ``\r`` line ends).
* :func:`write_table_parquet`: the same columns as float64 Parquet columns
  (pyarrow, the optional extra ``parquet``; :func:`parquet_available`).

The tables of prp3's files are built on them: ``TRAJ.csv``
(:mod:`prp3.io.trajectory`), measurement files (:mod:`prp3.io.measurements`),
the forces table (:mod:`prp3.io.forces`) and ``results.csv``
(:func:`prp3.io.results.results_table`).

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

from prp3.errors import InputFileError, OutputFileError
from prp3.files import MAX_LINE_BYTES, atomic_path, atomic_writer, read_text_lines

__all__ = [
    "Table",
    "format_float",
    "format_floats",
    "parquet_available",
    "read_table",
    "read_table_csv",
    "write_table_csv",
    "write_table_parquet",
]

#: Rows written per block by :func:`write_table_csv` (and per progress report).
ROWS_PER_BLOCK = 20_000

#: Rows per block when Arrow makes the text (bounds the memory of the texts).
ARROW_ROWS_PER_BLOCK = 100_000

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
        for start in range(0, rows if columns else 0, ROWS_PER_BLOCK):
            stop = min(start + ROWS_PER_BLOCK, rows)
            block = np.column_stack([column[start:stop] for column in columns]).tolist()
            stream.write("".join(row_format % tuple(row) for row in block))
            if progress is not None:
                progress(stop, rows)


def _pyarrow() -> Any:
    """The ``pyarrow`` module with its CSV writer, or ``None`` when it is not installed (an optional extra).

    Not ``pyarrow.compute`` (half of pyarrow's import time), which only
    :func:`format_floats` uses.
    """
    try:
        import pyarrow
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
    import pyarrow.compute

    return list(pyarrow.compute.cast(pa.array(column, type=pa.float64()), pa.string()).to_pylist())


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
            for start in range(0, rows, ARROW_ROWS_PER_BLOCK):
                stop = min(start + ARROW_ROWS_PER_BLOCK, rows)
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
    return read_table(Path(path), required, optional, what).columns


@dataclass(frozen=True)
class Table:
    """A numeric CSV table read by :func:`read_table`.

    Attributes
    ----------
    columns : dict of str to ndarray, shape (N,)
        The columns by name, in the file's order.
    lines : ndarray of int, shape (N,)
        The line number of each data row in the file (1-based, the header counted).
    header_line : int
        The line number of the header row.
    """

    columns: dict[str, FloatArray]
    lines: IntArray
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


def read_table(path: Path, required: Sequence[str], optional: Sequence[str], what: str) -> Table:
    """The table :func:`read_table_csv` reads, with the line of each row and of the header.

    The same parameters and refusals as :func:`read_table_csv`; the lines let a
    reader built on it name the line of a sample it refuses.
    """
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
    return Table(
        columns={name: values[:, c].copy() for c, name in enumerate(header)},
        lines=np.array(numbers, dtype=np.int64),
        header_line=header_line,
    )
