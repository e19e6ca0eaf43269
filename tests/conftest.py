"""Test configuration: hypothesis profiles and the import path of the shared helpers.

Profiles (choose with the environment variable ``PRP3_HYPOTHESIS_PROFILE``):

* ``default`` — 40 examples per property, no deadline, derandomized (the same
  examples on every run and every machine, so a CI failure reproduces locally)
  and no example database (nothing written to the working tree).
* ``thorough`` — 1000 random examples per property, for an occasional deep run:
  ``PRP3_HYPOTHESIS_PROFILE=thorough python -m pytest tests``.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest
from hypothesis import settings

# ``tests/strategies.py`` is a helper module imported by the test files
# (``from strategies import ...``); make it importable whatever the import mode.
_TESTS_DIR = str(Path(__file__).resolve().parent)
if _TESTS_DIR not in sys.path:
    sys.path.insert(0, _TESTS_DIR)

settings.register_profile(
    "default", max_examples=40, deadline=None, derandomize=True, database=None
)
settings.register_profile(
    "thorough", max_examples=1000, deadline=None, derandomize=False, database=None
)
settings.load_profile(os.environ.get("PRP3_HYPOTHESIS_PROFILE", "default"))


def pytest_configure(config: pytest.Config) -> None:
    """Keep a failing hypothesis test a plain failure under ``filterwarnings = error``.

    When hypothesis reports a falsifying example it touches
    ``mypy_extensions.TypedDict``, whose DeprecationWarning, turned into an error,
    aborts the whole session with an INTERNALERROR instead of showing the example.
    """
    config.addinivalue_line(
        "filterwarnings", "ignore:mypy_extensions.TypedDict is deprecated:DeprecationWarning"
    )


@pytest.fixture
def earlier_run(tmp_path: Path) -> Path:
    """An output directory holding the files of an earlier run (and a file of the user's)."""
    folder = tmp_path / "run"
    folder.mkdir()
    (folder / "results.csv").write_text("t,x\n0.0,1.0\n")
    (folder / "notes.txt").write_text("the user's own file\n")
    return folder
