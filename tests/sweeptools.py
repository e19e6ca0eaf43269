"""Helpers of the sweep tests (3-PRP, family and spatial specs): a sweep interrupted part way.

Imported by the test files as ``from sweeptools import ...`` (``tests/`` is on ``sys.path``,
see ``conftest.py``, which also holds the ``scheduler`` fixture: an in-process Dask cluster).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from clitools import cli


def interrupted_sweep(
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    argv: tuple[object, ...],
    output: Path,
    after: int = 2,
) -> None:
    """Run ``prp3 argv -o output`` stopped by Ctrl-C once ``after`` chunks are written.

    The run must exit 130 saying ``interrupted``, leave no ``designs.parquet`` and keep the
    ``after`` chunks in its staging folder; the chunk writer is restored after.
    """
    import prp3.apps.sweep

    original = prp3.apps.sweep.arrow_table
    written: list[int] = []

    def interrupt(columns: dict[str, object], names: list[str]) -> object:
        if len(written) == after:
            raise KeyboardInterrupt
        written.append(1)
        return original(columns, names)

    monkeypatch.setattr(prp3.apps.sweep, "arrow_table", interrupt)
    try:
        status, _, err = cli(capsys, *argv, "-o", output)
    finally:
        monkeypatch.setattr(prp3.apps.sweep, "arrow_table", original)
    assert status == 130 and "interrupted" in err, err
    assert not (output / "designs.parquet").exists()
    assert len(list(output.glob(".prp3-sweep-*/chunk-*.parquet"))) == after


def write(path: Path, text: str) -> Path:
    """Write ``text`` to ``path``; return ``path``."""
    path.write_text(text, encoding="utf-8")
    return path
