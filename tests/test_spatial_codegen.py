"""The generated C of the spatial robots (``prp3 export c``, docs/spatial.md §24).

The code is compiled with the system's C compiler (``cc -std=c99 -pedantic-errors -Wall
-Wextra -Werror -O2``; the tests are skipped when there is none), loaded with ctypes and
compared with :func:`prp3.spatial_inverse_dynamics` (the numpy route (b), another code
than the C's steps) over random regular states of each architecture, to 1e-12 relative
to the largest value of each output; its refusals against the compiled kernel's status
and the numpy route's errors; never ``PRP3_OK`` with a non-finite output.
"""

from __future__ import annotations

import ctypes
import math
import re
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import prp3
from ctools import COMPILER, shared_library
from prp3 import (
    RETURN_CODES,
    SPATIAL_STATUS,
    PlatformMotion,
    SpatialRobot,
    compile_spatial,
    delta,
    hexapod,
    spatial_c_inverse_dynamics,
    spatial_inverse_dynamics,
    spatial_random_motion,
    three_rps,
)
from prp3.apps.codegen import HEADER_NAME, SOURCE_NAME
from prp3.cli import main
from prp3.errors import ParameterError, Prp3Error
from prp3.spatial.rotations import rpy_matrix

pytestmark = pytest.mark.skipif(COMPILER is None, reason="no C compiler")
CODES = {name: value for name, value, _ in SPATIAL_STATUS}
ROBOTS: dict[str, Callable[[], SpatialRobot]] = {
    "6-UPS": hexapod,
    "3-RPS": three_rps,
    "3-RUU": delta,
}
_Double = ctypes.POINTER(ctypes.c_double)


class Compiled:
    """``prp3_inverse_dynamics`` of a shared library, called with numpy arrays."""

    def __init__(self, library: Path, robot: SpatialRobot) -> None:
        self.library = ctypes.CDLL(str(library))
        self.function = self.library.prp3_inverse_dynamics
        self.function.argtypes = [_Double] * 12
        self.function.restype = ctypes.c_int
        legs, dof = len(robot.legs), robot.legs[0].dof
        self.shapes = ((legs, dof), (legs, dof), (legs, dof), (legs,), (legs, 3, 3), (legs, 3, 3))

    def __call__(self, *state: np.ndarray) -> tuple[int, list[np.ndarray]]:
        inputs = [np.ascontiguousarray(v, dtype=np.float64) for v in state]
        outputs = [np.zeros(shape) for shape in self.shapes]
        pointers = [a.ctypes.data_as(_Double) for a in (*inputs, *outputs)]
        code = self.function(*pointers)
        return int(code), outputs  # q, dq, ddq, tau, force, moment


def build_from(folder: Path, robot: SpatialRobot) -> Compiled:
    library = shared_library(folder, "libprp3spatial.so")
    return Compiled(library, robot)


@pytest.fixture(scope="module")
def libraries(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Compiled]:
    built = {}
    for name, make in ROBOTS.items():
        robot = make()
        code = spatial_c_inverse_dynamics(robot)
        folder = tmp_path_factory.mktemp(name.replace("-", "_"))
        (folder / HEADER_NAME).write_text(code.header)
        (folder / SOURCE_NAME).write_text(code.source)
        built[name] = build_from(folder, robot)
    return built


def _state(motion: PlatformMotion, k: int) -> tuple[np.ndarray, ...]:
    return (motion.position[k], motion.rotation[k], motion.omega[k], motion.velocity[k],
            motion.alpha[k], motion.acceleration[k])  # fmt: skip


def _close(got: np.ndarray, want: np.ndarray, what: str) -> None:
    scale = max(float(np.max(np.abs(want))), 1e-300)
    error = float(np.max(np.abs(got - want)))
    assert error <= 1e-12 * scale, f"{what}: {error:.3g} against {scale:.3g}"


@pytest.mark.parametrize("name", list(ROBOTS))
@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_agrees_with_the_numpy_route(libraries: dict[str, Compiled], name: str, seed: int) -> None:
    robot = ROBOTS[name]()
    motion = spatial_random_motion(robot, 4, seed)
    solution = spatial_inverse_dynamics(robot, motion)
    assert solution.force is not None and solution.moment is not None
    kin = solution.kinematics
    for k in range(len(motion)):
        code, (q, dq, ddq, tau, force, moment) = libraries[name](*_state(motion, k))
        assert code == CODES["PRP3_OK"]
        for got, want, what in (
            (q, kin.q[k], "q"), (dq, kin.dq[k], "dq"), (ddq, kin.ddq[k], "ddq"),
            (tau, solution.tau[k], "tau"), (force, solution.force[k], "force"),
            (moment, solution.moment[k], "moment"),
        ):  # fmt: skip
            _close(got, want, f"{name} sample {k} {what}")


def _kernel_status(robot: SpatialRobot, state: tuple[np.ndarray, ...]) -> int:
    arrays = [np.ascontiguousarray(np.asarray(v, dtype=np.float64)[None]) for v in state]
    return int(compile_spatial(robot).raw(*arrays, threads=False).status[0])


def _refused(compiled: Compiled, state: tuple[np.ndarray, ...]) -> int:
    code, outputs = compiled(*state)
    assert code != 0
    assert all(np.isnan(a).all() for a in outputs), "a refusal leaves every output NaN"
    return code


def _home(robot: SpatialRobot) -> list[np.ndarray]:
    zero = np.zeros(3)
    return [np.asarray(robot.home_position, dtype=float), np.asarray(robot.home_rotation),
            zero, zero, zero, zero]  # fmt: skip


@pytest.mark.parametrize("name", list(ROBOTS))
def test_refusals_are_the_kernels(libraries: dict[str, Compiled], name: str) -> None:
    """Each refusal: the compiled kernel's status, the numpy route raises, outputs NaN."""
    robot = ROBOTS[name]()
    cases: dict[str, list[np.ndarray]] = {}
    far = _home(robot)
    far[0] = far[0] + np.array([0.0, 0.0, 50.0 * robot.scale])
    cases["far"] = far
    spun = _home(robot)
    spun[1] = spun[1] * 1.001
    cases["not a rotation"] = spun
    for what, state in cases.items():
        code = _refused(libraries[name], tuple(state))
        assert code == _kernel_status(robot, tuple(state)), what
        with pytest.raises(Prp3Error):
            spatial_inverse_dynamics(robot, PlatformMotion.of([0.0], *state))
    assert _refused(libraries[name], tuple(cases["not a rotation"])) == CODES["PRP3_NOT_ROTATION"]


def _check_status(compiled: Compiled, robot: SpatialRobot, state: list[np.ndarray]) -> int:
    code, outputs = compiled(*state)
    assert code == _kernel_status(robot, tuple(state))
    if code == 0:
        assert all(np.isfinite(a).all() for a in outputs)
    else:
        assert all(np.isnan(a).all() for a in outputs)
    return code


@pytest.mark.parametrize("name", list(ROBOTS))
@settings(max_examples=30, deadline=None)
@given(
    size=st.sampled_from([0.05, 0.3, 1.5]),
    offset=st.tuples(*[st.floats(-1.0, 1.0)] * 3),
    angles=st.tuples(*[st.floats(-1.0, 1.0)] * 3),
)
def test_status_matches_the_kernel_over_the_pose_space(
    libraries: dict[str, Compiled],
    name: str,
    size: float,
    offset: tuple[float, ...],
    angles: tuple[float, ...],
) -> None:
    """Random poses near and far — reachable or not, within the limits or not, a pose of the
    robot's DOF or not (the Delta only translates: its rotation is kept) — the C's code is the
    compiled kernel's, and ``PRP3_OK`` only with finite outputs."""
    robot = ROBOTS[name]()
    state = _home(robot)
    state[0] = state[0] + np.asarray(offset) * size * robot.scale
    if name != "3-RUU":
        state[1] = rpy_matrix(np.asarray(angles) * size) @ state[1]
    _check_status(libraries[name], robot, state)


@pytest.mark.parametrize("name", ["3-RPS", "3-RUU"])
@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), which=st.sampled_from([2, 4]))
def test_an_incompatible_twist_is_refused(
    libraries: dict[str, Compiled], name: str, seed: int, which: int
) -> None:
    """A robot of 3 DOF at one of its poses, its angular velocity or acceleration changed
    (neither the 3-RPS nor the Delta turns freely): ``PRP3_INCOMPATIBLE``, as the kernel."""
    robot = ROBOTS[name]()
    state = list(_state(spatial_random_motion(robot, 1, seed), 0))
    state[which] = state[which] + np.random.default_rng(seed).normal(size=3)
    assert _check_status(libraries[name], robot, state) == CODES["PRP3_INCOMPATIBLE"]


@pytest.mark.parametrize("name", list(ROBOTS))
def test_singular_pose(tmp_path: Path, name: str) -> None:
    """Robots of length 100 m (their Jacobians' moment rows in units of it nearly zero):
    ``μ_leg`` is below 1e-4 at home, ``PRP3_SINGULAR`` as the kernel and the numpy route."""
    robot = ROBOTS[name](scale=100.0)  # type: ignore[call-arg]
    code = spatial_c_inverse_dynamics(robot)
    (tmp_path / HEADER_NAME).write_text(code.header)
    (tmp_path / SOURCE_NAME).write_text(code.source)
    state = tuple(_home(robot))
    assert _kernel_status(robot, state) == CODES["PRP3_SINGULAR"]
    assert _refused(build_from(tmp_path, robot), state) == CODES["PRP3_SINGULAR"]
    with pytest.raises(prp3.SingularPoseError):
        spatial_inverse_dynamics(robot, PlatformMotion.of([0.0], *state))


@pytest.mark.parametrize("name", list(ROBOTS))
@pytest.mark.parametrize("where", range(6))
def test_non_finite_and_overflowing_inputs(
    libraries: dict[str, Compiled], name: str, where: int
) -> None:
    robot = ROBOTS[name]()
    motion = spatial_random_motion(robot, 1, 7)
    state = [np.array(v, dtype=float) for v in _state(motion, 0)]
    for bad in (math.nan, math.inf, -math.inf):
        trial = [v.copy() for v in state]
        trial[where].flat[1] = bad
        assert _refused(libraries[name], tuple(trial)) == CODES["PRP3_NOT_FINITE"]
    if where >= 2:  # finite rates too large for double precision: never OK with inf or NaN
        trial = [v.copy() for v in state]
        trial[where] = trial[where] + 1e300
        code, outputs = libraries[name](*trial)
        if code == 0:
            assert all(np.isfinite(a).all() for a in outputs)
        else:
            assert all(np.isnan(a).all() for a in outputs)
        huge = [v.copy() for v in state]
        huge[where] = huge[where] * 1e200
        code, outputs = libraries[name](*huge)
        assert code in (0, CODES["PRP3_OVERFLOW"], CODES["PRP3_INCOMPATIBLE"])
        if code == 0:
            assert all(np.isfinite(a).all() for a in outputs)


def test_overflow_is_refused(libraries: dict[str, Compiled]) -> None:
    """The hexapod's twist of 1e200 rad/s: inputs finite, ``ω × I·ω`` is not: PRP3_OVERFLOW."""
    robot = hexapod()
    state = _home(robot)
    state[2] = np.array([1e200, 0.0, 0.0])
    assert _refused(libraries["6-UPS"], tuple(state)) == CODES["PRP3_OVERFLOW"]
    assert _kernel_status(robot, tuple(state)) == CODES["PRP3_OVERFLOW"]


def test_header_lists_the_codes_once() -> None:
    header = spatial_c_inverse_dynamics(three_rps()).header
    for name, value, meaning in SPATIAL_STATUS:
        assert header.count(f"#define {name} ") == 1
        assert f"#define {name} {value} /* {meaning} */" in header
    # the planar C's codes are the first six, with the same names and values
    assert [(n, v) for n, v, _ in RETURN_CODES] == [(n, v) for n, v, _ in SPATIAL_STATUS[:6]]
    assert "#define PRP3_LEGS 3" in header and "#define PRP3_DOF 5" in header


def test_source_is_strict_c99_without_posix_constants() -> None:
    for make in ROBOTS.values():
        source = spatial_c_inverse_dynamics(make()).source
        assert not re.search(r"\bM_\w+", source)
        assert source.count("#include") == 2


def test_refuses_a_non_spatial_robot() -> None:
    with pytest.raises(ParameterError, match="robot"):
        spatial_c_inverse_dynamics(prp3.Robot())  # type: ignore[arg-type]


def test_cli_writes_both_files(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    robot_file = tmp_path / "delta.toml"
    robot_file.write_text('architecture = "3-RUU"\n')
    out = tmp_path / "code"
    assert main(["export", "c", "--robot", str(robot_file), "--output", str(out)]) == 0
    said = capsys.readouterr().out
    assert said.startswith("prp3 export c: C99 inverse dynamics of the robot of ")
    assert "3-RUU" in said.splitlines()[0]
    header = (out / HEADER_NAME).read_text()
    assert header == spatial_c_inverse_dynamics(delta()).header
    build_from(out, delta())  # compiles as written


def test_cli_bad_robot_file_is_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text('architecture = "6-UPS"\n[platform]\nmass = -1.0\n')
    out = tmp_path / "none"
    assert main(["export", "c", "--robot", str(bad), "--output", str(out)]) == 2
    error = capsys.readouterr().err.strip()
    assert len(error.splitlines()) == 1 and "bad.toml" in error
    assert not (out / SOURCE_NAME).exists()


def test_cli_as_a_subprocess(tmp_path: Path) -> None:
    robot_file = tmp_path / "hexapod.toml"
    robot_file.write_text('architecture = "6-UPS"\n')
    done = subprocess.run(
        [sys.executable, "-m", "prp3", "export", "c"]
        + ["--robot", str(robot_file), "--output", str(tmp_path / "c")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    assert "6-UPS" in done.stdout
    compiled = build_from(tmp_path / "c", hexapod())
    code, outputs = compiled(*_home(hexapod()))
    assert code == 0
    # at rest the six legs carry the platform's weight: the vertical forces at S sum to m g
    robot = hexapod()
    assert math.isclose(
        float(outputs[4][:, 2, 2].sum()), robot.platform.mass * -robot.gravity[2], rel_tol=1e-12
    )


def test_parallel_singular_hexapod(tmp_path: Path) -> None:
    """The hexapod turned about the vertical to where ``μ_par`` changes sign (bisection on the
    kernel's measure): ``PRP3_SINGULAR`` there, as the kernel and the numpy route; regular
    0.05 rad before it."""
    robot = hexapod(stroke=(0.01, 1.0), u_limit=1.5, s_limit=3.0)
    code = spatial_c_inverse_dynamics(robot)
    (tmp_path / HEADER_NAME).write_text(code.header)
    (tmp_path / SOURCE_NAME).write_text(code.source)
    compiled = build_from(tmp_path, robot)
    kernel = compile_spatial(robot)

    def state(yaw: float) -> list[np.ndarray]:
        at = _home(robot)
        at[1] = rpy_matrix(np.array([0.0, 0.0, yaw])) @ at[1]
        return at

    def measure(yaw: float) -> float:
        arrays = [np.ascontiguousarray(v[None]) for v in state(yaw)]
        return float(kernel.raw(*arrays, threads=False).parallel_measure[0])

    yaws = np.linspace(0.0, 2.0, 201)
    signs = np.sign([measure(float(y)) for y in yaws])
    k = int(np.argmax(signs != signs[0]))
    assert k > 0
    lo, hi = float(yaws[k - 1]), float(yaws[k])
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if np.sign(measure(mid)) == signs[0] else (lo, mid)
    near = state(lo)
    assert _kernel_status(robot, tuple(near)) == CODES["PRP3_SINGULAR"]
    assert _refused(compiled, tuple(near)) == CODES["PRP3_SINGULAR"]
    with pytest.raises(prp3.SingularPoseError, match="parallel singular"):
        spatial_inverse_dynamics(robot, PlatformMotion.of([0.0], *near))
    code_away, _ = compiled(*state(lo - 0.05))
    assert code_away == CODES["PRP3_OK"]
