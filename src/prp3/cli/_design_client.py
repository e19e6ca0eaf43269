"""The Dask client of ``--workers`` / ``--scheduler`` (shared by the design commands)."""

from __future__ import annotations

import argparse
import contextlib
from collections.abc import Iterator
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from dask.distributed import Client

__all__ = ["client_of"]


@contextlib.contextmanager
def client_of(args: argparse.Namespace) -> Iterator[Client]:
    """A client of ``--scheduler``, or of a LocalCluster of ``--workers`` processes."""
    from prp3.apps.cluster import dask_client

    with dask_client(args.workers, args.scheduler) as client:
        yield client
