"""The progress bar of every subcommand: tqdm on stderr, only on a terminal, only for long runs.

The library reports progress through optional callbacks ``progress(done,
total)`` (:func:`prp3.apps.runs.simulate_table`, :func:`prp3.analysis.workspace.orientation_scan`,
:func:`prp3.analysis.forward.forward_dynamics`, :func:`prp3.apps.identification.identify`,
:func:`prp3.apps.control.track`, :func:`prp3.apps.excitation.exciting_trajectory`,
:func:`prp3.apps.sweep.run_sweep`, :func:`prp3.apps.optimization.optimize_design`, the CSV
writer); only the command line decides to show them, through :class:`Progress`:
a bar with the count, the rate and the estimated time left (tqdm), nothing
when stderr is not a terminal (a pipe, a file, a CI log) or before the run
has lasted :data:`DELAY` seconds.
"""

from __future__ import annotations

import contextlib
import os
import sys
import time
from collections.abc import Callable, Iterator
from typing import Any, TextIO

__all__ = ["DELAY", "Progress", "progress_bar"]

#: Seconds a run lasts before its bar appears (shorter runs stay silent).
DELAY: float = 1.0

#: Seconds between two redraws of a bar.
INTERVAL: float = 0.1


def _screen(stream: TextIO) -> tuple[int, int]:
    """The terminal's columns and rows; 80 and 24 when it says none.

    A new pseudo-terminal reports 0 x 0, and tqdm then draws nothing (an empty
    bar, hidden below row 0).
    """
    try:
        size = os.get_terminal_size(stream.fileno())
        columns, rows = size.columns, size.lines
    except (AttributeError, OSError, ValueError):  # no file descriptor: a test's fake terminal
        columns, rows = 0, 0
    return (columns if columns > 0 else 80, rows if rows > 0 else 24)


class Progress:
    """Progress bars on ``stream`` (a terminal's stderr), one stage at a time, drawn by tqdm.

    ``update(stage, done, total)`` reports ``done`` of ``total`` units of a
    stage; a new stage ends the bar of the previous one.  Nothing is drawn
    (and tqdm is not even imported) unless ``stream`` is a terminal and
    ``delay`` seconds have passed since the object was made; redraws are
    throttled to one per :data:`INTERVAL` seconds (the last one of a stage is
    always drawn).  :meth:`close` erases the bar.

    >>> import io
    >>> bar = Progress(io.StringIO())          # not a terminal: never draws
    >>> bar.update("writing", 5, 10); bar.close()
    >>> bar.drawn
    False
    """

    def __init__(
        self,
        stream: TextIO,
        *,
        delay: float | None = None,
        clock: Callable[[], float] = time.monotonic,
        enabled: bool | None = None,
    ) -> None:
        isatty = getattr(stream, "isatty", None)
        try:
            terminal = bool(isatty and isatty())
        except (OSError, ValueError):  # a closed stream
            terminal = False
        self.stream = stream
        self.enabled = terminal if enabled is None else enabled
        self.delay = DELAY if delay is None else delay
        self.clock = clock
        self.start = clock()
        self.last = -float("inf")
        self.drawn = False
        self._bar: Any = None  # the tqdm bar of the current stage
        self._stage: str | None = None

    def update(self, stage: str, done: int, total: int, unit: str = "it") -> None:
        """Report ``done`` of ``total`` units of work of ``stage``."""
        if not self.enabled:
            return
        now = self.clock()
        if now - self.start < self.delay:
            return
        last = done >= total
        if now - self.last < INTERVAL and not last and stage == self._stage:
            return
        self.last = now
        try:
            if self._bar is None or stage != self._stage:
                self._end()
                from tqdm import tqdm

                columns, rows = _screen(self.stream)
                self._bar = tqdm(
                    total=max(int(total), 0),
                    initial=max(int(done), 0),
                    desc=stage,
                    unit=unit,
                    file=self.stream,
                    leave=False,
                    ncols=columns,
                    nrows=rows,
                    mininterval=0.0,
                    miniters=1,
                    delay=0.0,
                )
                self._stage = stage  # drawn when made, at ``done``
            else:
                if self._bar.total != total:
                    self._bar.total = max(int(total), 0)
                self._bar.n = max(int(done), 0)
                self._bar.refresh()
            self.drawn = True
        except (OSError, ValueError):  # stderr gone: the run goes on without a bar
            self.enabled = False
            self._bar = None

    def stage(self, stage: str, unit: str = "it") -> Callable[[int, int], None]:
        """A ``progress(done, total)`` callback for ``stage``."""
        return lambda done, total: self.update(stage, done, total, unit)

    def _end(self) -> None:
        bar, self._bar, self._stage = self._bar, None, None
        if bar is not None:
            bar.close()  # leave=False: the line is erased

    def close(self) -> None:
        """Erase the bar if it was drawn."""
        try:
            self._end()
        except (OSError, ValueError):
            pass
        self.drawn = False


@contextlib.contextmanager
def progress_bar(stream: TextIO | None = None) -> Iterator[Progress]:
    """A :class:`Progress` on ``stream`` (default: stderr now), erased when the block ends."""
    bar = Progress(sys.stderr if stream is None else stream)
    try:
        yield bar
    finally:
        bar.close()
