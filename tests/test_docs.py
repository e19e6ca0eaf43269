"""The repository stands on its own, and its documents say what the code does.

* every output a document quotes after ``<!-- output of: COMMAND -->`` (the
  summaries of the commands, the tables of ``docs/examples/*.py``) is what
  COMMAND prints today, so that a quoted number cannot drift from the code;

* nothing in it sends the reader to a file it does not contain (the model and
  the data contract are ``docs/model.md``);
* the ``ROBOT.toml`` shown in ``docs/model.md`` is the one ``prp3 robot
  --template`` prints.
"""

from __future__ import annotations

import contextlib
import doctest
import io
import re
import runpy
import shlex
import sys
from pathlib import Path

import pytest

from prp3.cli import main
from prp3.model.robot import robot_template

ROOT = Path(__file__).resolve().parents[1]

#: Folders that are not the project's text (caches, builds, version control).
_SKIPPED = {".git", "__pycache__", ".pytest_cache", ".mypy_cache", ".ruff_cache", ".hypothesis",
            "build", "dist", "out"}  # fmt: skip

#: References to files outside the repository (written in two pieces so that
#: this file does not contain them).
_OUTSIDE = ("MODEL" + ".md", ".." + "/shared")


def _project_text_files() -> list[Path]:
    found = []
    for path in ROOT.rglob("*"):
        parts = set(path.relative_to(ROOT).parts)
        if parts & _SKIPPED or any(part.endswith(".egg-info") for part in parts):
            continue
        if path.is_file() and (
            path.suffix in {".py", ".md", ".toml", ".txt", ".csv", ".cfg"}
            or path.parent.name == ".ci"
        ):
            found.append(path)
    return found


def test_nothing_refers_to_a_file_outside_the_repository() -> None:
    files = _project_text_files()
    assert ROOT / "docs" / "model.md" in files and ROOT / "README.md" in files
    offending = [
        f"{path.relative_to(ROOT)}:{number}: {line.strip()}"
        for path in files
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), start=1)
        if any(reference in line for reference in _OUTSIDE)
    ]
    assert offending == []


def test_the_help_texts_point_at_docs_model_md() -> None:
    for command in (["robot", "--help"], ["simulate", "--help"]):
        out = io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.suppress(SystemExit):
            main(command)
        assert "docs/model.md" in out.getvalue(), command
        assert not any(reference in out.getvalue() for reference in _OUTSIDE)


def test_the_documented_template_is_the_printed_one() -> None:
    text = (ROOT / "docs" / "model.md").read_text(encoding="utf-8")
    section = text.split("### ROBOT.toml", 1)[1]
    documented = re.search(r"```toml\n(.*?)```", section, re.S)
    assert documented is not None
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        assert main(["robot", "--template"]) == 0
    assert documented[1] == printed.getvalue() == robot_template()


def test_the_readme_says_what_the_test_extra_installs() -> None:
    # was: silent about the ~1 GB of MuJoCo and Pinocchio the test command downloads
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    first = text.split("## ", 1)[0]  # before the first section: next to the two commands
    assert "MuJoCo and Pinocchio" in first and "GB" in first and "pyarrow" in first
    assert "numba" in first and "sympy" in first
    pyproject = (ROOT / "pyproject.toml").read_text(encoding="utf-8")
    test_extra = pyproject.split("test = [", 1)[1].split("]", 1)[0]
    assert all(name in test_extra for name in ('"mujoco', '"pin', '"pyarrow'))


# --- the numbers the documents quote come from commands the suite runs -------------------------

#: ``<!-- output of: COMMAND -->`` before a fenced block, a table or a paragraph: that text is
#: exactly what COMMAND prints (``...`` on a line of its own stands for any lines, as in doctest).
#: ``<!-- output of (numbers within a factor of N): COMMAND -->``: the same text, but each number
#: written with an exponent (``2.7e-7``) within a factor ``N`` of the printed one (the drift of an unstable motion, whose round-off
#: grows 10⁸-fold, differs from one numpy build to the next).
_MARKER = re.compile(
    r"^<!-- output of(?: \(numbers within a factor of (\d+)\))?: (.+?) -->\n", re.M
)
_NUMBER = re.compile(r"[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?")


def _documents() -> list[Path]:
    return [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def _quoted_outputs() -> list[tuple[str, str, str, float | None]]:
    """(document, command, quoted text, factor of its numbers or None) for every marker."""
    found = []
    for document in _documents():
        text = document.read_text(encoding="utf-8")
        for match in _MARKER.finditer(text):
            rest = text[match.end() :]
            if rest.startswith("```"):
                body = rest.split("\n", 1)[1].split("\n```", 1)[0] + "\n"
            else:
                body = rest.split("\n\n", 1)[0] + "\n"
            factor = float(match[1]) if match[1] else None
            found.append((str(document.relative_to(ROOT)), match[2], body, factor))
    return found


def _run_documented(command: str, folder: Path) -> str:
    """What ``command`` (``prp3 …`` or ``python docs/examples/NAME.py …``) prints in ``folder``."""
    argv = shlex.split(command)
    out = io.StringIO()
    with (
        contextlib.chdir(folder),
        contextlib.redirect_stdout(out),
        contextlib.redirect_stderr(io.StringIO()),
    ):
        if argv[0] == "prp3":
            main(argv[1:])
        else:
            assert argv[0] == "python" and argv[1].startswith("docs/examples/"), command
            figures = folder / "figures"
            figures.mkdir(exist_ok=True)
            saved = sys.argv
            script = ROOT / argv[1]
            extra = ["--figures", str(figures)] if "--figures" in script.read_text() else []
            sys.argv = [str(script), *argv[2:], *extra]
            try:
                runpy.run_path(str(ROOT / argv[1]), run_name="__main__")
            finally:
                sys.argv = saved
    return out.getvalue()


def _same(quoted: str, printed: str, factor: float | None = None) -> bool:
    if factor is not None:  # the same words; each number within the factor, of the same sign
        quoted_numbers, printed_numbers = _NUMBER.findall(quoted), _NUMBER.findall(printed)
        if _NUMBER.sub("#", quoted) != _NUMBER.sub("#", printed):
            return False  # the same words and as many numbers
        return all(
            a == b
            or (
                "e" in a
                and "e" in b
                and float(a) * float(b) > 0.0
                and max(float(a) / float(b), float(b) / float(a)) <= factor
            )
            for a, b in zip(quoted_numbers, printed_numbers, strict=True)
        )
    checker = doctest.OutputChecker()
    return checker.check_output(quoted, printed, doctest.ELLIPSIS)


#: ``<!-- measured by: COMMAND -->``: a measurement of the machine (not compared digit for digit).
_MEASURED = re.compile(r"^<!-- measured by: (.+?) -->\n```text\n(.*?)```", re.M | re.S)


#: Quoted outputs whose command another test runs piece by piece against the same text: the
#: command matrix's 21 rows (tests/test_command_matrix.py runs each row and compares it with its
#: literal table, and that table with docs/cli.md's), rather than running the whole script twice.
RUN_ELSEWHERE = {"python docs/examples/command_matrix.py": "tests/test_command_matrix.py"}


def test_every_script_of_docs_examples_is_quoted_by_a_document() -> None:
    measured = [m[1] for doc in _documents() for m in _MEASURED.finditer(doc.read_text("utf-8"))]
    commands = " ".join([*(command for _, command, _, _ in _quoted_outputs()), *measured])
    for script in sorted((ROOT / "docs" / "examples").glob("*.py")):
        assert f"docs/examples/{script.name}" in commands, script


@pytest.mark.slow  # the scripts of docs/examples run for 5-20 s each
@pytest.mark.parametrize(
    "document, command, quoted, factor",
    [quoted for quoted in _quoted_outputs() if quoted[1] not in RUN_ELSEWHERE],
    ids=[f"{d}: {c}" for d, c, _, _ in _quoted_outputs() if c not in RUN_ELSEWHERE],
)
def test_the_quoted_output_is_what_the_command_prints(
    document: str, command: str, quoted: str, factor: float | None, tmp_path: Path
) -> None:
    script = ROOT / shlex.split(command)[1] if command.startswith("python ") else None
    if script is not None and "\nimport mujoco\n" in script.read_text(encoding="utf-8"):
        pytest.importorskip("mujoco")
    printed = _run_documented(command, tmp_path)
    assert _same(quoted, printed, factor), (
        f"{document} quotes for `{command}`:\n{quoted}\nit prints:\n{printed}"
    )


def test_the_documents_show_the_inputs_their_scripts_use() -> None:
    # the spec of the worked synthesis and the true robot of the worked identification
    design = (ROOT / "docs" / "design.md").read_text(encoding="utf-8")
    spec = (ROOT / "docs" / "examples" / "synthesis.toml").read_text(encoding="utf-8")
    assert f"```toml\n{spec}```" in design
    identification = (ROOT / "docs" / "identification.md").read_text(encoding="utf-8")
    script = runpy.run_path(str(ROOT / "docs" / "examples" / "identification.py"))
    assert f"```toml\n{script['TRUE_TOML']}```" in identification


def test_a_changed_number_is_caught() -> None:
    # the comparison is exact but for "..." lines: a digit changed in the quoted text fails
    printed = "prp3 simulate: 301 samples\n  peak |f10| (N)  31.9618\nfiles written:\n  a\n  b\n"
    assert _same(printed, printed)
    assert _same("prp3 simulate: 301 samples\n...\nfiles written:\n...\n", printed)
    assert not _same(printed.replace("31.9618", "31.9619"), printed)
    # within a factor: the words and plain numbers exact, each number written with an exponent
    # within it (and of the same sign)
    assert _same("drift 2.7e-7 at t = 3 s\n", "drift 2.7e-8 at t = 3 s\n", 30.0)
    assert not _same("drift 2.7e-7 at t = 3 s\n", "drift 2.7e-9 at t = 3 s\n", 30.0)
    assert not _same("drift 2.7e-7 at t = 3 s\n", "drift -2.7e-7 at t = 3 s\n", 30.0)
    assert not _same("drift 2.7e-7 at t = 3 s\n", "drift 2.7e-7 at t = 4 s\n", 30.0)
    assert not _same("drift 2.7e-7 at t = 3 s\n", "slip 2.7e-7 at t = 3 s\n", 30.0)


def test_the_measured_size_of_the_test_extra_is_the_one_quoted(tmp_path: Path) -> None:
    # was: "about 0.6 GB", measured without numba and sympy (1.05 GB with them)
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    (command, quoted) = _MEASURED.search(text.split("## ", 1)[0]).groups()  # type: ignore[union-attr]
    assert command == "python docs/examples/extra_size.py"
    printed = _run_documented(command, tmp_path)
    pattern = (
        r"test extra: ([0-9.]+) GB installed beyond the base install, \d+ distributions \(GB: "
    )
    size = float(re.match(pattern, printed)[1])  # type: ignore[index]
    said = float(re.match(pattern, quoted)[1])  # type: ignore[index]
    assert f"about {said} GB" in text.split("## ", 1)[0]
    if "not installed" not in printed:  # the whole extra here: the README's size holds
        assert abs(size - said) <= 0.15 * said, printed


def _notation_names(heading: str) -> list[str]:
    """The backquoted names of the last column of the tables of a section of notation.md."""
    text = (ROOT / "docs" / "notation.md").read_text(encoding="utf-8")
    section = text.split(heading, 1)[1].split("\n## ", 1)[0]
    rows = [line for line in section.splitlines() if line.startswith("| ") and "---" not in line]
    return [name for row in rows[1:] for name in re.findall(r"`([^`]+)`", row.rsplit("|", 2)[1])]


def test_the_names_of_notation_md_exist() -> None:
    # was: Ĵ2, Ĵ3 said to be about the centres of mass; each name of prp3 there is checked here
    import dataclasses

    import prp3
    from prp3.mechanics import geometry, kinematics
    from prp3.mechanics.joint_motion import KernelGeometry
    from prp3.references import paper, paper_kinematics

    classes = {
        "InverseDynamics": prp3.InverseDynamics,
        "InverseGeometry": geometry.InverseGeometry,
        "KernelGeometry": KernelGeometry,
        "Motion": prp3.Motion,
        "Robot": prp3.Robot(),
    }
    checked = 0
    for heading in ("## Geometry and motion", "## Dynamics (eqs. 19–25)"):
        for name in _notation_names(heading):
            head, _, rest = name.partition(".")
            target = classes.get(head) or (prp3 if head == "prp3" else None)
            if target is None or not rest:
                continue
            for part in re.sub(r"\[.*\]$", "", rest).split("."):
                if isinstance(target, type) and dataclasses.is_dataclass(target):
                    fields = {f.name for f in dataclasses.fields(target)}
                    assert part in fields or hasattr(target, part), name
                    target = None
                    break
                target = getattr(target, part)
            checked += 1
    fields = {f.name for f in dataclasses.fields(kinematics.Kinematics)}
    for name in _notation_names("## Kinematics (eqs. 11–18)"):
        assert name in fields or (name == "jacobian" and hasattr(kinematics, name)), name
        checked += 1
    result = {f.name for f in dataclasses.fields(paper.RecursiveMatrixResult)}
    for name in _notation_names("## The paper as printed"):
        base = name.split("(")[0]
        if re.fullmatch(r"T\d|r0\^G", base):  # a frame, the paper's symbol of `centre`
            continue
        assert (
            base in result
            or hasattr(paper, base)
            or hasattr(paper_kinematics, base)
            or base == "inverse_dynamics"
        ), name
        checked += 1
    assert checked > 60
    text = (ROOT / "docs" / "notation.md").read_text(encoding="utf-8")
    assert "about their centres of mass |" not in text  # Ĵ2, Ĵ3 are about A2 and A3 (the paper)


def test_every_figure_of_the_documents_is_rebuilt_by_a_script() -> None:
    # was: docs/figures/synthesis_pareto.png marking an optimum no command found any more
    scripts = " ".join(
        p.read_text(encoding="utf-8") for p in (ROOT / "docs" / "examples").glob("*.py")
    )
    figures = sorted((ROOT / "docs" / "figures").glob("*.png"))
    assert figures
    for figure in figures:
        assert f'"{figure.name}"' in scripts, f"no script of docs/examples writes {figure.name}"


# --- the error messages docs/cli.md shows are the ones prp3 prints ----------------------------

#: Rows of the table that depend on the machine (its memory, a full disk or standard output).
_MACHINE_ROWS = {"a full disk while writing", "a run too big for the memory",
                 "standard output full or closed"}  # fmt: skip

_TRAJ = "t,x,y,phi\n0,0,0,0\n0.1,0,0,0\n0.2,0,0,0\n0.3,0,0,0\n"
_ERROR_CASES: dict[str, tuple[dict[str, str], list[str]]] = {
    "missing, unknown or misspelled column": (
        {"traj.csv": "t,x,y,phy\n0,0,0,0\n1,0,0,0\n"},
        ["simulate", "--trajectory", "traj.csv", "-o", "out"],
    ),
    "only some derivative columns": (
        {"traj.csv": "t,x,y,phi,dx,dy,dphi,ddx,ddy\n0,0,0,0,0,0,0,0,0\n1,0,0,0,0,0,0,0,0\n"},
        ["simulate", "--trajectory", "traj.csv", "-o", "out"],
    ),
    "non-numeric cell, NaN, inf": (
        {"traj.csv": "t,x,y,phi\n0,0,0,0\n0.1,0,0,0\n0.2,0,oops,0\n"},
        ["simulate", "--trajectory", "traj.csv", "-o", "out"],
    ),
    "row of the wrong length": (
        {"traj.csv": _TRAJ + "0.4,0,0,0\n0.5,0,0\n"},
        ["simulate", "--trajectory", "traj.csv", "-o", "out"],
    ),
    "time not increasing": (
        {"traj.csv": "t,x,y,phi\n0,0,0,0\n0.1,0,0,0\n0.2,0,0,0\n0.2,0,0,0\n"},
        ["simulate", "--trajectory", "traj.csv", "-o", "out"],
    ),
    "fewer than 2 samples": (
        {"traj.csv": "t,x,y,phi\n0,0,0,0\n"},
        ["simulate", "--trajectory", "traj.csv", "-o", "out"],
    ),
    "singular pose (`φ ≡ π/3 mod π`)": (
        {"traj.csv": "t,x,y,phi\n0,0,0,0\n0.1,0,0,0.5\n0.2,0,0,1.0471975511965976\n0.3,0,0,0\n"},
        ["simulate", "--trajectory", "traj.csv", "-o", "out"],
    ),
    "pose beyond the bounds (below)": (
        {
            "traj.csv": "t,x,y,phi,dx,dy,dphi,ddx,ddy,ddphi\n0,0,1000000.0,0,0,0,0,0,0,0\n0.5,0,1000000.0,0,0,0,0,0,0,0\n1,0,1000000.0,0,0,0,0,0,0,0\n"
        },
        ["simulate", "--trajectory", "traj.csv", "-o", "out"],
    ),
    "pose outside `[limits] stroke`": (
        {"r.toml": "[limits]\nstroke = [-0.01, 0.01]\n"},
        ["simulate", "--robot", "r.toml", "--motion", "vertical", "-o", "out"],
    ),
    "malformed TOML": (
        {"robot.toml": "mass=\n"},
        ["simulate", "--robot", "robot.toml", "--motion", "vertical", "-o", "out"],
    ),
    "invalid or unknown key": (
        {"robot.toml": "[platform]\nmass = -3.0\n"},
        ["simulate", "--robot", "robot.toml", "--motion", "vertical", "-o", "out"],
    ),
    "unreadable input file": ({}, ["simulate", "--trajectory", "none.csv", "-o", "out"]),
    "output directory not writable": (
        {"file.txt": "x"},
        ["simulate", "--motion", "vertical", "-o", "file.txt/out"],
    ),
    "results that overflow (absurd speeds: the sample's largest input named)": (
        {
            "big.csv": "t,x,y,phi,dx,dy,dphi,ddx,ddy,ddphi\n0,0,0,0,0,0,1e160,0,0,0\n1e-300,0,0,1e-140,0,0,1e160,0,0,0\n"
        },
        ["simulate", "--trajectory", "big.csv", "-o", "out"],
    ),
    "parameters whose inertias overflow": (
        {"big.toml": "l0 = 1e200\n"},
        ["simulate", "--robot", "big.toml", "--motion", "vertical", "-o", "out"],
    ),
    "a huge or binary input file": ({}, ["simulate", "--trajectory", "/dev/zero", "-o", "out"]),
    "a line longer than 64 KiB": (
        {"big.csv": "t,x,y,phi\n0,0,0,0\n" + "1" * 70000 + "\n"},
        ["simulate", "--trajectory", "big.csv", "-o", "out"],
    ),
    "TOML nested too deeply, numbers of 4300+ digits": (
        {"robot.toml": "[platform]\nmass = " + "1" * 4400 + "\n"},
        ["robot", "--check", "robot.toml"],
    ),
    "an output that would replace an input": (
        {"out/results.csv": _TRAJ},
        ["simulate", "--trajectory", "out/results.csv", "-o", "out"],
    ),
    "a folder or special file under an output's name": (
        {"out/results.csv/x": ""},
        ["simulate", "--motion", "vertical", "-o", "out"],
    ),
    "bad option": ({}, ["simulate", "--motion", "vertical", "--samples", "1", "-o", "out"]),
    "empty path": ({}, ["simulate", "--motion", "vertical", "-o", ""]),
    "`--frames` without `--animate`": (
        {},
        ["simulate", "--motion", "vertical", "--frames", "12", "-o", "out"],
    ),
    "a motion that crosses the singularity between two samples": (
        {
            "traj.csv": "t,x,y,phi,dx,dy,dphi,ddx,ddy,ddphi\n0,0.01,0,0,0,0,2,0,0,0\n"
            "0.2,0.01,0,0.4,0,0,2,0,0,0\n0.4,0.01,0,0.8,0,0,2,0,0,0\n0.6,0.01,0,1.2,0,0,2,0,0,0\n"
        },
        ["simulate", "--trajectory", "traj.csv", "-o", "out"],
    ),
    "`--pareto` or `--sensitivity` without `--plots`": (
        {"spec.toml": "designs = 2\n[parameters]\nl0 = [0.25, 0.3]\n[task]\nsamples = 5\n"},
        ["sweep", "--spec", "spec.toml", "--pareto", "l0,energy", "-o", "out"],
    ),
    "a misspelled option that hides a required one": (
        {},
        ["simulate", "--mot", "vertical", "-o", "out"],
    ),
    "load columns where they are not used": (
        {
            "load.csv": "t,x,y,phi,dx,dy,dphi,ddx,ddy,ddphi,fx,fy,mz\n"
            "0,0,0,0,0,0,0,0,0,0,0,0,0\n1,0,0,0,0,0,0,0,0,0,0,0,0\n"
        },
        [
            "control",
            "--controller",
            "computed-torque",
            "--plant",
            "prp3",
            "--trajectory",
            "load.csv",
            "-o",
            "out",
        ],
    ),
    "an integration that fails at once": (
        {"f.csv": "t,f10_A,f10_B,f10_C\n0,1e300,1e300,-1e300\n1,1e300,1e300,-1e300\n"},
        ["forward", "--forces", "f.csv", "-o", "out"],
    ),
}


def _error_rows() -> dict[str, str]:
    text = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
    section = text.split("## Errors", 1)[1].split("### Bounds", 1)[0]
    found = re.findall(r"^\| (.+?) \| `(prp3 .+)` \|$", section, re.M)
    return {what: message.replace("\\|", "|") for what, message in found}


def test_every_error_row_of_cli_md_is_checked() -> None:
    assert set(_error_rows()) - set(_ERROR_CASES) == _MACHINE_ROWS


@pytest.mark.parametrize("what", sorted(_ERROR_CASES))
def test_the_error_messages_of_cli_md_are_printed(
    what: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    files, argv = _ERROR_CASES[what]
    for name, content in files.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(content, encoding="utf-8")
    with contextlib.chdir(tmp_path):
        try:
            status = main(argv)
        except SystemExit as exit_:  # argparse
            status = int(exit_.code or 0)
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1, err
    assert _same(_error_rows()[what] + "\n", err[0] + "\n"), (_error_rows()[what], err[0])


_SWEEP_SPEC = 'designs = 2\n[task]\nmotions = ["vertical"]\n[parameters]\n'
_SWEEP_CASES = {
    "unknown key path": _SWEEP_SPEC + '"platfrom.mass" = [2.0, 4.0]\n',
    "`low > high`": _SWEEP_SPEC + '"platform.mass" = [4.0, 2.0]\n',
    "empty range": _SWEEP_SPEC + '"platform.mass" = []\n',
    "a range end that is no robot": _SWEEP_SPEC + '"platform.mass" = [-1.0, 2.0]\n',
    "unknown sampling": 'sampling = "sobol"\n' + _SWEEP_SPEC + '"platform.mass" = [2.0, 4.0]\n',
    "missing trajectory file": _SWEEP_SPEC.replace('"vertical"', '"path.csv"')
    + '"platform.mass" = [2.0, 4.0]\n',
    "a key quoted and bare": _SWEEP_SPEC + '"l0" = [0.25, 0.35]\nl0 = [0.2, 0.3]\n',
    "a key path quoted and dotted": _SWEEP_SPEC
    + '"platform.mass" = [2.0, 4.0]\nplatform.mass = [2.0, 5.0]\n',
}
#: Rows that need a machine on the network or an environment without the extra.
_SWEEP_UNCHECKED = {"unreachable scheduler", "missing extra"}


def _sweep_error_rows() -> dict[str, str]:
    text = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
    section = text.split("## `prp3 sweep` and `prp3 optimize`", 1)[1]
    return dict(re.findall(r"^\| (.+?) \| `(prp3 sweep: .+)` \|$", section, re.M))


def test_every_sweep_error_row_of_cli_md_is_checked() -> None:
    assert set(_sweep_error_rows()) - set(_SWEEP_CASES) == _SWEEP_UNCHECKED


@pytest.mark.parametrize("what", sorted(_SWEEP_CASES))
def test_the_sweep_error_messages_of_cli_md_are_printed(
    what: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    pytest.importorskip("distributed")
    (tmp_path / "sweep.toml").write_text(_SWEEP_CASES[what], encoding="utf-8")
    with contextlib.chdir(tmp_path):
        status = main(["sweep", "--spec", "sweep.toml", "-o", "out", "--workers", "1"])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1, err
    assert _same(_sweep_error_rows()[what] + "\n", err[0] + "\n"), err[0]
    assert not (tmp_path / "out").exists()  # nothing written


#: The packages a user imports besides ``prp3``: the figures (``prp3.plotting.<name>``), the
#: explorer's scenes (``prp3.explorer.<name>``), the paper's matrices as printed
#: (``prp3.references.<name>``) and the command line's ``main``.
_PUBLIC_PACKAGES = ("prp3.plotting", "prp3.explorer", "prp3.references", "prp3.cli")


def test_the_docs_import_public_names_only() -> None:
    # the documents, their doctests and the scripts of docs/examples: prp3.<name> only
    deep = re.compile(
        r"^\s*(?:>>> |\.\.\. )?(?:from (prp3\.[\w.]+) import|import (prp3\.[\w.]+))", re.M
    )
    shown = []
    for path in [*_documents(), *sorted((ROOT / "docs" / "examples").glob("*.py"))]:
        for match in deep.finditer(path.read_text(encoding="utf-8")):
            module = match.group(1) or match.group(2)
            if module not in _PUBLIC_PACKAGES:
                shown.append(f"{path.name}: {module}")
    assert shown == [], f"docs import from internal modules (use prp3.<name>): {shown}"
