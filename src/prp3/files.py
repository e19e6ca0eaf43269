"""Files on disk: bounded input reads and atomic output files.

Input files are read with bounds (:func:`read_text_lines`, :func:`read_text`):
at most :data:`MAX_INPUT_BYTES` (or a smaller limit), lines of at most
:data:`MAX_LINE_BYTES`, UTF-8 text without NUL bytes; so a device such as
``/dev/zero`` or a huge file is refused early, naming the file.

Output files are written whole or not at all: the text goes to a temporary
file in the target directory, which is then renamed over the target
(``os.replace`` is atomic on POSIX and Windows).  A failure while writing (a
full disk) is an :class:`~prp3.errors.OutputFileError` naming the file.  A run
that writes several files stages them in a temporary directory and moves them
in place only when every one of them is complete
(:func:`prp3.staged_files.staged_output`).

>>> import tempfile, pathlib
>>> target = pathlib.Path(tempfile.mkdtemp()) / "note.txt"
>>> with atomic_writer(target) as stream:
...     _ = stream.write("done")
>>> read_text(target, "note")
'done'
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import IO

from prp3.errors import InputFileError, OutputFileError
from prp3.moved_paths import moved_attribute

__all__ = [
    "MAX_INPUT_BYTES",
    "MAX_LINE_BYTES",
    "atomic_path",
    "atomic_writer",
    "check_inputs_kept",
    "check_output_directory",
    "check_replaceable",
    "read_text",
    "read_text_lines",
]

#: Largest input file read (bytes): 2 GiB, more than the results.csv of 10⁶ samples.
MAX_INPUT_BYTES: int = 2 * 1024**3

#: Longest line of an input file (bytes); a CSV row of 46 full-precision numbers is ~1.2 KB.
MAX_LINE_BYTES: int = 64 * 1024


# ---------------------------------------------------------------- bounded input
def read_text_lines(path: str | Path, what: str, limit: int | None = None) -> Iterator[str]:
    """The lines of a UTF-8 text file (line ends kept, a BOM removed), read with bounds.

    A line ends at ``\n``, ``\r\n`` or a lone ``\r`` (old Mac files): Python's
    universal newlines (``open(..., newline="")``), the ends kept as they are.

    Raises
    ------
    InputFileError
        The file cannot be opened or read, is larger than ``limit`` bytes,
        has a line longer than :data:`MAX_LINE_BYTES`, contains NUL bytes
        (a binary file or a device such as ``/dev/zero``) or is not UTF-8
        (the fields name the file and the line).
    """
    path = Path(path)
    limit = MAX_INPUT_BYTES if limit is None else limit
    try:  # undecodable bytes kept as surrogates, to name the line they are on
        stream = open(path, encoding="utf-8", errors="surrogateescape", newline="")
    except OSError as error:
        raise InputFileError(
            f"cannot read {what} file ({error.strerror or error})", file=path
        ) from None
    with stream:
        try:  # a regular file over the bound is refused before a byte of it is read
            size = os.fstat(stream.fileno()).st_size if stream.seekable() else 0
        except OSError:
            size = 0
        if size > limit:
            raise InputFileError(
                f"{what} file is larger than {limit} bytes (the limit of prp3): {size} bytes",
                file=path,
            )
        total = 0
        number = 0
        while True:
            try:
                text = stream.readline(MAX_LINE_BYTES + 1)  # characters: at least as many bytes
            except OSError as error:
                raise InputFileError(
                    f"cannot read {what} file ({error.strerror or error})", file=path
                ) from None
            if not text:
                return
            number += 1
            raw = text.encode("utf-8", "surrogateescape")  # the bytes of the file
            total += len(raw)
            if "\0" in text:
                raise InputFileError(
                    f"{what} file contains NUL bytes: not a text file", file=path, line=number
                )
            if len(raw) > MAX_LINE_BYTES:
                raise InputFileError(
                    f"line longer than {MAX_LINE_BYTES} bytes in the {what} file",
                    file=path,
                    line=number,
                )
            if total > limit:
                raise InputFileError(
                    f"{what} file is larger than {limit} bytes (the limit of prp3)",
                    file=path,
                    line=number,
                )
            try:
                text.encode("utf-8")
            except UnicodeEncodeError:
                raise InputFileError(
                    f"{what} file is not UTF-8 text", file=path, line=number
                ) from None
            if number == 1 and text.startswith("\ufeff"):
                text = text[1:]
            yield text


def read_text(path: str | Path, what: str, limit: int | None = None) -> str:
    """The whole text of a UTF-8 file, read with the bounds of :func:`read_text_lines`."""
    return "".join(read_text_lines(path, what, limit))


# ---------------------------------------------------------------- atomic output
def _file_mode() -> int:
    """Permissions of a new file under the current umask (``mkstemp`` gives 0600)."""
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


def check_replaceable(path: Path) -> None:
    """Refuse a target that exists and is not a regular file (a rename would replace it).

    Renaming a finished file over ``/dev/null``, a named pipe or a directory
    would destroy it (or fail half-way through a group of files); symbolic
    links are followed for the test.

    Raises
    ------
    OutputFileError
        Naming ``path``: it exists and is a directory or not a regular file,
        or it cannot be inspected (a name too long for the file system).
    """
    try:
        regular = not path.exists() or path.is_file()
    except OSError as error:  # e.g. a name too long for the file system
        raise OutputFileError(f"cannot write ({error.strerror})", file=path) from None
    if not regular:
        kind = "a directory" if path.is_dir() else "not a regular file"
        raise OutputFileError(f"cannot write: it exists and is {kind}", file=path)


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
    with (
        atomic_path(path) as temporary,
        open(temporary, mode, encoding="utf-8", newline="") as stream,
    ):
        yield stream


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
    check_replaceable(path)
    try:
        handle, temporary = tempfile.mkstemp(
            prefix=f".{path.stem}.", suffix=f".tmp{path.suffix}", dir=path.parent
        )
    except OSError as error:
        raise OutputFileError(f"cannot write ({error.strerror})", file=path) from None
    os.close(handle)
    try:
        os.chmod(temporary, _file_mode())
        yield Path(temporary)
        os.replace(temporary, path)
    except OSError as error:  # e.g. a full disk: name the file
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        raise OutputFileError(f"cannot write ({error.strerror or error})", file=path) from None
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        raise


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
            f"cannot create output directory ({error.strerror})", file=directory
        ) from None
    if not existing.is_dir():
        raise OutputFileError(
            f"cannot create output directory ({existing} is not a directory)", file=directory
        )
    if not os.access(existing, os.W_OK | os.X_OK):
        raise OutputFileError(
            f"cannot write output directory ({existing} is not writable)", file=directory
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
                        "the output would replace this input file; choose another output directory",
                        file=target,
                    )


def __getattr__(name: str) -> object:
    """The names this module had in prp3 0.1, now elsewhere (a DeprecationWarning names where)."""
    return moved_attribute(__name__, name)
