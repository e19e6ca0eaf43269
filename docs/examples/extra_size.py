"""How much the ``test`` extra installs beyond prp3's own dependencies (the README quotes it).

Reads the ``test`` extra of ``pyproject.toml``, follows the requirements of
each package through the installed distributions' metadata
(``importlib.metadata``), and adds up the sizes of the files each
distribution installed (its ``RECORD``) — for every package the test extra
brings in and the base install (numpy, scipy, matplotlib and theirs) does not.
Run it in the environment of ``pip install -e ".[test]"``:
``python docs/examples/extra_size.py``.  A package of the extra that is not
installed is named and counted as 0.
"""

from __future__ import annotations

import re
import tomllib
from importlib import metadata
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

#: Groups of the README's sentence: distribution name → group.
GROUPS = {
    "mujoco": "MuJoCo",
    "pin": "Pinocchio",
    "cmeel": "Pinocchio",
    "eigenpy": "Pinocchio",
    "libpinocchio": "Pinocchio",
    "coal": "Pinocchio",
    "libcoal": "Pinocchio",
    "pyopengl": "MuJoCo",
    "pyarrow": "pyarrow",
    "numba": "numba",
    "llvmlite": "numba",
    "sympy": "sympy",
    "mpmath": "sympy",
    "dask": "dask",
    "distributed": "dask",
    "mypy": "mypy",
    "ruff": "ruff",
}


def _name(requirement: str) -> str:
    return re.split(r"[\s\[<>=!~;(]", requirement.strip(), maxsplit=1)[0].lower().replace("_", "-")


def _closure(requirements: list[str], extras: tuple[str, ...] = ()) -> set[str]:
    """The installed distributions ``requirements`` need, transitively (extras followed)."""
    found: set[str] = set()
    todo = [(r, extras) for r in requirements]
    while todo:
        requirement, wanted = todo.pop()
        name = _name(requirement)
        marker = requirement.split(";", 1)[1] if ";" in requirement else ""
        if "extra ==" in marker and not any(f'"{e}"' in marker or f"'{e}'" in marker
                                             for e in wanted):  # fmt: skip
            continue
        if name in found:
            continue
        try:
            dist = metadata.distribution(name)
        except metadata.PackageNotFoundError:
            continue
        found.add(name)
        inner = tuple(re.findall(r"\[([^\]]*)\]", requirement.split(";")[0])[:1])
        inner = tuple(e.strip() for part in inner for e in part.split(","))
        todo += [(r, inner) for r in dist.requires or []
                 if "platform_system == \"Windows\"" not in r]  # fmt: skip
    return found


def _size(name: str) -> int:
    dist = metadata.distribution(name)
    total = 0
    for file in dist.files or []:
        path = Path(str(dist.locate_file(file)))
        if path.is_file():
            total += path.stat().st_size
    return total


def main() -> None:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    test = project["optional-dependencies"]["test"]
    missing = [r for r in test if _name(r) not in _closure([r])]
    extra = _closure(test) - _closure(project["dependencies"])
    sizes = {name: _size(name) for name in extra}
    groups: dict[str, int] = {}
    for name, size in sizes.items():
        group = next((g for prefix, g in GROUPS.items() if name.startswith(prefix)), "others")
        groups[group] = groups.get(group, 0) + size
    total = sum(sizes.values())
    shown = ", ".join(f"{group} {size / 1e9:.2f}" for group, size in
                      sorted(groups.items(), key=lambda item: -item[1]))  # fmt: skip
    print(f"test extra: {total / 1e9:.2f} GB installed beyond the base install, "
          f"{len(sizes)} distributions (GB: {shown})")  # fmt: skip
    if missing:
        print("not installed, counted as 0: " + ", ".join(_name(r) for r in missing))


if __name__ == "__main__":
    main()
