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
import difflib
import errno
import os
import re
import signal
import sys
import threading
import warnings
from collections.abc import Callable, Sequence
from types import FrameType
from typing import Any, TextIO

from prp3 import __version__
from prp3.cli import (
    control,
    design,
    excite,
    explore,
    export,
    forward,
    identify,
    robot,
    simulate,
    workspace,
)
from prp3.errors import OutputFileError, Prp3Error

__all__ = ["main"]

#: Subcommand modules, in the order ``prp3 --help`` lists them.
COMMANDS = (
    simulate,
    robot,
    workspace,
    forward,
    control,
    excite,
    identify,
    export,
    design,
    explore,
)


#: Exit status after SIGTERM (128 + 15, as the shell reports a killed process).
EXIT_TERMINATED: int = 143

#: Negative numbers as option values: argparse's own pattern misses ``-1e-3`` and ``-inf``.
_NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$|^-(inf|infinity|nan)$", re.I)


class _Parser(argparse.ArgumentParser):
    """ArgumentParser whose usage errors exit with status 2 and one line.

    Values that look like negative numbers (``--phi -1e-3``) are values, not options.
    """

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault("allow_abbrev", False)  # no silent prefixes: --samp is not --samples
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = _NEGATIVE_NUMBER
        self._words: list[str] = []
        # the innermost (sub)command parsed sets it last: the prefix of every message
        self.set_defaults(program=self.prog)

    def error(self, message: str) -> None:  # type: ignore[override]
        unknown = self._unknown_options()
        if unknown:  # a misspelled option makes argparse complain of something else: name it
            message += "; unknown option" + ("s " if len(unknown) > 1 else " ")
            message += ", ".join(self._suggest(name) for name in unknown)
        self.exit(2, f"{self.prog}: error: {message}\n")

    def parse_known_args(  # type: ignore[override]
        self, args: Sequence[str] | None = None, namespace: argparse.Namespace | None = None
    ) -> tuple[argparse.Namespace, list[str]]:
        self._words = list(sys.argv[1:] if args is None else args)
        return super().parse_known_args(args, namespace)

    def _unknown_options(self) -> list[str]:
        """The option-like words given to this parser that it does not know (before a command)."""
        commands = any(isinstance(a, argparse._SubParsersAction) for a in self._actions)
        unknown = []
        for word in self._words:
            if word == "--" or (commands and not word.startswith("-")):
                break  # the options of a (mistyped) command are its own
            if not word.startswith("-") or word == "-" or self._negative_number_matcher.match(word):
                continue
            name = word.split("=", 1)[0]
            attached = not word.startswith("--") and word[:2] in self._option_string_actions
            if name not in self._option_string_actions and not attached and name not in unknown:
                unknown.append(name)
        return unknown

    def _suggest(self, name: str) -> str:
        """``name`` and the known option it is closest to, if any."""
        known = [option for option in self._option_string_actions if option.startswith("--")]
        close = difflib.get_close_matches(name, known, n=1, cutoff=0.6)
        return f"{name} (did you mean {close[0]}?)" if close else name

    def parse_args(  # type: ignore[override]
        self, args: Sequence[str] | None = None, namespace: argparse.Namespace | None = None
    ) -> argparse.Namespace:
        """Parse; unknown arguments are reported by the (sub)command that got them."""
        parsed, extras = self.parse_known_args(args, namespace)
        if extras:
            program = getattr(parsed, "program", self.prog)
            command = self._command_parser(program)
            named = [command._suggest(word) if word.startswith("-") else word for word in extras]
            self.exit(2, f"{program}: error: unrecognized arguments: {' '.join(named)}\n")
        return parsed

    def _command_parser(self, program: str) -> _Parser:
        """The (sub)parser whose ``prog`` is ``program`` (this one if none is)."""
        parser: _Parser = self
        for word in program.split()[1:]:
            choices = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
            child = choices[0].choices.get(word) if choices else None
            if not isinstance(child, _Parser):
                break
            parser = child
        return parser


#: Exit status after SIGINT (128 + 2, as the shell reports an interrupted process).
EXIT_INTERRUPTED: int = 130


class _Signalled(BaseException):
    """Raised by the signal handler, so that partial outputs are cleaned up as on Ctrl-C."""

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum


class _SignalGuard:
    """SIGINT and SIGTERM handlers that raise once: later signals of a burst are only counted.

    The first signal raises :class:`_Signalled` in the main thread; the
    clean-up that follows (removing the staging folder, putting older files
    back) then runs to its end even when more signals arrive, and the command
    ends with one line and 130 (SIGINT) or 143 (SIGTERM).
    """

    SIGNALS = (signal.SIGINT, signal.SIGTERM)

    def __init__(self) -> None:
        self.received: list[int] = []
        self.previous: dict[int, Any] = {}
        self.raised = False
        self.previous_hook: Any = None

    def handle(self, signum: int, frame: FrameType | None) -> None:
        self.received.append(signum)
        if not self.raised:
            self.raised = True
            raise _Signalled(signum)

    def unraisable(self, unraisable: Any) -> None:
        """Deliver again a signal that a C library's callback swallowed.

        A signal that arrives while C code runs a Python callback (numba's
        compiler calls llvmlite's object-cache hook) raises inside the
        callback, where Python can only print "Exception ignored" with a
        traceback. The signal is sent again a moment later instead, to be
        raised where the command can clean up.
        """
        if isinstance(unraisable.exc_value, _Signalled):
            self.raised = False
            again = threading.Timer(0.005, os.kill, (os.getpid(), unraisable.exc_value.signum))
            again.daemon = True
            again.start()
        elif self.previous_hook is not None:
            self.previous_hook(unraisable)

    def install(self) -> None:
        with contextlib.suppress(ValueError):  # signal handlers only in the main thread
            for number in self.SIGNALS:
                self.previous[number] = signal.signal(number, self.handle)
            self.previous_hook = sys.unraisablehook
            sys.unraisablehook = self.unraisable

    def restore(self) -> None:
        for number, handler in self.previous.items():
            signal.signal(number, handler)
        if self.previous_hook is not None:
            sys.unraisablehook = self.previous_hook


class _ClosedStream:
    """Standard output when the process started without one: every write fails.

    A write that a caller swallowed (argparse's ``--help``) fails again at
    the next :meth:`flush`, once, so that :func:`main` reports it.
    """

    def __init__(self) -> None:
        self.failed = False

    def write(self, text: str) -> int:
        self.failed = True
        raise OSError(errno.EBADF, "closed")

    def flush(self) -> None:
        if self.failed:
            self.failed = False
            raise OSError(errno.EBADF, "closed")


def one_line_warnings(program: str) -> Callable[..., None]:
    """A ``warnings.showwarning`` that shows a library's warning as one line on stderr."""

    def show(
        message: Warning | str,
        category: type[Warning],
        filename: str,
        lineno: int,
        file: TextIO | None = None,
        line: str | None = None,
    ) -> None:
        with contextlib.suppress(OSError, ValueError):  # no internal file.py:line for users
            print(f"{program}: warning: {message}", file=sys.stderr)

    return show


def _silence_stdout() -> None:
    """Point stdout at /dev/null so that the flush at exit raises nothing more."""
    if isinstance(sys.stdout, _ClosedStream):
        sys.stdout = None
        return
    with contextlib.suppress(OSError, ValueError, AttributeError):  # as the Python docs advise
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
    """Run the command line with ``argv`` (default ``sys.argv[1:]``); return the exit status.

    Every :class:`~prp3.errors.Prp3Error` becomes one line on stderr and exit
    status 2; SIGINT and SIGTERM (also in bursts) one line and 130 or 143.
    Standard output is flushed before the status is returned, so that a
    failing one is reported too.
    """
    guard = _SignalGuard()
    guard.install()  # before anything else: a signal while the parser is built is one line too
    try:
        return _main(argv, guard)
    except _Signalled as signalled:  # while the options were parsed
        return _signalled(_program_of(build_parser(), _words(argv)), signalled.signum)
    finally:
        if argv is None:
            # the process is ending with the command's status: its outputs are whole, so a
            # signal now (interpreter shutdown, the threads of a library) changes nothing
            for number in guard.SIGNALS:
                with contextlib.suppress(ValueError):
                    signal.signal(number, signal.SIG_IGN)
        else:
            guard.restore()


def _words(argv: Sequence[str] | None) -> list[str]:
    return list(argv) if argv is not None else sys.argv[1:]


def _signalled(program: str, signum: int) -> int:
    """One line for a command stopped by ``signum``; its exit status (130 or 143)."""
    with contextlib.suppress(OSError, ValueError, AttributeError):
        name = "interrupted" if signum == signal.SIGINT else "terminated"
        print(f"{program}: {name}", file=sys.stderr)
    return EXIT_INTERRUPTED if signum == signal.SIGINT else EXIT_TERMINATED


def _main(argv: Sequence[str] | None, guard: _SignalGuard) -> int:
    if sys.stdout is None:  # started with standard output closed (`prp3 ... >&-`)
        sys.stdout = _ClosedStream()  # every write fails, as one error
    parser = build_parser()
    words = _words(argv)
    try:
        args = parser.parse_args(words)
    except SystemExit as exit_:
        if exit_.code == 0:  # --help, --version: their text must reach standard output
            try:
                _flush_stdout()
            except BrokenPipeError:  # `prp3 --help | head -n 1`
                _silence_stdout()
                raise SystemExit(141) from None
            except OutputFileError as error:
                _error(_program_of(parser, words), str(error))
                _silence_stdout()  # the flush at exit would fail again
                raise SystemExit(2) from None
        raise
    if getattr(args, "handler", None) is None:
        parser.print_help(sys.stderr)
        return 2
    program = str(getattr(args, "program", "prp3"))
    args.command_line = ["prp3", *words]  # recorded in the manifest of the output folder
    return _run(args, program, guard)


def _program_of(parser: argparse.ArgumentParser, words: Sequence[str]) -> str:
    """``prp3`` and the (sub)command names at the start of ``words`` (``prp3 export mjcf``)."""
    program = [parser.prog]
    current: argparse.ArgumentParser | None = parser
    for word in words:
        if current is None:
            break
        commands = [a for a in current._actions if isinstance(a, argparse._SubParsersAction)]
        current = commands[0].choices.get(word) if commands else None
        if current is not None:
            program.append(word)
    return " ".join(program)


def _error(program: str, text: str) -> None:
    with contextlib.suppress(OSError, ValueError, AttributeError):  # stderr may be gone too
        print(f"{program}: error: {text}", file=sys.stderr)


def _run(args: argparse.Namespace, program: str, guard: _SignalGuard) -> int:
    try:
        try:
            with warnings.catch_warnings():
                warnings.showwarning = one_line_warnings(program)
                status = int(args.handler(args))
            _flush_stdout()
            return status
        except KeyboardInterrupt:  # raised by a handler prp3 did not install
            raise _Signalled(signal.SIGINT) from None
        except Exception:
            if guard.received:  # the signal, wrapped by the code it stopped (an import's
                raise _Signalled(guard.received[0]) from None  # "initialization failed")
            raise
    except _Signalled as signalled:
        return _signalled(program, signalled.signum)
    except Prp3Error as error:
        _error(program, str(error))
        if error.origin == "standard output":
            _silence_stdout()  # the flush at exit would fail again
        return 2
    except BrokenPipeError:  # e.g. `prp3 robot --template | head -n 3`
        _silence_stdout()
        return 141
    except MemoryError as error:
        _error(program, f"not enough memory ({error}): ask for fewer samples or grid points")
        return 2
    except OSError as error:  # a file operation prp3 did not wrap: name its file if known
        where = f"{error.filename}: " if error.filename is not None else ""
        _error(program, f"{where}{error.strerror or error}")
        _silence_stdout()
        return 2


def _flush_stdout() -> None:
    """Flush standard output now (not at exit), turning a failure into a Prp3Error."""
    stream = sys.stdout
    if stream is None:
        return
    try:
        stream.flush()
    except BrokenPipeError:
        raise
    except (OSError, ValueError) as error:
        reason = getattr(error, "strerror", None) or str(error)
        raise OutputFileError(reason, origin="standard output") from None
