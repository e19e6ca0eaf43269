"""Run ``prp3`` with a folder made read-only for real, in a mount namespace of its own.

Not a test module.  The tests of a read-only output folder used to skip as root (root
writes through ``chmod 0o555``), that is on this machine and in CI.  Here the folder is
bind-mounted over itself and remounted read-only inside ``unshare --map-root-user
--mount``, so the kernel refuses every write (``EROFS``) whoever runs the command; the
mount vanishes with the process.  Where user namespaces are not allowed the tests skip
with :data:`NAMESPACES`'s one-line reason.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

_SCRIPT = r"""
import contextlib, io, json, subprocess, sys
locked, argv = sys.argv[1], sys.argv[2:]
subprocess.run(["mount", "--bind", locked, locked], check=True)
subprocess.run(["mount", "-o", "remount,bind,ro", locked], check=True)
from prp3.cli import main
err = io.StringIO()
with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
    try:
        status = main(argv)
    except SystemExit as stop:
        status = stop.code if isinstance(stop.code, int) else 1
print(json.dumps({"status": status, "stderr": err.getvalue()}))
"""


def namespaces_allowed() -> bool:
    """Whether ``unshare --map-root-user --mount`` runs here (user and mount namespaces)."""
    if shutil.which("unshare") is None:
        return False
    try:
        done = subprocess.run(
            ["unshare", "--map-root-user", "--mount", "true"], capture_output=True, timeout=10
        )
    except (OSError, subprocess.SubprocessError):
        return False
    return done.returncode == 0


NAMESPACES = pytest.mark.skipif(
    not namespaces_allowed(), reason="user and mount namespaces are not allowed here"
)


def run_read_only(locked: Path, *argv: object, cwd: Path | None = None) -> tuple[int, str]:
    """``prp3 argv`` with the folder ``locked`` read-only: (exit status, stderr)."""
    done = subprocess.run(
        ["unshare", "--map-root-user", "--mount", sys.executable, "-c", _SCRIPT,
         str(locked), *(str(a) for a in argv)],
        capture_output=True, text=True, timeout=300, cwd=cwd,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout.strip().splitlines()[-1])
    return int(report["status"]), str(report["stderr"])
