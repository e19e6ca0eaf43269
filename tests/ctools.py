"""The C compiler of the generated-C tests (tests/test_codegen.py, test_family_codegen.py,
test_spatial_codegen.py): found once, the one set of strict flags, one shared library built."""

from __future__ import annotations

import ctypes
import shutil
import subprocess
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from prp3.apps.codegen import HEADER_NAME, SOURCE_NAME

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


def write_code(code: Any, folder: Path) -> Path:
    """Write a generated ``code``'s header and source into ``folder`` (made); return it."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / HEADER_NAME).write_text(code.header)
    (folder / SOURCE_NAME).write_text(code.source)
    return folder


class InverseDynamicsLibrary:
    """``prp3_inverse_dynamics`` of a shared library: the pose, velocity and acceleration
    (3 numbers each), then output vectors of the sizes ``outputs``, called with numpy
    vectors; ``join`` makes one array of the outputs (``np.stack``, ``np.concatenate``)."""

    def __init__(
        self, library: Path, outputs: Sequence[int], join: Callable[[list[np.ndarray]], Any]
    ) -> None:
        vector = [
            np.ctypeslib.ndpointer(dtype=np.float64, ndim=1, shape=(n,), flags="C_CONTIGUOUS")
            for n in (3, 3, 3, *outputs)
        ]
        self.library = ctypes.CDLL(str(library))
        self.function = self.library.prp3_inverse_dynamics
        self.function.argtypes = vector
        self.function.restype = ctypes.c_int
        self.outputs = tuple(outputs)
        self.join = join

    def __call__(self, pose: Any, velocity: Any, acceleration: Any) -> tuple[int, np.ndarray]:
        """The return code and the joined outputs."""
        inputs = [np.ascontiguousarray(v, dtype=np.float64) for v in (pose, velocity, acceleration)]
        outputs = [np.zeros(n) for n in self.outputs]
        code = self.function(*inputs, *outputs)
        return int(code), self.join(outputs)


def check_strict_c99(code: Any, outputs: str) -> None:
    """The generated ``code`` includes ``math.h`` and its header only, the header nothing,
    no ``M_PI``, and the header declares ``prp3_inverse_dynamics`` with ``outputs``."""
    includes = [line for line in code.source.splitlines() if line.startswith("#include")]
    assert includes == ["#include <math.h>", f'#include "{HEADER_NAME}"']
    assert "#include" not in code.header and "M_PI" not in code.source
    assert (
        "int prp3_inverse_dynamics(const double pose[3], const double velocity[3],\n"
        "                          const double acceleration[3],\n"
        f"                          {outputs});"
    ) in code.header
