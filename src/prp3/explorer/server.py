"""The server of ``prp3 explore``: a local Bokeh server of the explorer's page, until a signal.

:func:`serve` checks the port, then serves the 3-PRP page
(:func:`prp3.explorer.app.explorer_document`) or a family robot's
(:func:`prp3.explorer.family_app.family_document`), with a run or without, on
``http://host:port/``; SIGINT and SIGTERM stop it between two callbacks.  Its
websocket sends at once (``TCP_NODELAY``, :func:`_no_delay`).  Bokeh is
imported inside the functions only.
"""

from __future__ import annotations

import contextlib
import errno
import signal
import socket
import webbrowser
from collections.abc import Callable
from typing import Any

from prp3.errors import Prp3Error
from prp3.explorer.run_folder import Run, family_run_motion, run_motion
from prp3.family import FamilyRobot
from prp3.model.robot import Robot

__all__ = ["DEFAULT_HOST", "DEFAULT_PORT", "serve"]

DEFAULT_HOST: str = "127.0.0.1"
DEFAULT_PORT: int = 8765


def _listen_error(host: str, port: int, error: OSError) -> Prp3Error:
    if error.errno == errno.EADDRINUSE:
        return Prp3Error(
            f"port {port} on {host} is busy (another program listens there): "
            "choose another with --port",
            origin=f"--port {port}",
        )
    return Prp3Error(
        f"cannot listen on {host}:{port}: {error.strerror or error}", origin=f"--host {host}"
    )


def _no_delay() -> None:
    """Send the server's websocket messages at once (``TCP_NODELAY``), in this process.

    Bokeh's websocket handler leaves Nagle's algorithm on: a small message
    (the columns of one update) then waits for the browser's delayed
    acknowledgement, about 40 ms on loopback, at every slider move
    (``benchmarks/bench_explore.py`` measures the difference).
    """
    from bokeh.server.views.ws import WSHandler

    if getattr(WSHandler, "_prp3_no_delay", False):
        return
    opened = WSHandler.open

    def open_without_delay(self: Any) -> None:
        self.set_nodelay(True)
        opened(self)

    WSHandler.open = open_without_delay
    WSHandler._prp3_no_delay = True


def _check_port(host: str, port: int) -> None:
    """Refuse a port that is taken or an address this machine cannot listen on (one line)."""
    try:
        infos = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM, flags=socket.AI_PASSIVE)
    except OSError as error:
        raise Prp3Error(
            f"cannot listen on {host}:{port}: {error.strerror or error}", origin=f"--host {host}"
        ) from None
    for family, kind, protocol, _, address in infos:
        with socket.socket(family, kind, protocol) as probe:
            probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)  # as the server does
            try:
                probe.bind(address)
            except OSError as error:
                raise _listen_error(host, port, error) from None


def serve(
    robot: Robot | FamilyRobot,
    run: Run | None = None,
    *,
    host: str = DEFAULT_HOST,
    port: int = DEFAULT_PORT,
    open_browser: bool = True,
    announce: Callable[[str], None] = print,
) -> None:
    """Serve the explorer at ``http://host:port/`` until interrupted.

    A :class:`~prp3.family.FamilyRobot` is served by
    :func:`prp3.explorer.family_app.family_document` (its ``run`` read by
    :func:`~prp3.explorer.run_folder.read_family_run`).

    Raises
    ------
    Prp3Error
        The port is busy, or the address cannot be listened on (one line naming it);
        a run that is not the robot's.
    """
    from bokeh.application import Application
    from bokeh.application.handlers.function import FunctionHandler
    from bokeh.server.server import Server

    if isinstance(robot, FamilyRobot):
        family_robot = robot
        if run is not None:
            family_run_motion(family_robot, run)  # refused before the server starts

        def make(doc: Any) -> None:
            from prp3.explorer.family_app import family_document

            family_document(doc, family_robot, run)

    else:
        plain_robot = robot
        if run is not None:
            run_motion(plain_robot, run)  # refused before the server starts

        def make(doc: Any) -> None:
            from prp3.explorer.app import explorer_document

            explorer_document(doc, plain_robot, run)

    _check_port(host, port)
    _no_delay()
    origins = [f"{host}:{port}", f"localhost:{port}", f"127.0.0.1:{port}"]
    try:
        server = Server(
            {"/": Application(FunctionHandler(make))},
            address=host,
            port=port,
            allow_websocket_origin=origins,
            num_procs=1,
        )
    except OSError as error:  # taken between the check and the server's own bind
        raise _listen_error(host, port, error) from None
    url = f"http://{host}:{port}/"
    server.start()
    announce(url)
    if open_browser:
        server.io_loop.add_callback(lambda: webbrowser.open(url))
    received = _stop_on_signals(server.io_loop.asyncio_loop)
    try:
        server.io_loop.start()
    finally:
        server.stop()
        _raise_received(server.io_loop.asyncio_loop, received)


#: The signals that stop the server (the command line turns them into 130 and 143).
_STOP_SIGNALS: tuple[signal.Signals, ...] = (signal.SIGINT, signal.SIGTERM)


def _stop_on_signals(loop: Any) -> list[int]:
    """Stop ``loop`` at SIGINT or SIGTERM, between two callbacks; return the signals received.

    A Python signal handler that raises would raise inside whichever callback
    of the server runs at that moment, and asyncio logs and drops the
    exception of a callback: the server would go on.  The loop's own handlers
    run between callbacks; :func:`_raise_received` then hands the signal to
    the previous handler (the command line's), once the loop has stopped.
    """
    received: list[int] = []

    def stop(number: int) -> None:
        received.append(number)
        loop.stop()

    for number in _STOP_SIGNALS:
        try:
            loop.add_signal_handler(number, stop, int(number))
        except (NotImplementedError, RuntimeError, ValueError):  # not the main thread
            break
    return received


def _raise_received(loop: Any, received: list[int]) -> None:
    for number in _STOP_SIGNALS:
        with contextlib.suppress(NotImplementedError, RuntimeError, ValueError):
            loop.remove_signal_handler(number)
    if received:
        signal.raise_signal(received[0])
