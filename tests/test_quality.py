"""The code base stays lint-, format- and type-clean (ruff, mypy from the test extra).

Also the one-way import rule of the architecture: the import graph of
``src/prp3``, derived from the source, follows the layers of the table in
ARCHITECTURE.md (section "Import layers", the one statement of them) and has no
cycle; the library never imports the command line, and only ``prp3.plotting``
imports matplotlib.
"""

from __future__ import annotations

import ast
import functools
import re
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
    lint = _run("ruff", "check", "src", "tests", "benchmarks", "docs/examples")
    assert lint.returncode == 0, lint.stdout + lint.stderr
    form = _run("ruff", "format", "--check", "src", "tests", "benchmarks", "docs/examples")
    assert form.returncode == 0, form.stdout + form.stderr


@pytest.mark.slow  # a cold mypy run: 20 s of one core
def test_mypy_strict() -> None:
    pytest.importorskip("mypy")
    result = _run(sys.executable, "-m", "mypy")
    assert result.returncode == 0, result.stdout + result.stderr


def _type_checking_nodes(tree: ast.AST) -> set[int]:
    """The ids of the import nodes under ``if TYPE_CHECKING:`` (for the type checker only)."""
    skipped: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            skipped.update(id(inner) for stmt in node.body for inner in ast.walk(stmt))
    return skipped


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _runtime_imports(path: Path, text: str | None = None) -> set[str]:
    """The ``prp3`` modules ``path`` (or ``text`` in its place) imports when it runs.

    A name imported from the package itself is ``prp3:NAME``.
    """
    tree = ast.parse(path.read_text(encoding="utf-8") if text is None else text)
    skipped = _type_checking_nodes(tree)
    names: set[str] = set()
    for node in ast.walk(tree):
        if id(node) in skipped:
            continue
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            module = node.module or ""
            if node.level:  # relative: resolve against the file's package
                parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
                base = parts[: len(parts) - node.level]
                module = ".".join((*base, module)) if module else ".".join(base)
            for alias in node.names:
                full = f"{module}.{alias.name}"
                submodule = PACKAGE.parent.joinpath(*full.split("."))
                if submodule.with_suffix(".py").is_file() or submodule.is_dir():
                    names.add(full)  # ``from . import kernel``: the module kernel
                elif module == "prp3":
                    names.add(f"prp3:{alias.name}")  # a name of the package itself
                else:
                    names.add(module)
    return {name for name in names if name == "prp3" or name.startswith(("prp3.", "prp3:"))}


@functools.cache
def _layers() -> dict[str, int]:
    """ARCHITECTURE.md's table of import layers: unit (``model``, ``cli``, ``prp3``) → layer."""
    text = (ROOT / "ARCHITECTURE.md").read_text(encoding="utf-8")
    section = text.split("## Import layers", 1)[1].split("\n## ", 1)[0]
    layers: dict[str, int] = {}
    for number, cells in re.findall(r"^\| (\d+) [^|]*\| ([^|]*) \|$", section, re.M):
        for unit in re.findall(r"`([\w.]+)`", cells.split("(")[0]):
            assert unit not in layers, f"ARCHITECTURE.md names {unit} in two layers"
            layers[unit] = int(number)
    assert len(layers) > 12 and "prp3" in layers, "the table of import layers was not found"
    return layers


def _exceptions() -> set[tuple[str, str]]:
    """The imports against the table that ARCHITECTURE.md lists: ``- `a` → `b`: why``."""
    text = (ROOT / "ARCHITECTURE.md").read_text(encoding="utf-8")
    section = text.split("## Import layers", 1)[1].split("\n## ", 1)[0]
    return set(re.findall(r"^- `([\w.]+)` → `([\w.]+)`:", section, re.M))


def _unit(module: str) -> str:
    """The unit of the layer table a module belongs to: ``prp3.cli.simulate`` → ``cli``.

    A module the table names on its own (``family.forward``) is its own unit.
    """
    if module == "prp3":
        return "prp3"
    parts = module.split(".")
    return ".".join(parts[1:3]) if ".".join(parts[1:3]) in _layers() else parts[1]


def _import_graph() -> dict[str, set[str]]:
    return {_module_name(path): _runtime_imports(path) for path in sorted(PACKAGE.rglob("*.py"))}


def test_the_layer_table_names_every_module_and_no_other():
    layers = _layers()
    units = {_unit(module) for module in _import_graph()}
    units |= {unit.split(".")[0] for unit in units}  # a package named with some of its modules
    assert units - set(layers) == set(), "modules missing from ARCHITECTURE.md's import layers"
    assert set(layers) - units == set(), "ARCHITECTURE.md's import layers name missing modules"


def test_every_import_follows_the_layers_of_architecture_md():
    layers = _layers()
    against = []
    for module, imports in _import_graph().items():
        for name in sorted(imports):
            if name.startswith("prp3:"):  # a name from the package: only its version
                if name != "prp3:__version__" and layers[_unit(module)] < layers["prp3"]:
                    against.append(f"{module} imports {name[5:]} from prp3")
                continue
            if (_unit(module), _unit(name)) in _exceptions():
                continue
            if layers[_unit(name)] > layers[_unit(module)]:
                against.append(
                    f"{module} (layer {layers[_unit(module)]}) imports {name} "
                    f"(layer {layers[_unit(name)]})"
                )
    assert against == []


def test_the_import_graph_has_no_cycle():
    graph = {
        module: {name for name in imports if not name.startswith("prp3:")}
        for module, imports in _import_graph().items()
    }
    allowed = _exceptions()
    graph = {
        module: {
            name for name in names if name in graph and (_unit(module), _unit(name)) not in allowed
        }
        for module, names in graph.items()
    }
    state: dict[str, int] = {}  # 1 on the path, 2 done

    def visit(module: str, path: list[str]) -> None:
        state[module] = 1
        for name in sorted(graph[module]):
            if state.get(name) == 1:
                raise AssertionError("import cycle: " + " -> ".join([*path, module, name]))
            if name not in state:
                visit(name, [*path, module])
        state[module] = 2

    for module in sorted(graph):
        if module not in state:
            visit(module, [])


def test_the_layering_check_catches_an_upward_import() -> None:
    # the check itself can fail: a kernel importing the command line is reported
    layers = _layers()
    assert layers["mechanics"] < layers["cli"] and layers["plotting"] > layers["io"]
    kernel = PACKAGE / "mechanics" / "kernel.py"
    assert _runtime_imports(kernel, "def f():\n    from ..cli import main\n") == {"prp3.cli"}
    assert _runtime_imports(kernel, "from prp3.cli import main\n") == {"prp3.cli"}
    assert _runtime_imports(kernel, "from . import geometry\nfrom .. import __version__\n") == {
        "prp3.mechanics.geometry",
        "prp3:__version__",
    }
    lazy = "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from prp3.cli import main\n"
    assert _runtime_imports(kernel, lazy) == set()
    assert len(_exceptions()) <= 1  # ARCHITECTURE.md's list of exceptions does not grow


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


def _private_imports(path: Path, source: str | None = None) -> list[str]:
    """Private names (``_x``, not dunders) a file takes from another module of prp3.

    Both ``from prp3.m import _x`` and ``import prp3.m as m; m._x`` count.
    """
    tree = ast.parse(source if source is not None else path.read_text(encoding="utf-8"))
    aliases: set[str] = set()
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and (
            node.level or (node.module or "").startswith("prp3")
        ):
            found += [
                f"{node.module}.{a.name}"
                for a in node.names
                if a.name.startswith("_") and not a.name.startswith("__")
            ]
        elif isinstance(node, ast.Import):
            aliases |= {
                a.asname or a.name.split(".")[0] for a in node.names if a.name.startswith("prp3")
            }
    for node in ast.walk(tree):
        if (
            isinstance(node, ast.Attribute)
            and node.attr.startswith("_")
            and not node.attr.startswith("__")
            and isinstance(node.value, (ast.Name, ast.Attribute))
            and ast.unparse(node.value).split(".")[0] in aliases
            and not _is_module(ast.unparse(node))
        ):
            found.append(ast.unparse(node))
    return found


def _is_module(dotted: str) -> bool:
    """Whether ``prp3.a._b`` names a module (a package's private module, as ``cli._progress``)."""
    relative = Path(*dotted.split(".")[1:])
    return dotted.startswith("prp3.") and (
        (PACKAGE / relative).with_suffix(".py").exists() or (PACKAGE / relative).is_dir()
    )


_SOURCES = sorted(
    [*PACKAGE.rglob("*.py"), *(ROOT / "tests").glob("*.py"), *(ROOT / "benchmarks").glob("*.py")]
)


@pytest.mark.parametrize("path", _SOURCES, ids=lambda p: str(p.relative_to(ROOT)))
def test_no_private_name_is_imported_across_modules(path: Path) -> None:
    # a name another module needs is public in its module (the structure rule);
    # prp3's tests and benchmarks hold themselves to the same rule
    assert _private_imports(path) == []


def test_the_private_import_check_catches_both_forms() -> None:
    here = PACKAGE / "mechanics" / "kernel.py"
    assert _private_imports(here, "from prp3.family.chain import _x, __all__\n") == [
        "prp3.family.chain._x"
    ]
    assert _private_imports(here, "from .chain import _y\n") == ["chain._y"]
    assert _private_imports(here, "import prp3.family.chain as c\nc._z(1)\n") == ["c._z"]
    assert _private_imports(here, "import numpy as np\nnp._w\nfrom os import _exit\n") == []


#: The functions of src/prp3 over 80 lines when this check came (path -> names); the list
#: may only shrink (a function split below 80 lines must leave it, a new one may not join).
#: Why they stay for now: Newton-Euler assemblies (references/newton_euler._solve,
#: family/newton_euler, mechanics/wrenches.body_wrenches); numba kernels compiled as one
#: function (family/compiled*, spatial/compiled); files other helpers were changing at the
#: same time (spatial/compiled, spatial/forward, apps/control, cli/control, cli/_spatial*);
#: the rest are not split yet (issue 31, item 6).
LONG_FUNCTIONS: dict[str, tuple[str, ...]] = {
    "analysis/forward.py": ("forward_dynamics",),
    "engines/trace.py": ("broadcast_function",),
    "explorer/app.py": ("explorer_document",),
    "explorer/family_scene.py": ("family_view",),
    "family/codegen.py": ("family_c_inverse_dynamics",),
    "family/compiled_path.py": ("follow_path",),
    "family/forward.py": ("family_forward_dynamics",),
    "family/paper.py": ("paper_steps",),
    "family/sample_mechanics.py": ("sample_dynamics",),
    "mechanics/wrenches.py": ("body_wrenches",),
    "references/newton_euler.py": ("_solve",),
    "spatial/compiled.py": ("_geometry", "_sample"),
    "spatial/forward.py": ("spatial_forward_dynamics",),
}


def _long_functions() -> dict[str, set[str]]:
    found: dict[str, set[str]] = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        if "__pycache__" in path.parts:  # the generated kernels (engines.traced_numba)
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                if (node.end_lineno or node.lineno) - node.lineno + 1 > 80:
                    found.setdefault(path.relative_to(PACKAGE).as_posix(), set()).add(node.name)
    return found


def test_no_function_over_80_lines_but_the_listed_ones() -> None:
    found = _long_functions()
    new = {p: sorted(n - set(LONG_FUNCTIONS.get(p, ()))) for p, n in found.items()}
    assert not {p: n for p, n in new.items() if n}, "split these (no function over 80 lines)"
    gone = {p: sorted(set(n) - found.get(p, set())) for p, n in LONG_FUNCTIONS.items()}
    assert not {p: n for p, n in gone.items() if n}, "shorter now: take them off LONG_FUNCTIONS"
