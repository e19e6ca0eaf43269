"""The repository stands on its own, and its documents say what the code does.

* nothing in it sends the reader to a file it does not contain (the model and
  the data contract are ``docs/model.md``);
* the ``ROBOT.toml`` shown in ``docs/model.md`` is the one ``prp3 robot
  --template`` prints.
"""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

from prp3.cli import main
from prp3.model import robot_template

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
    pyproject = (ROOT / "pyproject.toml").read_text(encoding="utf-8")
    test_extra = pyproject.split("test = [", 1)[1].split("]", 1)[0]
    assert all(name in test_extra for name in ('"mujoco', '"pin', '"pyarrow'))
