"""An external checker of the command line's data contract holds.

The data contract (``docs/model.md``, "Data contract of the command line") is
checked by an independent program, kept outside the repository, that runs the
installed ``prp3``: the column names and order of ``results.csv``, the time
span of the paper's motions, the refusal of a singular trajectory and of a
negative mass without a traceback and without an output file.  Give its path
in ``PRP3_CONTRACT_CHECKER``; by default the test looks for
``shared/checks/contract.py`` in the folder that holds the checkout (where the
project's development machines keep it).  Without a checker the test is
skipped, saying what it needs.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def contract_checker() -> Path | None:
    """The checker given by ``PRP3_CONTRACT_CHECKER``, else the one beside the checkout."""
    given = os.environ.get("PRP3_CONTRACT_CHECKER")
    candidate = Path(given) if given else ROOT.parent / "shared" / "checks" / "contract.py"
    return candidate if candidate.is_file() else None


CHECKER = contract_checker()

SKIP_REASON = (
    "no external checker of the data contract of docs/model.md: set PRP3_CONTRACT_CHECKER "
    "to the path of contract.py (it runs the installed prp3 and prints 'contract: holds')"
)


@pytest.mark.skipif(CHECKER is None, reason=SKIP_REASON)
def test_contract_checker_holds() -> None:
    assert CHECKER is not None
    done = subprocess.run(
        [sys.executable, str(CHECKER)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.strip().splitlines()[-1] == "contract: holds", done.stdout


def test_the_skip_message_names_what_is_needed() -> None:
    # in the project's own terms: its docs, the variable to set, nothing outside the repository
    assert "docs/model.md" in SKIP_REASON and "PRP3_CONTRACT_CHECKER" in SKIP_REASON
    assert "shared" not in SKIP_REASON and "MODEL" not in SKIP_REASON
    assert (ROOT / "docs" / "model.md").is_file()
