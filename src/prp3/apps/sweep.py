"""Sweeps of designs on Dask, with the results in Parquet.

:func:`run_sweep` evaluates the designs of a :class:`~prp3.apps.sweep_spec.SweepSpec`
in chunks of ``chunk`` designs (:data:`~prp3.apps.sweep_spec.CHUNK_DESIGNS` by default), one
``dask.distributed`` task per chunk (:func:`prp3.apps.design_evaluation.evaluate_designs`),
and writes ``designs.parquet``: one row per design, in the order the designs
are generated, whatever the number of workers.

Resuming: every finished chunk is written at once, whole or not at all, to a
staging folder ``DIR/.prp3-sweep-<digest>`` named by the SHA-256 of
everything the rows depend on (:meth:`~prp3.apps.sweep_spec.SweepSpec.digest`: the
nominal robot, the parameters, the sampling, the task's samples).  A sweep
that was interrupted and is run again with the same spec computes only the
chunks the folder lacks; then the chunks are joined in order into one
Parquet file, written atomically, and the folder is removed.  The Parquet
file is the same, byte for byte, as the one of an uninterrupted run.  The
staging folders of other specs in ``DIR`` (an interrupted sweep whose spec
was changed since) hold work that ``DIR/designs.parquet`` no longer is
about: a sweep that finishes removes them, and says which
(:attr:`SweepRun.removed`; :func:`stale_staging_folders` lists them
before).  Its
key-value metadata holds the digest, the spec and the row of the nominal
design (``prp3.*`` keys; :func:`read_designs`).

dask and pyarrow are imported inside the functions (the ``design`` extra).
"""

from __future__ import annotations

import contextlib
import itertools
import json
import os
import re
import shutil
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
from numpy.typing import NDArray

from prp3.apps.cluster import ClientOrFactory, Progress, using, worker_count
from prp3.apps.design import DesignEvaluator, RowEvaluator
from prp3.apps.design_evaluation import evaluate_rows
from prp3.errors import InputFileError, OutputFileError
from prp3.files import atomic_path, check_output_directory

if TYPE_CHECKING:
    from dask.distributed import Client

__all__ = [
    "DESIGNS_FILE",
    "DesignTable",
    "SweepRun",
    "Sweepable",
    "arrow_table",
    "check_sweep_folder",
    "evaluate_chunk",
    "read_designs",
    "run_sweep",
    "staging_folder",
    "stale_staging_folders",
    "sweep_of",
]

FloatArray = NDArray[np.float64]

#: Name of the sweep's output file in its directory.
DESIGNS_FILE: str = "designs.parquet"

#: Rows per Parquet row group of ``designs.parquet``.
ROW_GROUP: int = 65_536

#: Names of the staging folders of sweeps (``.prp3-sweep-`` and 20 hex digits of the digest).
_STAGING = re.compile(r"^\.prp3-sweep-[0-9a-f]{20}$")

#: The file of a staging folder that says which sweep it belongs to.
_MANIFEST = "sweep.json"


class Sweepable(Protocol):
    """What :func:`run_sweep` needs of a spec: :class:`~prp3.apps.sweep_spec.SweepSpec` (the
    3-PRP) and :class:`~prp3.apps.spatial_design.SpatialSweepSpec` (the spatial robots)."""

    @property
    def source(self) -> str:
        """Where the spec came from (for messages)."""
        ...

    @property
    def chunk(self) -> int:
        """Designs per Dask task."""
        ...

    @property
    def evaluator(self) -> DesignEvaluator | RowEvaluator:
        """Evaluates a chunk of designs on a worker."""
        ...

    @property
    def paths(self) -> tuple[str, ...]:
        """Key paths of the varied parameters."""
        ...

    @property
    def count(self) -> int:
        """Number of rows."""
        ...

    def digest(self) -> str:
        """SHA-256 of everything the rows depend on."""
        ...

    def design_values(self) -> FloatArray:
        """The rows' designs ``(count, p)``, in order."""
        ...

    def nominal_row(self) -> dict[str, Any]:
        """The row of the nominal design (the file's metadata)."""
        ...

    def described(self) -> dict[str, Any]:
        """The spec as the file's metadata records it (JSON)."""
        ...


# ------------------------------------------------------------------ Parquet
def arrow_table(columns: dict[str, Any], names: Sequence[str]) -> Any:
    """The columns ``names`` as a pyarrow table: arrays of text (``status``, ...) as strings,
    the others float64."""
    import pyarrow as pa

    arrays = []
    for name in names:
        values = np.asarray(columns[name])
        arrays.append(
            pa.array(values.tolist(), type=pa.string())
            if values.dtype.kind in "US"
            else pa.array(np.asarray(values, dtype=np.float64), type=pa.float64())
        )
    return pa.Table.from_arrays(arrays, names=list(names))


def evaluate_chunk(evaluator: DesignEvaluator | RowEvaluator, values: FloatArray) -> dict[str, Any]:
    """:func:`~prp3.apps.design_evaluation.evaluate_rows`: the task of one chunk on a worker."""
    return evaluate_rows(evaluator, values)


@dataclass(frozen=True)
class DesignTable:
    """``designs.parquet`` read back.

    Attributes
    ----------
    columns : dict
        Column name -> ndarray (float64; ``status`` of str).
    parameters : tuple of str
        Key paths of the varied parameters (the first columns).
    nominal : dict
        The row of the nominal design (parameter values NaN when the nominal
        robot does not give them).
    digest : str
        The sweep's digest.
    """

    columns: dict[str, Any]
    parameters: tuple[str, ...]
    nominal: dict[str, Any]
    digest: str

    @property
    def rows(self) -> int:
        """Number of designs."""
        return len(self.columns["status"])


#: The four bytes that begin and end every Parquet file.
_PARQUET_MAGIC = b"PAR1"


def _truncation(path: Path) -> str | None:
    """What is wrong with ``path`` when it is a Parquet file cut short, else ``None``.

    A Parquet file begins and ends with ``PAR1``; its footer, at the end,
    describes the rows and holds prp3's metadata (the sweep's digest and spec),
    so a file that begins as Parquet but has lost its end (a copy or a disk
    that filled up) can be neither read nor told apart from another sweep's.
    """
    try:
        with path.open("rb") as stream:
            head = stream.read(4)
            size = stream.seek(0, os.SEEK_END)
            stream.seek(max(size - 4, 0))
            tail = stream.read(4)
    except OSError:
        return None
    if not _PARQUET_MAGIC.startswith(head) or (size >= 12 and tail == _PARQUET_MAGIC):
        return None  # not Parquet at all (an empty file is one cut at 0 bytes), or whole
    return (
        f"truncated: a Parquet file cut short ({size} bytes, without the footer that ends "
        "every Parquet file and holds the rows' layout and prp3's metadata)"
    )


def read_designs(path: str | Path, columns: Sequence[str] | None = None) -> DesignTable:
    """Read ``designs.parquet`` written by :func:`run_sweep` (only ``columns`` when given).

    Raises
    ------
    InputFileError
        Unreadable file, not Parquet, a Parquet file cut short (``truncated``),
        or not written by ``prp3 sweep`` (names the file).
    """
    import pyarrow.parquet as pq

    path = Path(path)
    try:
        table = pq.read_table(path, columns=None if columns is None else list(columns))
    except (OSError, ValueError, KeyError) as error:
        truncated = _truncation(path)
        if truncated is not None:
            raise InputFileError(
                f"{truncated}; run the sweep again to rewrite it", file=path
            ) from None
        reason = re.sub(r"\s+", " ", str(error)).strip()[:200]
        raise InputFileError(f"{path}: cannot read a Parquet file ({reason})") from None
    metadata = table.schema.metadata or {}
    try:
        parameters = tuple(json.loads(metadata[b"prp3.parameters"]))
        nominal = json.loads(metadata[b"prp3.nominal"])
        digest = metadata[b"prp3.digest"].decode()
    except (KeyError, ValueError):
        raise InputFileError(
            f"{path}: not a designs file of prp3 sweep (no prp3 metadata)"
        ) from None
    import pyarrow as pa

    read: dict[str, Any] = {}
    for name in table.column_names:
        column = table.column(name)
        if pa.types.is_string(column.type):
            read[name] = np.array(column.to_pylist(), dtype=str)
        else:
            read[name] = np.asarray(column.to_numpy(), dtype=np.float64)
    return DesignTable(columns=read, parameters=parameters, nominal=nominal, digest=digest)


def _metadata(spec: Sweepable) -> dict[bytes, bytes]:
    return {
        b"prp3.digest": spec.digest().encode(),
        b"prp3.parameters": json.dumps(list(spec.paths)).encode(),
        b"prp3.nominal": json.dumps(spec.nominal_row()).encode(),
        b"prp3.spec": json.dumps(spec.described()).encode(),
    }


# ------------------------------------------------------------------ sweep
@dataclass(frozen=True)
class SweepRun:
    """What :func:`run_sweep` did.

    Attributes
    ----------
    path : Path
        ``DIR/designs.parquet``.
    rows : int
        Designs in it.
    chunks : int
        Chunks of the sweep.
    computed : int
        Chunks computed by this run (the others were found in the staging
        folder of an interrupted run, or the file was complete already).
    status : dict
        Number of designs per status.
    removed : tuple of str
        The staging folders of other specs that were removed, described
        (:func:`stale_staging_folders`).
    """

    path: Path
    rows: int
    chunks: int
    computed: int
    status: dict[str, int] = field(default_factory=dict)
    removed: tuple[str, ...] = ()


def sweep_of(path: str | Path) -> tuple[str, str] | None:
    """The digest and the spec file of the sweep whose designs ``path`` holds.

    ``None`` when ``path`` is not a designs file of prp3 (unreadable, not
    Parquet, without prp3's metadata).
    """
    import pyarrow.parquet as pq

    try:
        metadata = pq.read_schema(Path(path)).metadata or {}
        digest = metadata[b"prp3.digest"].decode()
    except (OSError, ValueError, KeyError, UnicodeDecodeError):
        return None
    source = "an unnamed spec"
    with contextlib.suppress(KeyError, ValueError, TypeError, AttributeError):
        source = str(json.loads(metadata[b"prp3.spec"])["source"])[:200]
    return digest, source


def check_sweep_folder(output: str | Path, spec: Sweepable, *, force: bool = False) -> None:
    """Refuse an output folder whose ``designs.parquet`` is not of ``spec`` (unless ``force``).

    The designs of another spec (or a file of that name prp3 did not write)
    would otherwise be replaced silently.

    Raises
    ------
    OutputFileError
        Naming the file and the spec it holds.
    """
    target = Path(output) / DESIGNS_FILE
    if force or not os.path.lexists(target):
        return
    held = sweep_of(target)
    if held is not None and held[0] == spec.digest():
        return
    truncated = None if held is not None else _truncation(target)
    if truncated is not None:  # its spec cannot be read: perhaps this one's, perhaps not
        raise OutputFileError(
            f"{truncated}, so the sweep it holds cannot be told; recompute it into this "
            "directory (--force, force=True), or choose another output directory",
            file=target,
        )
    what = (
        f"holds the designs of another sweep ({held[1]})"
        if held is not None
        else "is not a designs file of prp3 sweep"
    )
    raise OutputFileError(
        f"{what}; choose another output directory, or replace it (--force, force=True)",
        file=target,
    )


def staging_folder(output: str | Path, spec: Sweepable) -> Path:
    """The staging folder of the chunks of ``spec`` in ``output``."""
    return Path(output) / f".prp3-sweep-{spec.digest()[:20]}"


def stale_staging_folders(output: str | Path, spec: Sweepable) -> list[tuple[Path, str]]:
    """The staging folders in ``output`` of sweeps of other specs, each with its description.

    An interrupted sweep leaves its folder; when its spec is changed and the
    sweep run again into the same directory, the old folder can no longer be
    resumed into ``output/designs.parquet`` (that file is the new spec's).
    Only folders named as :func:`staging_folder` names them are listed.  The
    description names the folder, its chunks and, when it says so, its spec
    file: ``DIR/.prp3-sweep-… (2 of 4 chunks of old.toml)``.
    """
    output = Path(output)
    own = staging_folder(output, spec).name
    try:
        entries = sorted(output.iterdir())
    except OSError:
        return []
    stale = []
    for folder in entries:
        if folder.name == own or not _STAGING.match(folder.name) or not folder.is_dir():
            continue
        chunks = len(list(folder.glob("chunk-*.parquet")))
        of = ""
        try:  # written by the sweep that made the folder; a missing or odd one says less
            manifest = json.loads((folder / _MANIFEST).read_text(encoding="utf-8"))
            of = f" of {int(manifest['chunks'])} chunks of {str(manifest['spec'])[:200]}"
        except (OSError, ValueError, KeyError, TypeError):
            of = " chunks"
        stale.append((folder, f"{folder} ({chunks}{of})"))
    return stale


def _remove_stale(output: Path, spec: Sweepable) -> tuple[str, ...]:
    removed = []
    for folder, described in stale_staging_folders(output, spec):
        shutil.rmtree(folder, ignore_errors=True)
        if not folder.exists():
            removed.append(described)
    return tuple(removed)


def _chunk_file(staging: Path, index: int) -> Path:
    return staging / f"chunk-{index:07d}.parquet"


def _chunk_ok(path: Path, rows: int, names: Sequence[str]) -> bool:
    import pyarrow.parquet as pq

    try:
        meta = pq.read_metadata(path)
    except (OSError, ValueError):
        return False
    return bool(meta.num_rows == rows and list(meta.schema.names) == list(names))


def run_sweep(
    spec: Sweepable,
    output: str | Path,
    client: ClientOrFactory,
    *,
    progress: Progress | None = None,
    force: bool = False,
) -> SweepRun:
    """Evaluate every design of ``spec`` and write ``output/designs.parquet``.

    Parameters
    ----------
    spec : SweepSpec
    output : path
        Output directory, created when missing.
    client : dask.distributed.Client or callable
        A Dask client (used, left open), or a callable of no argument that
        makes one or a context manager giving one (e.g.
        ``lambda: dask_client(2)``), called only when some chunk is missing.
    progress : callable, optional
        ``progress(chunks_done, chunks)``.
    force : bool
        Replace a ``designs.parquet`` of another spec (refused otherwise,
        :func:`check_sweep_folder`).

    Raises
    ------
    OutputFileError
        The directory cannot be written, or it holds the designs of another
        spec and not ``force``.
    ParameterError
        A design that is not a valid robot; ``client`` neither a client nor a
        factory.
    """
    output = Path(output)
    staging = staging_folder(output, spec)
    created_output = not output.exists()
    created_staging = not staging.exists()
    try:
        check_output_directory(output)
        check_sweep_folder(output, spec, force=force)
        target = output / DESIGNS_FILE
        if target.is_file():
            with contextlib.suppress(InputFileError):
                done = read_designs(target, ["status"])
                if done.digest == spec.digest():  # finished: its staging leftovers go
                    shutil.rmtree(staging, ignore_errors=True)
                    removed = _remove_stale(output, spec)
                    return _summary(target, done.columns, 0, spec, removed)
        values = spec.design_values()
        return _sweep_into(spec, output, staging, target, values, client, progress=progress)
    except BaseException:
        # A run that fails before its first chunk leaves the folder as it was:
        # the staging folder it made goes, and the output folder if it made it
        # and nothing else is in it.  Chunks already computed stay for a resume.
        if created_staging and staging.is_dir() and not any(staging.glob("chunk-*")):
            shutil.rmtree(staging, ignore_errors=True)
        if created_output and output.is_dir() and not any(output.iterdir()):
            with contextlib.suppress(OSError):
                output.rmdir()
        raise


def _sweep_into(
    spec: Sweepable,
    output: Path,
    staging: Path,
    target: Path,
    values: Any,
    client: ClientOrFactory,
    *,
    progress: Progress | None,
) -> SweepRun:
    """The body of :func:`run_sweep` once the folder is checked: chunks, then the file."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    digest = spec.digest()
    names = spec.evaluator.columns
    count = len(values)
    starts = list(range(0, count, spec.chunk))
    try:
        staging.mkdir(parents=True, exist_ok=True)
        if not (staging / _MANIFEST).is_file():
            described = {"spec": spec.source, "digest": digest, "chunks": len(starts)}
            with atomic_path(staging / _MANIFEST) as temporary:
                temporary.write_text(json.dumps(described), encoding="utf-8")
    except OSError as error:
        raise OutputFileError(f"{staging}: cannot create ({error.strerror})") from None
    rows = [min(spec.chunk, count - start) for start in starts]
    missing = [
        i
        for i, start in enumerate(starts)
        if not _chunk_ok(_chunk_file(staging, i), rows[i], names)
    ]
    finished = len(starts) - len(missing)
    if progress is not None:
        progress(finished, len(starts))
    if missing:
        with using(client, "client") as dask:
            finished = _compute_chunks(
                dask,
                spec.chunk,
                spec.evaluator,
                values,
                starts,
                missing,
                staging,
                names,
                finished,
                progress,
            )
    text = spec.evaluator.text_columns
    schema = pa.schema(
        [(n, pa.string() if n in text else pa.float64()) for n in names],
        metadata=_metadata(spec),
    )
    with atomic_path(target) as temporary:
        with pq.ParquetWriter(temporary, schema) as writer:
            group: list[Any] = []
            grouped = 0
            for i in range(len(starts)):
                part = pq.read_table(_chunk_file(staging, i)).replace_schema_metadata(
                    schema.metadata
                )
                group.append(part)
                grouped += part.num_rows
                if grouped >= ROW_GROUP or i == len(starts) - 1:
                    writer.write_table(pa.concat_tables(group), row_group_size=ROW_GROUP)
                    group, grouped = [], 0
    shutil.rmtree(staging, ignore_errors=True)
    removed = _remove_stale(output, spec)
    columns = read_designs(target, ["status"]).columns
    return _summary(target, columns, len(missing), spec, removed)


def _compute_chunks(
    dask: Client,
    chunk: int,
    evaluator: DesignEvaluator | RowEvaluator,
    values: FloatArray,
    starts: list[int],
    missing: list[int],
    staging: Path,
    names: Sequence[str],
    finished: int,
    progress: Progress | None,
) -> int:
    """Run the missing chunks on Dask, a bounded window of them at a time; write each one."""
    import pyarrow.parquet as pq
    from dask.distributed import as_completed

    shared = dask.scatter(evaluator, broadcast=True, hash=False)
    window = 4 * worker_count(dask) + 4
    pending = iter(missing)
    index_of: dict[Any, int] = {}

    def submit(index: int) -> Any:
        part = values[starts[index] : starts[index] + chunk]
        future = dask.submit(evaluate_chunk, shared, part, pure=False)
        index_of[future.key] = index
        return future

    queue = as_completed([submit(i) for i in itertools.islice(pending, window)], loop=dask.loop)
    for future in queue:
        index = index_of.pop(future.key)
        columns = future.result()
        with atomic_path(_chunk_file(staging, index)) as temporary:
            pq.write_table(arrow_table(columns, names), temporary)
        finished += 1
        if progress is not None:
            progress(finished, len(starts))
        following = next(pending, None)
        if following is not None:
            queue.add(submit(following))
        del future
    return finished


def _summary(
    path: Path, columns: dict[str, Any], computed: int, spec: Sweepable, removed: tuple[str, ...]
) -> SweepRun:
    statuses, counts = np.unique(np.asarray(columns["status"]), return_counts=True)
    chunks = -(-spec.count // spec.chunk)
    return SweepRun(
        path=path,
        rows=len(columns["status"]),
        chunks=chunks,
        computed=computed,
        status={str(s): int(c) for s, c in zip(statuses, counts, strict=True)},
        removed=removed,
    )
