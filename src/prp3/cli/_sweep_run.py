"""What the design commands share on the command line: the Dask client of ``--workers`` /
``--scheduler``, and a sweep's run with its folder checks, warnings, progress and summary
line (``prp3 sweep`` of the 3-PRP, the family and the spatial robots)."""

from __future__ import annotations

import argparse
import contextlib
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING

from prp3.cli._progress import Progress

if TYPE_CHECKING:
    from dask.distributed import Client

    from prp3.apps.sweep import Sweepable, SweepRun

__all__ = ["client_of", "swept"]


@contextlib.contextmanager
def client_of(args: argparse.Namespace) -> Iterator[Client]:
    """A client of ``--scheduler``, or of a LocalCluster of ``--workers`` processes."""
    from prp3.apps.cluster import dask_client

    with dask_client(args.workers, args.scheduler) as client:
        yield client


def swept(args: argparse.Namespace, spec: Sweepable, output: Path) -> tuple[SweepRun, list[str]]:
    """Run the sweep of ``spec`` into ``output`` (:func:`prp3.apps.sweep.run_sweep`): refuse
    another spec's designs unless ``--force``, warn of other specs' unfinished sweeps, show
    the progress; return the run and the summary's lines on its chunks."""
    from prp3.apps import sweep

    sweep.check_sweep_folder(output, spec, force=args.force)  # before any warning
    for _, described in sweep.stale_staging_folders(output, spec):
        print(
            f"{args.program}: warning: {described}: an unfinished sweep of another spec; "
            "it is removed when this sweep finishes (resume it first to keep it)",
            file=sys.stderr,
        )
    progress = Progress(sys.stderr)
    start = time.monotonic()
    try:
        result = sweep.run_sweep(
            spec, output, lambda: client_of(args), progress=progress.stage("designs"),
            force=args.force,
        )  # fmt: skip
    finally:
        progress.close()
    elapsed = time.monotonic() - start
    reused = result.chunks - result.computed
    lines = [
        f"  {result.computed} of {result.chunks} chunks computed"
        + (f", {reused} found done" if reused else "")
        + f", {elapsed:.3g} s",
        *(f"  removed {described}: superseded by this sweep" for described in result.removed),
    ]
    return result, lines
