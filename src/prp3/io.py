"""Files: atomic writes and strict numeric CSV tables.

Output files are written whole or not at all: the text goes to a temporary
file in the target directory, which is then renamed over the target
(``os.replace`` is atomic on POSIX and Windows).  CSV input is read strictly:
a header row of known column names, then numbers only; every error names the
file, the line and the column.

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
import math
import os
import tempfile
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import IO

import numpy as np
from numpy.typing import NDArray

from .errors import InputFileError

__all__ = ["atomic_writer", "format_float", "read_table_csv", "write_table_csv"]

FloatArray = NDArray[np.float64]


def format_float(value: float) -> str:
    """Format a float with full precision: ``repr``, the shortest text that reads back exactly.

    >>> format_float(0.1), format_float(2.0), format_float(-1e-20)
    ('0.1', '2.0', '-1e-20')
    """
    return repr(float(value))


@contextlib.contextmanager
def atomic_writer(path: str | Path, mode: str = "w") -> Iterator[IO[str]]:
    """Open ``path`` for writing so that it appears whole or not at all.

    The content goes to a temporary file beside ``path``; on success it is
    renamed over ``path``, on any exception it is deleted and ``path`` is left
    untouched.  The directory must exist.

    Raises
    ------
    InputFileError
        If the directory does not exist or is not writable (names the path).
    """
    path = Path(path)
    try:
        handle, temporary = tempfile.mkstemp(
            prefix=f".{path.name}.", suffix=".tmp", dir=path.parent
        )
    except OSError as error:
        raise InputFileError(f"{path}: cannot write ({error.strerror})") from None
    try:
        with os.fdopen(handle, mode, encoding="utf-8", newline="") as stream:
            yield stream
        os.replace(temporary, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        raise


def write_table_csv(path: str | Path, table: Mapping[str, FloatArray]) -> None:
    """Write named columns ``(N,)`` (or scalars) as CSV, full precision, atomically."""
    names = list(table)
    columns = [np.atleast_1d(np.asarray(table[name], dtype=np.float64)) for name in names]
    rows = len(columns[0]) if columns else 0
    buffer = io.StringIO()
    buffer.write(",".join(names) + "\n")
    if columns:
        matrix = np.column_stack(columns)
        for row in range(rows):
            buffer.write(",".join(format_float(v) for v in matrix[row].tolist()) + "\n")
    with atomic_writer(path) as stream:
        stream.write(buffer.getvalue())


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
    path = Path(path)
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
    return {name: values[:, c].copy() for c, name in enumerate(header)}
