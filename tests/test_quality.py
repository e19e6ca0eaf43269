"""The code base stays lint-, format- and type-clean (ruff, mypy from the test extra).

Also the one-way import rule of the architecture: the library never imports
the command line, and only ``prp3.plotting`` imports matplotlib.
"""

from __future__ import annotations

import ast
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src" / "prp3"


def _run(*command: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(command, cwd=ROOT, capture_output=True, text=True, timeout=300)


@pytest.mark.skipif(shutil.which("ruff") is None, reason="ruff not installed")
def test_ruff_check_and_format() -> None:
    lint = _run("ruff", "check", "src", "tests", "benchmarks")
    assert lint.returncode == 0, lint.stdout + lint.stderr
    form = _run("ruff", "format", "--check", "src", "tests", "benchmarks")
    assert form.returncode == 0, form.stdout + form.stderr


def test_mypy_strict() -> None:
    pytest.importorskip("mypy")
    result = _run(sys.executable, "-m", "mypy")
    assert result.returncode == 0, result.stdout + result.stderr


def _imports(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            module = node.module or ""
            if node.level:  # relative: resolve against the file's package
                parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
                base = parts[: len(parts) - node.level]
                module = ".".join((*base, module)) if module else ".".join(base)
            names.add(module)
            names.update(f"{module}.{alias.name}" for alias in node.names)
    return names


def _library_modules() -> list[Path]:
    return sorted(
        p
        for p in PACKAGE.rglob("*.py")
        if "cli" not in p.relative_to(PACKAGE).parts and p.name != "__main__.py"
    )


@pytest.mark.parametrize("path", _library_modules(), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_library_never_imports_the_command_line(path: Path) -> None:
    assert not any(name == "prp3.cli" or name.startswith("prp3.cli.") for name in _imports(path))


@pytest.mark.parametrize(
    "path", sorted(PACKAGE.rglob("*.py")), ids=lambda p: str(p.relative_to(PACKAGE))
)
def test_only_plotting_imports_matplotlib(path: Path) -> None:
    if "plotting" in path.relative_to(PACKAGE).parts:
        return
    assert not any(name.split(".")[0] == "matplotlib" for name in _imports(path))


def test_importing_prp3_does_not_import_matplotlib_or_scipy() -> None:
    code = "import sys, prp3; print('matplotlib' in sys.modules, 'scipy' in sys.modules)"
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    )
    assert result.stdout.split() == ["False", "False"]
