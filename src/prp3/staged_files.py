"""Staged groups of output files with a manifest: a run's files appear together or not at all.

A run that writes several files stages them in a temporary folder inside the
output directory and moves them in only when every one of them is complete
(:func:`staged_output`).  The directory keeps a manifest
(:data:`MANIFEST_NAME`) with one record per command — its files, the prp3
version, the command line and the SHA-256 of its inputs — so that a run
removes only the stale files of its own command.  The single files are
written by :mod:`prp3.files`.
"""

from __future__ import annotations

import contextlib
import datetime
import hashlib
import json
import os
import shutil
import stat
import tempfile
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from prp3.errors import OutputFileError
from prp3.files import check_replaceable

__all__ = [
    "LIBRARY_COMMAND",
    "MANIFEST_NAME",
    "StagedOutput",
    "file_digest",
    "read_manifest",
    "read_manifest_commands",
    "staged_output",
]


#: The manifest of an output directory: per command, the files its last run wrote there,
#: the prp3 version, the command line and the SHA-256 of every input file.
MANIFEST_NAME: str = ".prp3-manifest.json"

#: Largest manifest read back (a longer file is not one prp3 wrote: it is ignored).
_MANIFEST_MAX_BYTES: int = 1 << 20

#: The key of the runs of :func:`staged_output` called without a command (from Python).
LIBRARY_COMMAND: str = "library"


def file_digest(path: str | Path) -> str:
    """The SHA-256 of a file's bytes, in hex (read in blocks of 1 MiB).

    >>> import tempfile, pathlib
    >>> note = pathlib.Path(tempfile.mkdtemp()) / "note.txt"
    >>> _ = note.write_bytes(b"abc")
    >>> file_digest(note)[:16]
    'ba7816bf8f01cfea'

    Raises
    ------
    OSError
        The file cannot be read.
    """
    digest = hashlib.sha256()
    with open(path, "rb") as stream:
        for block in iter(lambda: stream.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _input_record(path: str | Path) -> dict[str, Any]:
    """What the manifest says of an input file: its path, size and SHA-256 (or why not)."""
    record: dict[str, Any] = {"path": os.fspath(path)}
    try:
        info = os.stat(path)
        if not stat.S_ISREG(info.st_mode):  # a pipe read already: its bytes are gone
            record["sha256"] = None
            record["unreadable"] = "not a regular file"
            return record
        record["size"] = info.st_size
        record["sha256"] = file_digest(path)
    except OSError as error:
        record["sha256"] = None
        record["unreadable"] = error.strerror or type(error).__name__
    return record


@dataclass
class StagedOutput:
    """Files of one run, written into a staging folder first (see :func:`staged_output`).

    Attributes
    ----------
    directory : Path
        The output directory the files end up in.
    staging : Path
        The temporary folder inside ``directory`` where they are written.
    command : str
        The command whose files these are (``"simulate"``, ``"export c"``):
        the key of its record in the manifest.
    command_line : list of str
        The command line recorded in the manifest.
    inputs : list of dict
        The input files recorded in the manifest: ``path``, ``size``, ``sha256``.
    names : list of str
        The file names asked for so far, in order.
    adopted : list of str
        Files this run wrote into ``directory`` itself (not staged, see
        :meth:`adopt`), recorded in the manifest as its own.
    written : list of Path
        The final paths, filled in when the run succeeded.
    removed : list of Path
        Files an earlier run of the same command wrote into ``directory``
        (listed in the manifest, unchanged since) that this run did not
        write again, and removed.
    kept : list of Path
        Files of the same command's earlier record that were changed or
        replaced since (so they are not prp3's any more) and were left alone.
    """

    directory: Path
    staging: Path
    command: str = LIBRARY_COMMAND
    command_line: list[str] = field(default_factory=list)
    inputs: list[dict[str, Any]] = field(default_factory=list)
    names: list[str] = field(default_factory=list)
    adopted: list[str] = field(default_factory=list)
    written: list[Path] = field(default_factory=list)
    removed: list[Path] = field(default_factory=list)
    kept: list[Path] = field(default_factory=list)

    @property
    def targets(self) -> list[Path]:
        """The final paths of the files asked for so far (where they will be moved)."""
        return [self.directory / name for name in [*self.adopted, *self.names]]

    def _earlier(self) -> dict[str, dict[str, int]]:
        return read_manifest(self.directory, self.command)

    def stale(self) -> list[Path]:
        """The files of the same command's earlier run that moving in will remove.

        Known before the files are moved in, so that a summary can list them first.
        """
        return [
            self.directory / name
            for name, stamp in self._earlier().items()
            if name not in self.names
            and name not in self.adopted
            and _file_stamp(self.directory / name) == stamp
        ]

    def changed(self) -> list[Path]:
        """The files of the earlier run's record changed since: moving in leaves them alone."""
        return [
            self.directory / name
            for name, stamp in self._earlier().items()
            if name not in self.names
            and name not in self.adopted
            and _file_stamp(self.directory / name) != stamp
            and os.path.lexists(self.directory / name)
        ]

    def final(self, path: str | Path) -> Path:
        """The final path of a staging path (``path`` itself when it is not staged)."""
        path = Path(path)
        if path.parent == self.staging:
            return self.directory / path.name
        return path

    def _check_name(self, name: str) -> None:
        if (
            name in self.names
            or name in self.adopted
            or Path(name).name != name
            or name in ("", ".", "..", MANIFEST_NAME)
        ):
            raise ValueError(f"output file name {name!r} is repeated or not a plain name")

    def path(self, name: str) -> Path:
        """The staging path to write the output file ``name`` to."""
        self._check_name(name)
        self.names.append(name)
        return self.staging / name

    def adopt(self, name: str) -> Path:
        """Count ``directory/name``, written by this run in place (atomically), as one of its files.

        For an output that has its own staging (the resumable
        ``designs.parquet`` of a sweep): it is not moved, but the manifest
        records it, so that it is not counted as stale.
        """
        self._check_name(name)
        self.adopted.append(name)
        return self.directory / name


@contextlib.contextmanager
def staged_output(
    directory: str | Path,
    *,
    command: str | None = None,
    command_line: Sequence[str] | None = None,
    inputs: Sequence[str | Path | None] = (),
) -> Iterator[StagedOutput]:
    """Write several output files so that they appear together or not at all.

    Creates ``directory`` (and its parents) when missing, and a temporary
    staging folder inside it.  Files are written to
    ``staged.path(name)``; when the block ends without an exception they are
    renamed into ``directory`` (replacing older files of the same name) and
    :attr:`StagedOutput.written` lists them.  On an exception the staging
    folder is deleted, folders this call created are removed again, and no
    file in ``directory`` changes.  A failure while a file is written is
    reported with the file's final path (:attr:`StagedOutput.targets`).

    The directory keeps a manifest, :data:`MANIFEST_NAME`, with one record
    per ``command``: the names, sizes and modification times of the files
    its last run wrote there, the prp3 version, the time, the
    ``command_line`` and the path, size and SHA-256 of every file of
    ``inputs`` (``None`` entries are skipped), so that a folder says how it
    was made.  A new run of a command removes the files of that command's
    earlier record that it does not write again — only those still exactly
    as prp3 wrote them (same size and modification time, regular files); the
    files of other commands, and a file the user changed, replaced or added,
    are never touched — and replaces its own record (a file it writes again
    that another command's record lists leaves that record).
    :attr:`StagedOutput.removed` lists what was removed,
    :attr:`StagedOutput.kept` what was left alone.

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
    >>> with staged_output(out, command="one") as staged:
    ...     _ = staged.path("a.txt").write_text("a")
    >>> [path.name for path in staged.written], sorted(p.name for p in out.iterdir())
    (['a.txt'], ['.prp3-manifest.json', 'a.txt'])
    >>> with staged_output(out, command="two") as staged:   # another command: a.txt stays
    ...     _ = staged.path("c.txt").write_text("c")
    >>> with staged_output(out, command="one") as staged:   # one again, writing b.txt only
    ...     _ = staged.path("b.txt").write_text("b")
    >>> [path.name for path in staged.removed], sorted(p.name for p in out.iterdir())
    (['a.txt'], ['.prp3-manifest.json', 'b.txt', 'c.txt'])
    >>> sorted(read_manifest_commands(out))
    ['one', 'two']
    """
    directory = Path(directory)
    records = [_input_record(path) for path in inputs if path is not None]
    staged, created = _start_staging(directory, command, command_line, records)
    try:
        try:
            yield staged
        except OutputFileError as error:  # name the output file, not its staging copy
            if error.file is None:
                raise
            raise error.located(file=staged.final(error.file)) from None
        except OSError as error:  # a writer's own failure (a full disk): the file being written
            raise _write_failure(staged, error) from None
        _move_in(staged)
    except BaseException:
        shutil.rmtree(staged.staging, ignore_errors=True)
        _remove_empty(created)
        raise
    try:
        shutil.rmtree(staged.staging, ignore_errors=True)
    except BaseException:  # an interrupt after the files are in: finish the cleanup, then stop
        shutil.rmtree(staged.staging, ignore_errors=True)
        raise


def _start_staging(
    directory: Path,
    command: str | None,
    command_line: Sequence[str] | None,
    records: list[dict[str, Any]],
) -> tuple[StagedOutput, list[Path]]:
    """The :class:`StagedOutput` of :func:`staged_output` (``directory`` made, a staging
    folder in it) and the folders made for it, deepest first."""
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
        raise OutputFileError(f"cannot write output directory ({reason})", file=directory) from None
    staged = StagedOutput(
        directory=directory,
        staging=staging,
        command=command or LIBRARY_COMMAND,
        command_line=[str(word) for word in command_line or ()],
        inputs=records,
    )
    return staged, created


def _write_failure(staged: StagedOutput, error: OSError) -> OutputFileError:
    """A writer's ``error`` as the :class:`OutputFileError` of the file being written."""
    if error.filename is not None:
        where = staged.final(os.fsdecode(error.filename))
    elif staged.names:
        where = staged.directory / staged.names[-1]
    else:
        where = staged.directory
    reason = error.strerror or str(error)
    return OutputFileError(f"cannot write ({reason})", file=where)


def _file_stamp(path: Path) -> dict[str, int] | None:
    """Size and modification time (ns) of a regular file (not a link); ``None`` otherwise."""
    try:
        info = os.lstat(path)
    except OSError:
        return None
    if not stat.S_ISREG(info.st_mode):
        return None
    return {"size": int(info.st_size), "mtime_ns": int(info.st_mtime_ns)}


def _plain_name(name: object) -> bool:
    return (
        isinstance(name, str)
        and name not in ("", ".", "..", MANIFEST_NAME)
        and Path(name).name == name
    )


def _stamps(files: object) -> dict[str, dict[str, int]]:
    """The well-formed entries ``name -> {size, mtime_ns}`` of a record's ``files``."""
    if not isinstance(files, dict):
        return {}
    entries: dict[str, dict[str, int]] = {}
    for name, stamp in files.items():
        if (
            _plain_name(name)
            and isinstance(stamp, dict)
            and all(type(stamp.get(key)) is int for key in ("size", "mtime_ns"))
        ):
            entries[name] = {"size": stamp["size"], "mtime_ns": stamp["mtime_ns"]}
    return entries


def read_manifest_commands(directory: str | Path) -> dict[str, dict[str, Any]]:
    """The records of the manifest of ``directory``, by command.

    Each record holds ``files`` (``name -> {size, mtime_ns}``, only the
    well-formed entries: plain file names with integer stamps) and, as
    written, ``prp3`` (the version), ``finished`` (UTC, ISO 8601),
    ``command_line`` and ``inputs``.  An absent, unreadable, oversized or
    malformed manifest, and a manifest of a prp3 older than the records per
    command (one list of files, whose command is unknown), count as nothing
    written: prp3 then removes nothing.
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
    commands = manifest.get("commands") if isinstance(manifest, dict) else None
    if not isinstance(commands, dict):
        return {}
    records: dict[str, dict[str, Any]] = {}
    for command, record in commands.items():
        if isinstance(command, str) and command and isinstance(record, dict):
            records[command] = {**record, "files": _stamps(record.get("files"))}
    return records


def read_manifest(directory: str | Path, command: str | None = None) -> dict[str, dict[str, int]]:
    """The files the last run of ``command`` wrote into ``directory``: ``name -> {size, mtime_ns}``.

    ``command`` ``None`` means the runs of :func:`staged_output` without a
    command.  See :func:`read_manifest_commands`: what is malformed counts as
    nothing written.
    """
    record = read_manifest_commands(directory).get(command or LIBRARY_COMMAND, {})
    files = record.get("files", {})
    return dict(files) if isinstance(files, dict) else {}


def _manifest_text(staged: StagedOutput, names: Sequence[str]) -> str:
    """The new manifest: this run's record, and the other commands' records kept."""
    from prp3 import __version__  # here: the package is initialised by the time a run ends

    written = set(names)
    commands: dict[str, Any] = {}
    for command, record in read_manifest_commands(staged.directory).items():
        if command == staged.command:
            continue
        files = {name: stamp for name, stamp in record["files"].items() if name not in written}
        if files:  # a record whose files were all written again by this run goes
            commands[command] = {**record, "files": files}
    stamps = {name: _file_stamp(staged.staging / name) for name in names}
    stamps |= {name: _file_stamp(staged.directory / name) for name in staged.adopted}
    now = datetime.datetime.now(datetime.UTC).replace(microsecond=0)
    commands[staged.command] = {
        "prp3": __version__,
        "finished": now.isoformat().replace("+00:00", "Z"),
        "command_line": staged.command_line,
        "working_directory": os.getcwd(),
        "inputs": staged.inputs,
        "files": {name: stamp for name, stamp in stamps.items() if stamp is not None},
    }
    manifest = {
        "about": "what prp3 wrote into this folder, per command: the files of its last run "
        "(the next run of the same command removes those it does not write again, when "
        "unchanged; nothing else), the version, the command line and the inputs' SHA-256",
        "commands": dict(sorted(commands.items())),
    }
    return json.dumps(manifest, indent=1) + "\n"


def _move_in(staged: StagedOutput) -> None:
    """Rename the staged files into the output directory: all of them, or none.

    Every target is checked first (an existing directory or special file of
    the same name is refused before anything moves).  Older files are
    hard-linked into the staging folder before they are replaced, so that a
    failure half-way (or an interrupt) puts them back and removes the new
    files already moved in.  The files of the same command's earlier record
    that this run does not write again (and that are unchanged) are moved
    into the staging folder too, and the new manifest is moved in last.
    """
    names = [name for name in staged.names if (staged.staging / name).exists()]
    for name in names:
        check_replaceable(staged.directory / name)
    stale: list[str] = []
    for name, stamp in read_manifest(staged.directory, staged.command).items():
        if name in names or name in staged.adopted:
            continue
        now = _file_stamp(staged.directory / name)
        if now == stamp:
            stale.append(name)
        elif now is not None or os.path.lexists(staged.directory / name):
            staged.kept.append(staged.directory / name)
    try:
        text = _manifest_text(staged, names)
        (staged.staging / MANIFEST_NAME).write_text(text, encoding="utf-8")
    except OSError as error:
        raise OutputFileError(
            f"cannot write ({error.strerror})", file=staged.directory / MANIFEST_NAME
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
            raise OutputFileError(f"cannot write ({error.strerror})", file=target) from None
        raise
    staged.written.extend(staged.directory / name for name in [*staged.adopted, *names])
    staged.removed.extend(staged.directory / name for name in stale)


def _remove_empty(folders: Sequence[Path]) -> None:
    """Remove the folders (deepest first) that are empty; ignore the others."""
    for folder in folders:
        with contextlib.suppress(OSError):
            folder.rmdir()
