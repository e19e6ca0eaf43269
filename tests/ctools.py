"""The C compiler of the generated-C tests (tests/test_codegen.py, test_family_codegen.py,
test_spatial_codegen.py): found once, the one set of strict flags, one shared library built."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

from prp3.apps.codegen import SOURCE_NAME

#: The system C compiler, or ``None`` (the tests skip).
COMPILER = shutil.which("cc") or shutil.which("gcc") or shutil.which("clang")
#: C99, every warning an error: the generated code must compile cleanly anywhere.
FLAGS = ["-std=c99", "-pedantic-errors", "-Wall", "-Wextra", "-Werror", "-O2"]


def shared_library(folder: Path, name: str) -> Path:
    """Compile ``folder/prp3_inverse_dynamics.c`` into ``folder/name`` (a shared library)."""
    library = folder / name
    assert COMPILER is not None
    done = subprocess.run(
        [COMPILER, *FLAGS, "-shared", "-fPIC", "-o", str(library), str(folder / SOURCE_NAME),
         "-lm"],
        capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    return library
