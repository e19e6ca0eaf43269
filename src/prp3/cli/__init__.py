"""The ``prp3`` command line (argparse).

Each subcommand lives in its own module of this package and exposes
``register(subparsers)``, which adds its parser and sets ``handler`` to a
function ``handler(args) -> int``.  :func:`main` turns every
:class:`~prp3.errors.Prp3Error` into one line on stderr and exit status 2.
Nothing in the library imports this package.

Every message on stderr has one prefix, the command that was run:
``prp3 simulate: error: ...``, ``prp3 export mjcf: warning: ...`` — usage
errors of argparse included (``args.program`` holds it; ``prp3`` before a
command is known).
"""

from __future__ import annotations

import argparse
import contextlib
import os
import re
import signal
import sys
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path
from types import FrameType
from typing import Any, TextIO

from .. import __version__
from ..errors import Prp3Error
from . import control, design, excite, export, forward, identify, robot, simulate, workspace

__all__ = ["main"]

#: Subcommand modules, in the order ``prp3 --help`` lists them.
COMMANDS = (simulate, robot, workspace, forward, control, excite, identify, export, design)


#: Exit status after SIGTERM (128 + 15, as the shell reports a killed process).
EXIT_TERMINATED: int = 143

#: Negative numbers as option values: argparse's own pattern misses ``-1e-3`` and ``-inf``.
_NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$|^-(inf|infinity|nan)$", re.I)


class _Parser(argparse.ArgumentParser):
    """ArgumentParser whose usage errors exit with status 2 and one line.

    Values that look like negative numbers (``--phi -1e-3``) are values, not options.
    """

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = _NEGATIVE_NUMBER
        # the innermost (sub)command parsed sets it last: the prefix of every message
        self.set_defaults(program=self.prog)

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(2, f"{self.prog}: error: {message}\n")

    def parse_args(  # type: ignore[override]
        self, args: Sequence[str] | None = None, namespace: argparse.Namespace | None = None
    ) -> argparse.Namespace:
        """Parse; unknown arguments are reported by the (sub)command that got them."""
        parsed, extras = self.parse_known_args(args, namespace)
        if extras:
            program = getattr(parsed, "program", self.prog)
            self.exit(2, f"{program}: error: unrecognized arguments: {' '.join(extras)}\n")
        return parsed


class _Terminated(BaseException):
    """Raised by the SIGTERM handler, so that partial outputs are cleaned up as on Ctrl-C."""


def _terminate(signum: int, frame: FrameType | None) -> None:
    raise _Terminated


def _one_line_warnings(program: str) -> Callable[..., None]:
    """A ``warnings.showwarning`` that shows a library's warning as one line on stderr."""

    def show(
        message: Warning | str,
        category: type[Warning],
        filename: str,
        lineno: int,
        file: TextIO | None = None,
        line: str | None = None,
    ) -> None:
        with contextlib.suppress(OSError, ValueError):
            print(
                f"{program}: warning: {message} ({category.__name__}, "
                f"{Path(filename).name}:{lineno})",
                file=sys.stderr,
            )

    return show


def _silence_stdout() -> None:
    """Point stdout at /dev/null so that the flush at exit raises nothing more."""
    with contextlib.suppress(OSError, ValueError):  # as the Python docs advise
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())


def build_parser() -> argparse.ArgumentParser:
    """The ``prp3`` argument parser with every subcommand."""
    parser = _Parser(
        prog="prp3",
        description="Kinematics and complete inverse dynamics of the 3-PRP planar parallel robot.",
        epilog=(
            "examples:\n"
            "  prp3 simulate --motion vertical --output out --plots   # the paper's Figs. 3-5\n"
            "  prp3 robot --template > robot.toml\n"
            "  prp3 COMMAND --help\n"
            "\n"
            "Errors: one line on stderr, exit status 2, no output file written."
        ),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"prp3 {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for command in COMMANDS:
        command.register(subparsers)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line with ``argv`` (default ``sys.argv[1:]``); return the exit status."""
    parser = build_parser()
    args = parser.parse_args(list(argv) if argv is not None else None)
    if getattr(args, "handler", None) is None:
        parser.print_help(sys.stderr)
        return 2
    program = str(getattr(args, "program", "prp3"))
    previous: Any = None
    with contextlib.suppress(ValueError):  # signal handlers only in the main thread
        previous = signal.signal(signal.SIGTERM, _terminate)
    try:
        with warnings.catch_warnings():
            warnings.showwarning = _one_line_warnings(program)
            status = int(args.handler(args))
            sys.stdout.flush()  # here, not at exit: a failing stdout gets its one line
            return status
    except Prp3Error as error:
        print(f"{program}: error: {error}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"{program}: interrupted", file=sys.stderr)
        return 130
    except _Terminated:
        print(f"{program}: terminated", file=sys.stderr)
        return EXIT_TERMINATED
    except BrokenPipeError:  # e.g. `prp3 robot --template | head -n 3`
        _silence_stdout()
        return 141
    except MemoryError as error:
        print(
            f"{program}: error: not enough memory ({error}): ask for fewer samples or grid points",
            file=sys.stderr,
        )
        return 2
    except OSError as error:  # e.g. stdout on a full disk: `prp3 robot --template > /dev/full`
        where = error.filename if error.filename is not None else "standard output"
        with contextlib.suppress(OSError, ValueError):
            print(f"{program}: error: {where}: {error.strerror or error}", file=sys.stderr)
        _silence_stdout()
        return 2
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
