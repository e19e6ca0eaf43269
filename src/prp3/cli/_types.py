"""Pieces shared by the subcommands: argparse value types (one-line errors, exit 2),
the ``--robot`` and ``--output DIR`` options and loading the robot.

>>> finite_float("0.5"), positive_float("1e-10"), integer_at_least(2)("301")
(0.5, 1e-10, 301)
>>> finite_float("nan")
Traceback (most recent call last):
...
argparse.ArgumentTypeError: expected a finite number, got 'nan'
"""

from __future__ import annotations

import argparse
import contextlib
import math
import sys
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, TypedDict

from prp3.analysis.forward import MAX_EVALUATIONS, MAX_SECONDS
from prp3.errors import OutputFileError, ParameterError, Prp3Error
from prp3.model.robot import Robot
from prp3.staged_files import MANIFEST_NAME, StagedOutput, staged_output

if TYPE_CHECKING:
    from prp3.family import FamilyRobot
    from prp3.io.spatial_robot import SpatialRobotFile

__all__ = [
    "ForwardBounds",
    "add_forward_bounds",
    "add_output_directory",
    "add_robot_option",
    "bound_stopped",
    "emit",
    "files_report",
    "finite_float",
    "forward_bounds",
    "input_paths",
    "integer_at_least",
    "load_any_robot",
    "load_robot_or_spatial",
    "output_folder",
    "path_name",
    "positive_float",
    "spatial_refusal",
]


def finite_float(text: str) -> float:
    """A finite float."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return value


def positive_float(text: str) -> float:
    """A finite float > 0."""
    value = finite_float(text)
    if value <= 0.0:
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}")
    return value


def integer_at_least(minimum: int, maximum: int = 10**9) -> Callable[[str], int]:
    """The type of an integer option from ``minimum`` to ``maximum``.

    The upper bound keeps absurd sizes (``--samples 1e20``) a usage error
    rather than a failed allocation.

    >>> integer_at_least(2, 10)("11")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: expected an integer from 2 to 10, got '11'
    """

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            value = minimum - 1
        if value < minimum:
            raise argparse.ArgumentTypeError(f"expected an integer >= {minimum}, got {text!r}")
        if value > maximum:
            raise argparse.ArgumentTypeError(
                f"expected an integer from {minimum} to {maximum}, got {text!r}"
            )
        return value

    return parse


def add_forward_bounds(parser: argparse.ArgumentParser) -> None:
    """Add ``--max-evaluations N`` and ``--max-seconds S``: the bounds of a forward integration
    (``max_evaluations``, ``max_seconds`` of :func:`prp3.forward_dynamics`,
    :func:`prp3.family_forward_dynamics` and :func:`prp3.spatial_forward_dynamics`)."""
    parser.add_argument(
        "--max-evaluations",
        metavar="N",
        type=integer_at_least(1, 10**12),
        help=f"stop the integration after N evaluations of the equations of motion, an "
        f"integer from 1 to 10^12 (default {MAX_EVALUATIONS}): one line, exit 2, nothing written",
    )
    parser.add_argument(
        "--max-seconds",
        metavar="S",
        type=positive_float,
        help=f"stop the integration after S seconds of wall time, a positive number "
        f"(default {MAX_SECONDS:g}): one line, exit 2, nothing written",
    )


class ForwardBounds(TypedDict):
    """The bounds of a forward integration, as keyword arguments."""

    max_evaluations: int
    max_seconds: float


def forward_bounds(args: argparse.Namespace) -> ForwardBounds:
    """The keyword arguments ``max_evaluations``, ``max_seconds`` of ``--max-evaluations`` and
    ``--max-seconds`` (their defaults when not given).

    >>> forward_bounds(argparse.Namespace(max_evaluations=300, max_seconds=None))
    {'max_evaluations': 300, 'max_seconds': 600.0}
    """
    evaluations = MAX_EVALUATIONS if args.max_evaluations is None else args.max_evaluations
    seconds = MAX_SECONDS if args.max_seconds is None else args.max_seconds
    return ForwardBounds(max_evaluations=evaluations, max_seconds=seconds)


def bound_stopped(error: Prp3Error, args: argparse.Namespace) -> Prp3Error | None:
    """A forward integration's ``error`` laid to the option of the bound that stopped it
    (``--max-evaluations N`` or ``--max-seconds S``, ``(the default)`` when not given); None
    for another error.

    >>> from prp3.errors import TrajectoryError
    >>> stop = TrajectoryError("the integration was stopped by its bound max_evaluations = 300",
    ...                        file="f.csv", subject="forward dynamics")
    >>> print(bound_stopped(stop, argparse.Namespace(max_evaluations=300, max_seconds=None)))
    --max-evaluations 300: forward dynamics: the integration was stopped by its bound max_evaluations = 300
    """
    bounds = forward_bounds(args)
    for name in ("max_evaluations", "max_seconds"):
        if f"stopped by its bound {name} = " in error.reason:
            option = "--" + name.replace("_", "-")
            default = " (the default)" if getattr(args, name) is None else ""
            origin = f"{option} {bounds[name]!r}{default}"
            return error.located(file=None, line=None, origin=origin)
    return None


def path_name(text: str) -> Path:
    """A non-empty path (``--output ""`` would otherwise mean the current directory).

    >>> path_name("")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: expected a path, got an empty string
    """
    if not text.strip():
        raise argparse.ArgumentTypeError(
            f"expected a path, got {'an empty string' if not text else repr(text)}"
        )
    return Path(text)


def add_robot_option(parser: argparse.ArgumentParser, note: str = "") -> None:
    """Add ``--robot ROBOT.toml`` (default: the paper's robot)."""
    parser.add_argument(
        "--robot",
        metavar="ROBOT.toml",
        type=path_name,
        help=f"robot parameters (default: the paper's robot{note})",
    )


#: What a command that runs planar robots only says of a spatial robot file.
SPATIAL_COMMANDS_NOTE = (
    "docs/spatial.md §13: prp3 simulate, forward, workspace, control, identify, excite, "
    "export mjcf, export urdf, export c, explore and robot --check take it, and sweep and optimize a spec "
    "with spatial = ..."
)


def spatial_refusal(args: argparse.Namespace, robot: SpatialRobotFile) -> ParameterError:
    """The refusal, by capability, of a spatial robot file in a command that runs the planar
    robots only."""
    return ParameterError(
        f"{args.program} computes the planar robots only, not yet the {robot.architecture} "
        f"of a spatial robot file ({SPATIAL_COMMANDS_NOTE})",
        file=args.robot,
    )


def load_any_robot(args: argparse.Namespace) -> Robot | FamilyRobot:
    """The robot of ``--robot`` in either form (docs/family.md §1), or the paper's robot.

    For the commands that run a family-form robot their own way; an error in the file
    names it.
    """
    if args.robot is None:
        return Robot()
    from prp3.io.spatial_robot import SpatialRobotFile, read_any_robot

    try:
        robot = read_any_robot(args.robot)
    except ParameterError as error:
        raise error.located(file=args.robot) from None
    if isinstance(robot, SpatialRobotFile):
        raise spatial_refusal(args, robot)
    return robot


def load_robot_or_spatial(args: argparse.Namespace) -> Robot | FamilyRobot | SpatialRobotFile:
    """The robot of ``--robot`` in any form, spatial included (``prp3 simulate``), or the
    paper's robot."""
    if args.robot is None:
        return Robot()
    from prp3.io.spatial_robot import read_any_robot

    try:
        return read_any_robot(args.robot)
    except ParameterError as error:
        raise error.located(file=args.robot) from None


def add_output_directory(parser: argparse.ArgumentParser) -> None:
    """Add the required ``--output/-o DIR``."""
    parser.add_argument(
        "--output",
        "-o",
        metavar="DIR",
        type=path_name,
        required=True,
        help="output directory, created if missing; files of the same name are replaced",
    )


def command_name(args: argparse.Namespace) -> str:
    """The subcommand that was run, as the manifest keys it: ``simulate``, ``export c``."""
    program = str(getattr(args, "program", "prp3"))
    return program.removeprefix("prp3").strip() or "prp3"


def input_paths(args: argparse.Namespace) -> list[Path]:
    """The input files of a run: the values of its path options (``--robot``, ``--trajectory``...).

    Every option parsed by :func:`path_name` but ``--output``, in the order of ``args``.

    >>> input_paths(argparse.Namespace(robot=Path("r.toml"), output=Path("out"), samples=3))
    [PosixPath('r.toml')]
    """
    return [
        value for name, value in vars(args).items() if isinstance(value, Path) and name != "output"
    ]


@contextlib.contextmanager
def output_folder(
    args: argparse.Namespace,
    directory: str | Path,
    inputs: Sequence[str | Path | None] | None = None,
) -> Iterator[StagedOutput]:
    """:func:`prp3.staged_files.staged_output` for a subcommand: its record in the manifest, a note.

    The manifest records the subcommand, its command line (``args.command_line``,
    set by :func:`prp3.cli.main`) and the SHA-256 of ``inputs`` (default:
    every path option of ``args`` but ``--output``, :func:`input_paths`).  After the
    files are moved in, one note on stderr names the files of the same
    subcommand's earlier run that were removed (the files of other
    subcommands in the folder are kept).
    """
    command = command_name(args)
    inputs = input_paths(args) if inputs is None else inputs
    line = getattr(args, "command_line", None) or ["prp3", *command.split()]
    with staged_output(directory, command=command, command_line=line, inputs=inputs) as staged:
        yield staged
    if staged.removed:
        names = ", ".join(path.name for path in staged.removed)
        count = len(staged.removed)
        print(
            f"{args.program}: note: removed {count} file{'s' if count > 1 else ''} that the "
            f"last `prp3 {command}` wrote into {staged.directory} and this run did not write "
            f"again ({names}); files of other commands are kept",
            file=sys.stderr,
        )


def files_report(staged: StagedOutput) -> list[str]:
    """The lines of a summary that say which files a run writes and removes.

    Known before the files are moved in (the summary is printed first): the
    files of the same command's earlier run in the folder (its record in the
    manifest, ``DIR/.prp3-manifest.json``) that this run does not write again
    are removed and listed; those changed since are kept and listed.  Files
    of other commands are not touched.
    """
    lines = ["files written:", *(f"  {path}" for path in staged.targets)]
    removed = staged.stale()
    if removed:
        lines += [
            f"files removed (the last run of this command wrote them, {MANIFEST_NAME}; "
            "not written again):",
            *(f"  {path}" for path in removed),
        ]
    kept = staged.changed()
    if kept:
        lines += [
            "files kept (the last run of this command wrote them, but they have changed since):",
            *(f"  {path}" for path in kept),
        ]
    return lines


def emit(text: str, end: str = "\n") -> None:
    """Print ``text`` and ``end`` on standard output, flushed now.

    Flushing here, not at exit, makes a failing standard output (a full disk,
    a closed descriptor) an error of the run, reported in one line, before
    the run's files are moved in.

    Raises
    ------
    OutputFileError
        ``standard output: <reason>`` when it is closed or cannot be written.
    BrokenPipeError
        When the reader went away (``prp3 ... | head``): the command line
        then exits quietly.
    """
    stream = sys.stdout
    if stream is None:
        raise OutputFileError("closed", origin="standard output")
    try:
        stream.write(text + end)
        stream.flush()
    except BrokenPipeError:
        raise
    except (OSError, ValueError) as error:  # ValueError: a closed file object
        reason = getattr(error, "strerror", None) or str(error)
        raise OutputFileError(reason, origin="standard output") from None


def check_extent(extent: Sequence[float]) -> tuple[float, float, float, float]:
    """``--extent XMIN XMAX YMIN YMAX`` as four floats, refused unless ``XMIN < XMAX`` and
    ``YMIN < YMAX``."""
    xmin, xmax, ymin, ymax = extent
    if not (xmin < xmax and ymin < ymax):
        raise ParameterError(
            f"--extent must be XMIN XMAX YMIN YMAX with XMIN < XMAX and YMIN < YMAX, got "
            f"{' '.join(repr(v) for v in extent)}"
        )
    return xmin, xmax, ymin, ymax
