"""The project's data-contract checker, ``../shared/checks/contract.py``, holds.

The checker lives outside the repository (beside it, in the shared folder of
the project); it runs the installed ``prp3`` on the contract of MODEL.md.  The
test is skipped cleanly where the file does not exist (e.g. a fresh clone on
its own).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CHECKER = ROOT / ".." / "shared" / "checks" / "contract.py"


@pytest.mark.skipif(not CHECKER.is_file(), reason="../shared/checks/contract.py not present")
def test_contract_checker_holds():
    done = subprocess.run(
        [sys.executable, str(CHECKER)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.strip().splitlines()[-1] == "contract: holds", done.stdout
