"""Helpers of the command-line tests: run ``prp3`` in-process, read an output folder.

Imported by the test files as ``from clitools import cli, listing, one_line``
(``tests/`` is on ``sys.path``, see ``conftest.py``).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from prp3.cli import main


def cli(capsys: pytest.CaptureFixture[str], *argv: object) -> tuple[int, str, str]:
    """Run ``prp3 argv`` in-process; return (exit status, stdout, stderr)."""
    try:
        status = main([str(a) for a in argv])
    except SystemExit as exit_:  # argparse: --help, --version, usage errors
        status = int(exit_.code or 0)
    out, err = capsys.readouterr()
    return status, out, err


def one_line(err: str) -> str:
    """The one line of an error report (and no traceback)."""
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    return lines[0]


def listing(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder`` (hidden ones included) with its content."""
    return {
        str(path.relative_to(folder)): path.read_bytes()
        for path in sorted(folder.rglob("*"))
        if path.is_file()
    }
