"""Every command for every architecture (docs/cli.md): one table of what ``prp3`` does.

Runs, in a temporary folder, each command form of ``prp3`` (through ``prp3.cli.main``, as the
tests do) on the robot file of each architecture and actuation: the 3-PRP in its model form
(docs/model.md), the seven planar architectures in family form with every allowed actuation
(docs/family.md) and the three spatial robots (docs/spatial.md), each from ``prp3 robot
--template [--architecture A]``, with tiny sizes (a few samples, frames, grid points, designs,
one in-process Dask worker).  It prints a markdown table: ``ok`` (exit status 0), ``n.a.``
where the form has no meaning for that kind of robot and ``prp3`` refuses it in one line
(exit 2, see the footnotes), or the reason of a refusal in a few words.
``tests/test_docs.py`` runs it and compares its output with docs/cli.md;
``tests/test_command_matrix.py`` holds the expected cells.
"""

from __future__ import annotations

import contextlib
import csv
import importlib.util
import io
import logging
import os
import re
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

from prp3.cli import main as prp3_main

#: The family architectures and their allowed actuations (docs/family.md §3: the others
#: leave two passive P joints or start at a singularity, and are refused when read).
FAMILY = {
    "3-PRP": (1, 3),
    "3-RPR": (1, 2, 3),
    "3-RRR": (1, 2, 3),
    "3-PRR": (1, 2, 3),
    "3-PPR": (1, 2),
    "3-RPP": (2, 3),
    "3-RRP": (1, 3),
}
SPATIAL = ("6-UPS", "3-RPS", "3-RUU")

#: Footnotes of the cells ``n.a.``: why the form has no meaning for that kind of robot.
NOTES = {
    1: "the spatial robots have one route, Newton–Euler (every joint's wrench); "
    "`--method fast` and `--method paper` are the planar routes, refused by name in one line",
}

#: A refusal's one line -> the few words of the table (the first that matches).
REASONS = (
    (r"export urdf takes a spatial robot file", "refused: spatial robots only"),
    (r"pip install 'prp3\[(\w+)\]'", r"needs prp3[\1]"),
)


@dataclass(frozen=True)
class Row:
    """One architecture (and actuation) of the table and its robot file."""

    name: str
    kind: str  # "model", "family" or "spatial"
    architecture: str
    actuated: int = 0


@dataclass(frozen=True)
class Column:
    """One command form: its title, its arguments for a row, and when it is n.a."""

    title: str
    argv: Callable[[Row, Path], list[str]]
    not_applicable: Callable[[Row], int] = lambda row: 0  # the footnote, 0: applicable
    needs: str = ""  # a prerequisite of ``prepare``: "run", "excite" or "measured"


def rows() -> list[Row]:
    """The 21 rows: model form, 17 family robots, three spatial robots."""
    found = [Row("3-PRP (model form)", "model", "3-PRP")]
    for architecture, actuations in FAMILY.items():
        for a in actuations:
            found.append(Row(f"{architecture} a={a}", "family", architecture, a))
    found.extend(Row(name, "spatial", name) for name in SPATIAL)
    return found


def _robot(row: Row, folder: Path) -> str:
    return str(folder / "robot.toml")


def _motion(row: Row) -> list[str]:
    return ["--motion", "heave" if row.kind == "spatial" else "vertical", "--samples", "7"]


def _simulate(*options: str) -> Callable[[Row, Path], list[str]]:
    def argv(row: Row, folder: Path) -> list[str]:
        out = str(folder / "simulate")
        return ["simulate", "--robot", _robot(row, folder), *_motion(row), *options, "-o", out]

    return argv


def _spatial(row: Row) -> int:
    return 1 if row.kind == "spatial" else 0


def _workspace(statics: bool) -> Callable[[Row, Path], list[str]]:
    def argv(row: Row, folder: Path) -> list[str]:
        size = (
            ["--points", "9"] if row.kind == "spatial" else ["--points", "9", "--orientations", "3"]
        )
        extra = ["--statics"] if statics else []
        return [
            "workspace",
            "--robot",
            _robot(row, folder),
            *size,
            *extra,
            "-o",
            str(folder / "ws"),
        ]

    return argv


def _forward(row: Row, folder: Path) -> list[str]:
    if row.kind == "spatial":
        efforts = ["--efforts", "hold", "--duration", "0.02"]
    else:
        efforts = ["--forces", str(folder / "run" / "results.csv")]
    return ["forward", "--robot", _robot(row, folder), *efforts, "-o", str(folder / "fwd")]


def _control(plant: str) -> Callable[[Row, Path], list[str]]:
    def argv(row: Row, folder: Path) -> list[str]:
        if row.kind == "spatial":
            motion = ["--motion", "heave", "--duration", "0.02"]
        else:
            motion = ["--trajectory", str(folder / "short.csv")]
        law = ["--plant", plant, "--controller", "computed-torque", "--rate", "200"]
        return ["control", "--robot", _robot(row, folder), *motion, *law, "-o", str(folder / "ctl")]

    return argv


def _study(command: str) -> Callable[[Row, Path], list[str]]:
    def argv(row: Row, folder: Path) -> list[str]:
        spec = folder / "spec.toml"
        spec.write_text(sweep_spec(row), encoding="utf-8")
        out = str(folder / command)
        return [command, "--spec", str(spec), "-o", out, "--scheduler", SCHEDULER[0]]

    return argv


def _explore(results: bool) -> Callable[[Row, Path], list[str]]:
    def argv(row: Row, folder: Path) -> list[str]:
        extra = ["--results", str(folder / "run")] if results else []
        page = str(folder / "page.html")
        return ["explore", "--robot", _robot(row, folder), *extra, "--export", page]

    return argv


def _excite(row: Row, folder: Path) -> list[str]:
    sizes = ["--samples", "121", "--iterations", "1"]
    return ["excite", "--robot", _robot(row, folder), *sizes, "-o", str(folder / "ex")]


def _identify(row: Row, folder: Path) -> list[str]:
    measured = str(folder / "measured.csv")
    return [
        "identify",
        "--robot",
        _robot(row, folder),
        "--measurements",
        measured,
        "-o",
        str(folder / "id"),
    ]


COLUMNS = (
    Column("robot --check", lambda row, f: ["robot", "--check", _robot(row, f)]),
    Column("simulate fast", _simulate("--method", "fast"), _spatial),
    Column("simulate paper", _simulate("--method", "paper"), _spatial),
    Column("simulate newton-euler", _simulate("--method", "newton-euler")),
    Column("--plots", _simulate("--plots")),
    Column("--animate", _simulate("--animate", "--frames", "2")),
    Column(
        "--html", lambda row, folder: _simulate("--html", str(folder / "run.html"))(row, folder)
    ),
    Column("workspace --statics", _workspace(True)),
    Column("forward", _forward, needs="run"),
    Column(
        "export c", lambda row, f: ["export", "c", "--robot", _robot(row, f), "-o", str(f / "c")]
    ),
    Column(
        "export mjcf",
        lambda row, f: ["export", "mjcf", "--robot", _robot(row, f), "-o", str(f / "m.xml")],
    ),
    Column(
        "export urdf",
        lambda row, f: ["export", "urdf", "--robot", _robot(row, f), "-o", str(f / "u.urdf")],
    ),
    Column("excite", _excite, needs="excite"),
    Column("identify", _identify, needs="measured"),
    Column("control prp3", _control("prp3")),
    Column("control mujoco", _control("mujoco")),
    Column("sweep", _study("sweep")),
    Column("optimize", _study("optimize")),
    Column("explore --export", _explore(False)),
    Column("explore --results", _explore(True), needs="run"),
)

#: The address of the in-process Dask scheduler of the sweeps (set by ``main``).
SCHEDULER = [""]


def sweep_spec(row: Row) -> str:
    """A SWEEP.toml of two designs of the row's robot on a short task (docs/design.md)."""
    head = 'designs = 2\nsampling = "lhs"\nseed = 1\n'
    optimize = '[optimize]\nobjective = "{}"\nmaxiter = 1\npopsize = 2\n'
    if row.kind == "model":
        task = '[task]\nmotions = ["vertical"]\nsamples = 11\n'
        body = '[parameters]\n"platform.mass" = [2.5, 3.5]\n' + task
        return head + body + optimize.format("peak_f10")
    if row.kind == "family":
        task = '[task]\nmotions = ["vertical"]\nsamples = 11\n'
        study = f'[[study]]\narchitecture = "{row.architecture}"\nactuated = {row.actuated}\n'
        body = task + study + '[study.parameters]\n"platform.mass" = [2.5, 3.5]\n'
        return head + body + optimize.format("peak_joint_force")
    task = '[task]\nmotions = ["heave"]\nsamples = 11\n'
    body = (
        f'spatial = "{row.architecture}"\n' + head + '[parameters]\n"platform.mass" = [0.5, 2.0]\n'
    )
    return body + task + optimize.format("peak_joint_force")


def run(argv: list[str]) -> tuple[int, str]:
    """``prp3 argv`` in-process: (exit status, its last line on stderr)."""
    err = io.StringIO()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
        try:
            status = prp3_main(argv)
        except SystemExit as exit_:  # argparse's usage errors
            status = int(exit_.code or 0)
        except Exception as error:  # a traceback: a bug, named in the cell
            return 99, f"crash: {type(error).__name__}"
    lines = [line for line in err.getvalue().splitlines() if line.strip()]
    return status, lines[-1] if lines else ""


def reason(line: str) -> str:
    """The few words of a refusal's one line."""
    for pattern, words in REASONS:
        match = re.search(pattern, line, re.I)
        if match:
            return match.expand(words)
    message = re.sub(r"^prp3 [\w ]+: error: ", "", line)
    message = re.sub(r"^\S+\.(toml|csv|html)(:\d+)*: ", "", message)
    return " ".join(message.split()[:6]).replace("|", "/")


def robot_file(row: Row) -> str:
    """The row's robot file: ``prp3 robot --template [--architecture A]``, its actuation set."""
    template = ["robot", "--template"]
    if row.kind != "model":
        template += ["--architecture", row.architecture]
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        prp3_main(template)
    if row.kind != "family":
        return out.getvalue()
    return re.sub(r"^actuated = \d", f"actuated = {row.actuated}", out.getvalue(), flags=re.M)


def prepare(row: Row, folder: Path) -> dict[str, tuple[int, str]]:
    """The robot file, a short trajectory and the runs other cells read: name -> (status, line).

    ``run``: a ``prp3 simulate`` folder (for ``forward`` and ``explore --results``);
    ``excite``: ``prp3 excite`` (its cell); ``measured``: ``measured.csv``, the exciting motion
    and its efforts by ``prp3 simulate`` (for ``identify``).
    """
    (folder / "robot.toml").write_text(robot_file(row), encoding="utf-8")
    times = [0.02 * k for k in range(6)]
    rows_ = "".join(f"{t},0,{0.01 * t},0\n" for t in times)
    (folder / "short.csv").write_text("t,x,y,phi\n" + rows_, encoding="utf-8")
    robot = str(folder / "robot.toml")
    if row.kind == "spatial":
        motion = ["--motion", "heave", "--samples", "7"]
    else:
        motion = ["--trajectory", str(folder / "short.csv")]
    done = {"run": run(["simulate", "--robot", robot, *motion, "-o", str(folder / "run")])}
    done["excite"] = run(_excite(row, folder))
    done["measured"] = _measured(row, folder) if done["excite"][0] == 0 else (1, "")
    return done


def _measured(row: Row, folder: Path) -> tuple[int, str]:
    """``measured.csv``: the motion of ``prp3 excite`` and its efforts by ``prp3 simulate``."""
    trajectory = folder / "ex" / "trajectory.csv"
    argv = ["simulate", "--robot", str(folder / "robot.toml"), "--trajectory", str(trajectory)]
    done = run([*argv, "-o", str(folder / "msim")])
    if done[0] != 0:
        return done
    motion = list(csv.reader(trajectory.read_text().splitlines()))
    results = list(csv.reader((folder / "msim" / "results.csv").read_text().splitlines()))
    effort = r"f10_[ABC]" if row.kind == "model" else r"tau_(\d+|[ABC])"
    picked = [k for k, name in enumerate(results[0]) if re.fullmatch(effort, name)]
    with (folder / "measured.csv").open("w", newline="") as stream:
        writer = csv.writer(stream)
        for line, result in zip(motion, results, strict=True):
            writer.writerow(line + [result[k] for k in picked])
    return done


def words(status: int, line: str) -> str:
    """A cell's text for an exit status and the last line on stderr."""
    if status == 0:
        return "ok"
    if status == 1:
        return "stopped early"
    return reason(line) if status == 2 else f"{line} (exit {status})"


def cell(row: Row, column: Column, folder: Path, done: dict[str, tuple[int, str]]) -> str:
    """What the command form does for the row: ok, n.a. (footnote), or the refusal's words."""
    if column.title in ("sweep", "optimize") and not SCHEDULER[0]:
        return "dask not installed"
    if column.title == "control mujoco" and importlib.util.find_spec("mujoco") is None:
        return "mujoco not installed"
    if column.needs == column.title:  # the run of ``prepare`` is the cell's
        return words(*done[column.needs])
    if column.needs and done[column.needs][0] != 0:
        return f"needs {column.needs}"
    status, line = run(column.argv(row, folder))
    note = column.not_applicable(row)
    if note:
        return f"n.a.{'¹²'[note - 1]}" if status == 2 else f"exit {status} (n.a.{note})"
    return words(status, line)


def table(selected: list[Row] | None = None) -> list[str]:
    """The markdown table (of every row, or of ``selected``), one line per row."""
    lines = ["| robot | " + " | ".join(c.title for c in COLUMNS) + " |"]
    lines.append("|---" * (len(COLUMNS) + 1) + "|")
    for row in rows() if selected is None else selected:
        with tempfile.TemporaryDirectory() as name:
            folder = Path(name)
            done = prepare(row, folder)
            cells = []
            for column in COLUMNS:
                start = time.perf_counter()
                cells.append(cell(row, column, folder, done))
                if os.environ.get("MATRIX_TIMES"):
                    spent = time.perf_counter() - start
                    print(f"{row.name}: {column.title} {spent:.2f} s", file=sys.__stderr__)
        lines.append(f"| {row.name} | " + " | ".join(cells) + " |")
    return lines


@contextlib.contextmanager
def scheduler() -> Iterator[None]:
    """An in-process Dask cluster of one worker thread for the sweeps (none without dask)."""
    if importlib.util.find_spec("distributed") is None:
        yield
        return
    from dask.distributed import LocalCluster

    with LocalCluster(
        n_workers=1,
        threads_per_worker=1,
        processes=False,
        dashboard_address=None,
        scheduler_kwargs={"dashboard": False, "dashboard_address": ":0"},  # no port 8787
        silence_logs=logging.ERROR,
    ) as cluster:
        SCHEDULER[0] = cluster.scheduler_address
        try:
            yield
        finally:
            SCHEDULER[0] = ""


def main() -> None:
    if "--notes" in sys.argv[1:]:  # the footnotes of the table
        for number, text in NOTES.items():
            print(f"{'¹²'[number - 1]} {text}.")
        return
    with scheduler():
        print("\n".join(table()))


if __name__ == "__main__":
    main()
