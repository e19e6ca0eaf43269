"""Helpers of the browser tests (headless Chromium driven by Playwright) and of the tests that
run ``prp3`` in a subprocess: the browser, a free port, ``prp3 explore`` served, ``prp3 ...`` run.

Imported by the test files as ``from browsertools import ...`` (``tests/`` is on ``sys.path``,
see ``conftest.py``, which also holds the ``browser`` fixture built on :func:`chromium_browser`).
"""

from __future__ import annotations

import contextlib
import os
import shutil
import socket
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: Chromium's flags on a machine without a network or a screen, as root.
FLAGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
]  # fmt: skip


def chromium_path() -> str | None:
    """Chromium of the OS (Playwright's own download does not work here); PRP3_CHROMIUM
    overrides."""
    return (
        os.environ.get("PRP3_CHROMIUM")
        or shutil.which("chromium")
        or shutil.which("chromium-browser")
    )


def require_browser() -> None:
    """Skip the calling test module, with one line, when Playwright or Chromium is missing
    (``.ci/run`` installs Debian's chromium; the ``test`` extra the ``playwright`` package)."""
    pytest.importorskip(
        "playwright.sync_api", reason="no browser driver: pip install playwright (the test extra)"
    )
    if chromium_path() is None:
        pytest.skip(
            "no browser: install chromium (apt-get install chromium, as .ci/run does)",
            allow_module_level=True,
        )


def chromium_browser() -> Iterator[Any]:
    """A launched headless Chromium, closed after; a browser that does not start skips."""
    sync_api = pytest.importorskip(
        "playwright.sync_api", reason="no browser driver: pip install playwright (the test extra)"
    )
    path = chromium_path()
    if path is None:
        pytest.skip("no browser: install chromium (apt-get install chromium, as .ci/run does)")
    with sync_api.sync_playwright() as playwright:
        try:
            chromium = playwright.chromium.launch(executable_path=path, args=FLAGS)
        except Exception as error:  # a browser that does not start: skip with its reason
            pytest.skip(f"no browser: {path} does not start ({str(error)[:120]})")
        yield chromium
        chromium.close()


def free_port() -> int:
    """A port of 127.0.0.1 nothing listens on at this moment."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def prp3_env() -> dict[str, str]:
    """The environment of a ``prp3`` subprocess: this tree's ``src`` first."""
    return {**os.environ, "PYTHONPATH": str(ROOT / "src")}


def run_prp3(*argv: str) -> str:
    """Run ``python -m prp3 argv`` in a subprocess, which must succeed; return its stdout."""
    return subprocess.run(
        [sys.executable, "-m", "prp3", *argv],
        env=prp3_env(), check=True, capture_output=True, text=True,
    ).stdout  # fmt: skip


@contextlib.contextmanager
def explore_server(*options: str) -> Iterator[tuple[str, str]]:
    """``prp3 explore --no-browser --port P options`` served in a subprocess: yield its URL and
    the first line it printed (the server is stopped after)."""
    port = free_port()
    server = subprocess.Popen(
        [sys.executable, "-m", "prp3", "explore", "--no-browser", "--port", str(port), *options],
        env=prp3_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        assert server.stdout is not None
        line = server.stdout.readline()
        assert "serving" in line, line + (server.stderr.read() if server.stderr else "")
        yield f"http://127.0.0.1:{port}/", line
    finally:
        server.terminate()
        server.communicate(timeout=30)
