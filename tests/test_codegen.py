"""The generated C code (``prp3 export c``): strict C99, the kernel's numbers, the refusals.

The code is compiled with the system's C compiler (``cc -std=c99
-pedantic-errors -Wall -Wextra -Werror``; the tests are skipped when there is
none), loaded with ctypes and compared with prp3's batch inverse dynamics
(``prp3.engines.entries.paper_forces``, numpy; another path than the single-sample code
the C is generated from) over random robots and samples, to 1e-12 relative
to the largest force of the sample.
"""

from __future__ import annotations

import math
import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ctools import COMPILER, InverseDynamicsLibrary, check_strict_c99, shared_library, write_code
from prp3 import Limits, Motion, Robot, inverse_dynamics
from prp3.apps.codegen import (
    C_NOT_FINITE,
    C_OK,
    C_OUTSIDE_STROKE,
    C_OVERFLOW,
    C_SINGULAR,
    HEADER_NAME,
    RETURN_CODES,
    SOURCE_NAME,
    c_inverse_dynamics,
)
from prp3.cli import main
from prp3.engines.compiled_robot import compile_robot
from prp3.engines.entries import paper_forces
from prp3.engines.sample_entries import sample_forces, sample_forces_unchecked
from prp3.errors import ParameterError, SingularPoseError, TrajectoryError, UnreachablePoseError
from prp3.model.parameters import Friction, JointFriction, Load, Spring, SpringParameters
from strategies import poses, robots

pytest.importorskip("sympy")
pytestmark = pytest.mark.skipif(COMPILER is None, reason="no C compiler")


#: ``prp3_inverse_dynamics`` of a shared library: the return code and rows f10, f21y, f21z.
Compiled = InverseDynamicsLibrary


def build(robot: Robot, folder: Path) -> Compiled:
    return build_from(write_code(c_inverse_dynamics(robot), folder))


def build_from(folder: Path) -> Compiled:
    return Compiled(shared_library(folder, "libprp3id.so"), (3, 3, 3), np.stack)


@pytest.fixture(scope="module")
def paper_robot(tmp_path_factory: pytest.TempPathFactory) -> Compiled:
    """The paper's robot through the command line ``prp3 export c``."""
    folder = tmp_path_factory.mktemp("paper")
    assert main(["export", "c", "--output", str(folder)]) == 0
    return build_from(folder)


def _expected(robot: Robot, pose, velocity, acceleration) -> np.ndarray:
    forces = paper_forces(compile_robot(robot), pose, velocity, acceleration)
    return np.stack([forces.f10, forces.f21y, forces.f21z], axis=1)  # (N, 3 outputs, 3 legs)


def _compare(compiled: Compiled, robot: Robot, pose, velocity, acceleration) -> float:
    expected = _expected(robot, pose, velocity, acceleration)
    worst = 0.0
    for k in range(len(pose)):
        code, got = compiled(pose[k], velocity[k], acceleration[k])
        assert code == 0
        scale = max(float(np.abs(expected[k]).max()), 1e-9)  # relative; 1 nN when all vanish
        worst = max(worst, float(np.abs(got - expected[k]).max()) / scale)
    return worst


def test_the_paper_robot_matches_the_kernel(paper_robot: Compiled) -> None:
    rng = np.random.default_rng(12)
    count = 400
    pose = np.column_stack(
        [
            rng.uniform(-0.1, 0.1, count),
            rng.uniform(-0.1, 0.1, count),
            rng.uniform(-1.7, 0.7, count),
        ]
    )
    velocity = rng.uniform(-2.0, 2.0, (count, 3))
    acceleration = rng.uniform(-20.0, 20.0, (count, 3))
    assert _compare(paper_robot, Robot(), pose, velocity, acceleration) <= 1e-12
    # and with the independent Newton-Euler solver (its own closure solves), to its round-off
    motion = Motion(
        t=np.arange(float(count)), pose=pose, velocity=velocity, acceleration=acceleration
    )
    reference = inverse_dynamics(Robot(), motion, method="newton-euler")[1]
    for k in range(0, count, 20):
        code, got = paper_robot(pose[k], velocity[k], acceleration[k])
        want = np.stack([reference.f10[k], reference.f21y[k], reference.f21z[k]])
        assert code == 0 and np.abs(got - want).max() <= 1e-9 * np.abs(want).max()


@settings(max_examples=6)
@given(robot=robots(), data=st.data())
def test_random_robots_match_the_kernel(
    tmp_path_factory: pytest.TempPathFactory, robot: Robot, data: st.DataObject
) -> None:
    compiled = build(robot, tmp_path_factory.mktemp("random"))
    pose = np.stack([data.draw(poses(robot.l0)) for _ in range(20)])
    rates = st.lists(st.floats(-5.0, 5.0), min_size=60, max_size=60)
    velocity = np.array(data.draw(rates)).reshape(20, 3)
    acceleration = 10.0 * np.array(data.draw(rates)).reshape(20, 3)
    assert _compare(compiled, robot, pose, velocity, acceleration) <= 1e-12


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
@pytest.mark.parametrize("where", range(9))
def test_non_finite_input_returns_1_and_nan(paper_robot: Compiled, where: int, bad: float) -> None:
    values = np.zeros(9)
    values[where] = bad
    code, outputs = paper_robot(values[:3], values[3:6], values[6:])
    assert code == 1 and np.isnan(outputs).all()


@pytest.mark.parametrize(
    "phi", [math.pi / 3.0, math.pi / 3.0 + 5e-5, math.pi / 3.0 - 9e-5, -2.0 * math.pi / 3.0]
)
def test_singular_pose_returns_2_and_nan(paper_robot: Compiled, phi: float) -> None:
    code, outputs = paper_robot([0.0, 0.0, phi], np.zeros(3), np.zeros(3))
    assert code == 2 and np.isnan(outputs).all()
    code, _ = paper_robot([0.0, 0.0, math.pi / 3.0 + 2e-4], np.zeros(3), np.zeros(3))
    assert code == 0  # beyond the threshold: computed


def test_outside_the_stroke_returns_3(tmp_path: Path) -> None:
    robot = Robot(limits=Limits(stroke=(-0.01, 0.02)))
    compiled = build(robot, tmp_path)
    # y raises every actuator alike: lambda10 = y·(2/√3)·... crosses the stroke
    inside = np.array([0.0, 0.005, 0.0])
    code, outputs = compiled(inside, np.zeros(3), np.zeros(3))
    assert code == 0 and np.isfinite(outputs).all()
    assert _compare(compiled, robot, inside[None], np.zeros((1, 3)), np.zeros((1, 3))) <= 1e-12
    for pose in ([0.0, 0.05, 0.0], [0.0, -0.05, 0.0], [0.05, 0.0, 0.0], [0.0, 0.0, 0.3]):
        code, outputs = compiled(np.array(pose), np.zeros(3), np.zeros(3))
        assert code == 3 and np.isnan(outputs).all(), pose


STROKE = (-0.01, 0.02)

#: Inputs that prp3's Python entry refuses, the error it raises and the code the C must return.
#: A 3-PRP's forces do not depend on (x, y): only the stroke bounds the position.
REFUSED = [
    # accelerations of 1e308: the forces overflow (f10 ~ m·ddx)
    ([0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [1e308, 0.0, 0.0], TrajectoryError, C_OVERFLOW),
    ([0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 1e308, 0.0], TrajectoryError, C_OVERFLOW),
    ([0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [1e308, -1e308, 1e308], TrajectoryError, C_OVERFLOW),
    ([0.002, 0.0, 0.1], [0.0, 0.0, 0.0], [-1e308, 1e308, 0.0], TrajectoryError, C_OVERFLOW),
    # a rate of 1e160: its square overflows
    ([0.0, 0.0, 0.0], [0.0, 0.0, 1e160], [0.0, 0.0, 0.0], TrajectoryError, C_OVERFLOW),
    ([0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [math.nan, 0.0, 0.0], TrajectoryError, C_NOT_FINITE),
    ([0.0, math.inf, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], TrajectoryError, C_NOT_FINITE),
    ([0.0, 0.0, 0.0], [0.0, -math.inf, 0.0], [1e308, 0.0, 0.0], TrajectoryError, C_NOT_FINITE),
    ([0.0, 0.0, math.pi / 3.0], [0.0, 0.0, 0.0], [1e308, 0.0, 0.0], SingularPoseError, C_SINGULAR),
    # out of the stroke, with a pose so far that lambda10 overflows to inf - inf = NaN
    ([0.0, 0.05, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], UnreachablePoseError, C_OUTSIDE_STROKE),
    ([0.0, 0.05, 0.0], [0.0, 0.0, 0.0], [1e308, 0.0, 0.0], UnreachablePoseError, C_OUTSIDE_STROKE),
]


@pytest.fixture(scope="module")
def stroke_robot(tmp_path_factory: pytest.TempPathFactory) -> Compiled:
    return build(Robot(limits=Limits(stroke=STROKE)), tmp_path_factory.mktemp("stroke"))


@pytest.mark.parametrize(("pose", "velocity", "acceleration", "error", "status"), REFUSED)
def test_every_refusal_has_its_code_and_nan_outputs(
    paper_robot: Compiled,
    stroke_robot: Compiled,
    pose: list[float],
    velocity: list[float],
    acceleration: list[float],
    error: type[Exception],
    status: int,
) -> None:
    robot = Robot(limits=Limits(stroke=STROKE))
    # prp3's Python entry refuses the same sample, with the error of the same kind
    with pytest.raises(error, match="overflow" if status == C_OVERFLOW else None):
        sample_forces(compile_robot(robot), pose, velocity, acceleration)
    code, outputs = stroke_robot(pose, velocity, acceleration)
    assert code == status and np.isnan(outputs).all()
    if status != C_OUTSIDE_STROKE:  # without a stroke: the same code
        code, outputs = paper_robot(pose, velocity, acceleration)
        assert code == status and np.isnan(outputs).all()


def test_the_stroke_refuses_a_displacement_that_overflows(stroke_robot: Compiled) -> None:
    # lambda10 = inf - inf = NaN, not a number inside the stroke; and inf itself
    for pose in ([1e308, -1e308, 0.0], [-1e308, 1e308, 0.0], [1e308, 0.0, 0.0]):
        code, outputs = stroke_robot(pose, np.zeros(3), np.zeros(3))
        assert code == C_OUTSIDE_STROKE and np.isnan(outputs).all(), pose


@settings(max_examples=40)
@given(
    pose=poses(0.3),
    rates=st.lists(st.floats(-5.0, 5.0), min_size=3, max_size=3),
    exponent=st.integers(300, 308),
    signs=st.lists(st.sampled_from([-1.0, 0.0, 1.0]), min_size=2, max_size=2),
)
def test_ok_only_with_finite_outputs(
    paper_robot: Compiled, pose, rates: list[float], exponent: int, signs: list[float]
) -> None:
    """Huge translational accelerations: the C returns OK exactly when the kernel's nine forces
    (prp3 on Python floats, unchecked) are finite, and then their numbers; else the overflow
    code, never OK with a non-finite output."""
    acceleration = [signs[0] * 10.0**exponent, signs[1] * 10.0**exponent, 1.0]
    code, outputs = paper_robot(pose, rates, acceleration)
    f = sample_forces_unchecked(compile_robot(Robot()), *pose, *rates, *acceleration)
    expected = np.array([f[0:3], f[6:9], f[9:12]])  # f10, f21y, f21z (p10 is not in the C)
    if np.isfinite(expected).all():
        assert code == C_OK and np.isfinite(outputs).all()
        assert np.abs(outputs - expected).max() <= 1e-12 * np.abs(expected).max()
    else:
        assert code == C_OVERFLOW and np.isnan(outputs).all()


def test_every_return_code_is_defined_and_explained_in_the_header() -> None:
    header = c_inverse_dynamics(Robot()).header
    values = [value for _, value, _ in RETURN_CODES]
    assert values == list(range(len(values)))  # distinct, 0 = OK
    for name, value, _ in RETURN_CODES:
        line = next(line for line in header.splitlines() if line.startswith(f"#define {name} "))
        assert re.fullmatch(rf"#define {name} {value} /\* \S.* \*/", line), line
    assert "PRP3_OVERFLOW 5 /* the inputs are finite, an output is not" in header
    assert "PRP3_OUTSIDE_STROKE 3 /* never returned" in header  # the paper's robot: no stroke
    stroked = c_inverse_dynamics(Robot(limits=Limits(stroke=STROKE))).header
    assert "PRP3_OUTSIDE_STROKE 3 /* an actuator displacement lambda10 is outside" in stroked


def test_source_is_strict_c99_with_only_math_h() -> None:
    code = c_inverse_dynamics(Robot(limits=Limits(stroke=(-0.1, 0.1))))
    check_strict_c99(code, "double f10[3], double f21y[3], double f21z[3]")
    assert "0.3;" in code.source  # l0 as a constant


def test_cli_export_c_with_a_robot_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    robot_file = tmp_path / "robot.toml"
    robot_file.write_text("l0 = 0.4\n[platform]\nmass = 5.0\n")
    out = tmp_path / "c"
    assert main(["export", "c", "--robot", str(robot_file), "--output", str(out)]) == 0
    assert sorted(p.name for p in out.iterdir()) == sorted(
        [".prp3-manifest.json", HEADER_NAME, SOURCE_NAME]
    )
    assert "l0 = 0.4 m" in (out / SOURCE_NAME).read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text("l0 = -1\n")
    assert main(["export", "c", "--robot", str(bad), "--output", str(tmp_path / "no")]) == 2
    err = capsys.readouterr().err
    assert "l0 must be a positive" in err and not (tmp_path / "no").exists()


@settings(max_examples=4)
@given(
    robot=robots(),
    stiffness=st.floats(0.0, 5e3),
    rest=st.floats(-0.05, 0.05),
    damping=st.floats(0.0, 50.0),
    data=st.data(),
)
def test_the_actuator_spring_is_in_the_c_code(
    tmp_path_factory: pytest.TempPathFactory,
    robot: Robot,
    stiffness: float,
    rest: float,
    damping: float,
    data: st.DataObject,
) -> None:
    # the spring's element supports C: its constants appear and the numbers are the kernel's
    # (batch path) and the independent Newton-Euler solver's, which adds the spring itself
    spring = Spring(SpringParameters(stiffness=stiffness, rest=rest, damping=damping))
    robot = replace(robot, spring=spring)
    code = c_inverse_dynamics(robot)
    for name, value in (("stiffness", stiffness), ("rest", rest), ("damping", damping)):
        assert (f"prp3_spring_{name} = " in code.source) == (
            value != 0.0 and (name != "rest" or stiffness != 0.0)
        )
    compiled = build(robot, tmp_path_factory.mktemp("spring"))
    pose = np.stack([data.draw(poses(robot.l0)) for _ in range(10)])
    rates = st.lists(st.floats(-5.0, 5.0), min_size=30, max_size=30)
    velocity = np.array(data.draw(rates)).reshape(10, 3)
    acceleration = 10.0 * np.array(data.draw(rates)).reshape(10, 3)
    assert _compare(compiled, robot, pose, velocity, acceleration) <= 1e-12
    motion = Motion(t=np.arange(10.0), pose=pose, velocity=velocity, acceleration=acceleration)
    kin, reference = inverse_dynamics(robot, motion, method="newton-euler")
    free = inverse_dynamics(replace(robot, spring=None), motion, method="newton-euler")[1]
    lam, dlam = kin.geometry.lambda10, kin.dlambda10
    # the spring's own force, from the outputs: f10 = f10(no spring) + k(λ10 − rest) + c·λ̇10
    assert np.allclose(
        reference.f10 - free.f10, stiffness * (lam - rest) + damping * dlam, rtol=0, atol=1e-9
    )
    for k in range(10):
        status, got = compiled(pose[k], velocity[k], acceleration[k])
        want = np.stack([reference.f10[k], reference.f21y[k], reference.f21z[k]])
        assert status == 0 and np.abs(got - want).max() <= 1e-9 * (np.abs(want).max() + 1.0)


@pytest.mark.parametrize(
    ("robot", "element"),
    [
        (Robot(load=Load(force=(1.0, 0.0))), "[load]"),
        (Robot(friction=Friction(revolute=JointFriction(viscous=0.1))), "[friction.actuator]"),
        (
            Robot(spring=Spring(SpringParameters(stiffness=1.0)), load=Load(moment=1.0)),
            "[load]",
        ),
    ],
)
def test_an_element_the_c_code_does_not_support_is_refused_by_name(
    robot: Robot, element: str
) -> None:
    with pytest.raises(ParameterError, match=re.escape(f"not {element}")):
        c_inverse_dynamics(robot)


@settings(max_examples=3)
@given(
    robot=robots(),
    revolute=st.tuples(st.floats(0.0, 20.0), st.floats(-0.5, 0.5), st.floats(0.0, 2.0)),
    sleeve=st.tuples(st.floats(0.0, 500.0), st.floats(-0.1, 0.1), st.floats(0.0, 20.0)),
    data=st.data(),
)
def test_the_passive_joints_springs_are_in_the_c_code(
    tmp_path_factory: pytest.TempPathFactory,
    robot: Robot,
    revolute: tuple[float, float, float],
    sleeve: tuple[float, float, float],
    data: st.DataObject,
) -> None:
    # [spring.revolute] and [spring.sleeve] are compiled into the C code: its numbers are
    # the independent Newton-Euler solver's, which applies both springs itself
    spring = Spring(
        revolute=SpringParameters(*revolute, kind="revolute"),
        sleeve=SpringParameters(*sleeve, kind="sleeve"),
    )
    robot = replace(robot, spring=spring)
    compiled = build(robot, tmp_path_factory.mktemp("passive_springs"))
    pose = np.stack([data.draw(poses(robot.l0)) for _ in range(6)])
    rates = st.lists(st.floats(-5.0, 5.0), min_size=18, max_size=18)
    velocity = np.array(data.draw(rates)).reshape(6, 3)
    acceleration = 10.0 * np.array(data.draw(rates)).reshape(6, 3)
    motion = Motion(t=np.arange(6.0), pose=pose, velocity=velocity, acceleration=acceleration)
    _, reference = inverse_dynamics(robot, motion, method="newton-euler")
    for k in range(6):
        status, got = compiled(pose[k], velocity[k], acceleration[k])
        want = np.stack([reference.f10[k], reference.f21y[k], reference.f21z[k]])
        assert status == 0 and np.abs(got - want).max() <= 1e-9 * (np.abs(want).max() + 1.0)
