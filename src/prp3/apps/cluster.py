"""The Dask client of the sweeps and optimizations of designs: of a scheduler, or of a new cluster.

:func:`dask_client` connects to a running ``dask.distributed`` scheduler
(probed first: an address that is not a scheduler is reported within
:data:`CONNECT_TIMEOUT` seconds) or starts a LocalCluster.
:func:`prp3.apps.sweep.run_sweep` and
:func:`prp3.apps.optimization.optimize_design` take a client or a factory of one
(:data:`ClientOrFactory`).

dask is imported inside the functions (the ``design`` extra).
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import os
import re
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, Any

from prp3.errors import ParameterError, Prp3Error

if TYPE_CHECKING:
    from dask.distributed import Client

__all__ = [
    "CONNECT_TIMEOUT",
    "ClientOrFactory",
    "dask_client",
]

Progress = Callable[[int, int], None]

#: What :func:`~prp3.apps.sweep.run_sweep` and :func:`~prp3.apps.optimization.optimize_design`
#: take as ``client``: a Dask client, or a callable of no argument that makes one (or a
#: context manager giving one, e.g. ``lambda: dask_client(2)``).
ClientOrFactory = Any

#: Seconds to wait for an existing scheduler (an unreachable one is reported within 10 s).
CONNECT_TIMEOUT: float = 5.0

#: No dashboard, and the scheduler's HTTP server (metrics) on a free port, not 8787.
QUIET_SCHEDULER: dict[str, Any] = {"dashboard": False, "dashboard_address": ":0"}


# ------------------------------------------------------------------ cluster
@contextlib.contextmanager
def dask_client(workers: int | None = None, scheduler: str | None = None) -> Iterator[Client]:
    """A ``dask.distributed`` client: of an existing scheduler, or of a new LocalCluster.

    Parameters
    ----------
    workers : int, optional
        Worker processes of the LocalCluster (one thread each); default: the
        machine's cores.  Ignored with ``scheduler``.
    scheduler : str, optional
        Address ``tcp://HOST:PORT`` of a running scheduler.

    Raises
    ------
    Prp3Error
        The scheduler cannot be reached within :data:`CONNECT_TIMEOUT` seconds
        or its address is malformed (names the address).
    """
    from dask.distributed import Client, LocalCluster

    if scheduler is not None:
        try:
            if not scheduler.startswith("inproc://"):  # in-process: nothing to probe
                asyncio.run(asyncio.wait_for(_probe(scheduler), CONNECT_TIMEOUT))
            client = Client(scheduler, timeout=CONNECT_TIMEOUT, set_as_default=False)
        except (Exception, MemoryError) as error:  # whatever the other end does
            reason = re.sub(r"\s+", " ", str(error)).strip() or type(error).__name__
            raise Prp3Error(
                f"--scheduler {scheduler}: cannot reach the Dask scheduler within "
                f"{CONNECT_TIMEOUT:g} s ({reason[:200]})"
            ) from None
        with client:
            yield client
        return
    with (
        LocalCluster(
            n_workers=workers or os.cpu_count() or 1,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            scheduler_kwargs=QUIET_SCHEDULER,
            silence_logs=logging.ERROR,
        ) as cluster,
        Client(cluster, set_as_default=False) as client,
    ):
        yield client


async def _probe(address: str) -> None:
    """Ask ``address`` who it is; raise unless a Dask scheduler answers.

    A client that connects to something else (a web server, a closed port
    behind a firewall) could wait, or allocate what a garbled reply asks for,
    before it fails; this fails first.
    """
    from distributed.comm.core import connect

    comm = await connect(address, timeout=CONNECT_TIMEOUT)
    try:
        await comm.write({"op": "identity", "reply": True})
        reply = await comm.read()
    finally:
        comm.abort()
    if not isinstance(reply, dict) or reply.get("type") != "Scheduler":
        raise ValueError(f"it answered as {str(reply)[:80]!r}, not as a Dask scheduler")


def worker_count(client: Client) -> int:
    return max(1, len(client.scheduler_info().get("workers", {})))


@contextlib.contextmanager
def using(client: ClientOrFactory, name: str) -> Iterator[Client]:
    """The Dask client of ``client``: a client itself (left open), or made by a factory.

    A factory is called with no argument; what it returns is a client (closed
    at the end) or a context manager giving one (entered, then left).

    Raises
    ------
    ParameterError
        ``client`` is neither (names the argument and the value).
    """
    from dask.distributed import Client

    if isinstance(client, Client):
        yield client
        return
    if not callable(client):
        raise ParameterError(
            f"{name} must be a dask.distributed.Client or a callable of no argument that makes "
            f"one (e.g. lambda: dask_client(2)), got {type(client).__name__}",
            key=name,
        )
    made = client()
    if isinstance(made, Client):
        with made:
            yield made
        return
    if isinstance(made, contextlib.AbstractContextManager):
        with made as entered:
            if not isinstance(entered, Client):
                raise ParameterError(
                    f"{name}() must give a dask.distributed.Client, got {type(entered).__name__}",
                    key=name,
                )
            yield entered
        return
    raise ParameterError(
        f"{name}() must make a dask.distributed.Client or a context manager giving one, "
        f"got {type(made).__name__}",
        key=name,
    )
