"""The ``prp3`` command line (argparse).

Each subcommand lives in its own module of this package and exposes
``register(subparsers)``, which adds its parser and sets ``handler`` to a
function ``handler(args) -> int``.  :func:`main` turns every
:class:`~prp3.errors.Prp3Error` into one line on stderr and exit status 2.
Nothing in the library imports this package.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
from collections.abc import Sequence

from .. import __version__
from ..errors import Prp3Error
from . import export, forward, robot, simulate, workspace

__all__ = ["main"]

#: Subcommand modules, in the order ``prp3 --help`` lists them.
COMMANDS = (simulate, robot, workspace, forward, export)


class _Parser(argparse.ArgumentParser):
    """ArgumentParser whose usage errors exit with status 2 and one line."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(2, f"{self.prog}: error: {message}\n")


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
    try:
        return int(args.handler(args))
    except Prp3Error as error:
        print(f"prp3: error: {error}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("prp3: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # e.g. `prp3 robot --template | head -n 3`
        with contextlib.suppress(OSError, ValueError):  # as the Python docs advise:
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # no error at exit
        return 141
