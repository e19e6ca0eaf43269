"""The family's generated C (``prp3.family.codegen``, ``prp3 export c``): strict C99, the numbers, the codes.

The code of each robot is compiled with the system's C compiler (``-std=c99
-pedantic-errors -Wall -Wextra -Werror``; skipped without one), loaded with
ctypes and compared with prp3's family route (``family_inverse_dynamics``,
the numpy fast route: angles, ``atan2`` and batched 3×3 inverses, another
path than the C's rotation pairs) to 1e-12 relative to the largest output of
the sample: ``tau`` and every joint wrench, for every architecture and
allowed actuation along the paper's motions, and on hypothesis-random
designs, inertias, payloads, loads and motions.  The return codes: 1 for a
non-finite input, 2 at a leg or parallel singularity, 4 out of reach; NaN
outputs then.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from ctools import COMPILER, InverseDynamicsLibrary, check_strict_c99, shared_library, write_code
from prp3.apps.codegen import (
    C_NOT_FINITE,
    C_OK,
    C_OVERFLOW,
    C_SINGULAR,
    HEADER_NAME,
    RETURN_CODES,
    SOURCE_NAME,
)
from prp3.cli import main
from prp3.errors import SingularPoseError, TrajectoryError, UnreachablePoseError
from prp3.family import ARCHITECTURES, FamilyRobot, family_inverse_dynamics
from prp3.family.codegen import C_UNREACHABLE, family_c_inverse_dynamics, python_sample
from prp3.model.motion import Motion, paper_motion
from strategies import FAMILY_ALLOWED, family_designs, family_motions, loaded_family_robot

pytestmark = pytest.mark.skipif(COMPILER is None, reason="no C compiler")

CROSSING = {("3-PRR", 2, "rotation")}


#: ``prp3_inverse_dynamics`` of a shared library: the return code and ``[tau (3), joint (27)]``.
Compiled = InverseDynamicsLibrary


def build(robot: FamilyRobot, folder: Path) -> Compiled:
    return build_from(write_code(family_c_inverse_dynamics(robot), folder))


def build_from(folder: Path) -> Compiled:
    return Compiled(shared_library(folder, "libprp3family.so"), (3, 27), np.concatenate)


def expected(robot: FamilyRobot, motion: Motion) -> np.ndarray:
    """``[tau (3), joint (27)]`` per sample from the family route, shape ``(N, 30)``."""
    solution = family_inverse_dynamics(robot, motion)
    joint = np.concatenate([solution.force, solution.moment[..., None]], axis=-1)
    return np.concatenate([solution.tau, joint.reshape(-1, 27)], axis=1)


def worst_error(compiled: Compiled, robot: FamilyRobot, motion: Motion) -> float:
    want = expected(robot, motion)
    worst = 0.0
    for k in range(motion.samples):
        code, got = compiled(motion.pose[k], motion.velocity[k], motion.acceleration[k])
        assert code == 0
        scale = max(float(np.abs(want[k]).max()), 1e-9)
        worst = max(worst, float(np.abs(got - want[k]).max()) / scale)
    return worst


@pytest.mark.parametrize(("arch", "act"), FAMILY_ALLOWED)
def test_every_actuation_matches_the_family_route(
    tmp_path_factory: pytest.TempPathFactory, arch: str, act: int
) -> None:
    robot = loaded_family_robot(arch, act)
    compiled = build(robot, tmp_path_factory.mktemp(f"{arch}-{act}"))
    for name in ("vertical", "rotation"):
        if (arch, act, name) in CROSSING:
            continue
        assert worst_error(compiled, robot, paper_motion(name, 41)) <= 1e-12, name


def test_python_steps_match_the_family_route() -> None:
    """The generated steps on Python floats (no compiler), the same check."""
    for arch, act in FAMILY_ALLOWED:
        robot = loaded_family_robot(arch, act)
        motion = paper_motion("vertical", 9)
        want = expected(robot, motion)
        for k in range(motion.samples):
            code, got = python_sample(
                robot, motion.pose[k], motion.velocity[k], motion.acceleration[k]
            )
            assert code == 0
            assert np.abs(np.array(got) - want[k]).max() <= 1e-12 * np.abs(want[k]).max()


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_random_designs_match_the_family_route(
    tmp_path_factory: pytest.TempPathFactory, data: st.DataObject
) -> None:
    robot = data.draw(family_designs())
    motion = data.draw(family_motions(robot.home_poses.mean(axis=0), samples=9))
    try:
        expected(robot, motion)
    except (SingularPoseError, UnreachablePoseError):
        assume(False)
    compiled = build(robot, tmp_path_factory.mktemp("random"))
    assert worst_error(compiled, robot, motion) <= 1e-12


@pytest.fixture(scope="module")
def rrr(tmp_path_factory: pytest.TempPathFactory) -> Compiled:
    """The default 3-RRR through the command line ``prp3 export c``."""
    folder = tmp_path_factory.mktemp("rrr")
    robot = folder / "robot.toml"
    robot.write_text('architecture = "3-RRR"\n')
    assert main(["export", "c", "--robot", str(robot), "--output", str(folder / "c")]) == 0
    return build_from(folder / "c")


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
@pytest.mark.parametrize("where", range(9))
def test_non_finite_input_returns_1_and_nan(rrr: Compiled, where: int, bad: float) -> None:
    values = np.zeros(9)
    values[where] = bad
    code, outputs = rrr(values[:3], values[3:6], values[6:])
    assert code == 1 and np.isnan(outputs).all()


def test_out_of_reach_returns_4_and_nan(rrr: Compiled) -> None:
    # leg A's wrist O_3 = G − (−0.2, 0.1) is 0.4 m from its base pivot at most (two 0.2 m links)
    code, outputs = rrr([0.5, 0.0, 0.0], np.zeros(3), np.zeros(3))
    assert code == C_UNREACHABLE == 4 and np.isnan(outputs).all()
    with pytest.raises(UnreachablePoseError):
        family_inverse_dynamics(FamilyRobot.default("3-RRR"), Motion.at_rest([0.5, 0.0, 0.0]))


def test_a_leg_singularity_returns_2(tmp_path: Path) -> None:
    # the 3-PRP's leg measure is sin(φ − π/3) up to sign (docs/family.md §6)
    compiled = build(FamilyRobot.default("3-PRP"), tmp_path)
    for phi in (math.pi / 3.0, math.pi / 3.0 - 5e-5, 2.0):
        code, outputs = compiled([0.0, 0.0, phi], np.zeros(3), np.zeros(3))
        assert code == 2 and np.isnan(outputs).all(), phi
    code, _ = compiled([0.0, 0.0, math.pi / 3.0 - 2e-4], np.zeros(3), np.zeros(3))
    assert code == 0  # before the threshold: computed


def test_a_parallel_singularity_returns_2(tmp_path: Path) -> None:
    # the 3-PRR actuated at joint 2 meets a parallel singularity at φ = atan(1/2) (docs/family.md §3)
    robot = FamilyRobot.default("3-PRR", 2)
    compiled = build(robot, tmp_path)
    code, outputs = compiled([0.0, 0.0, math.atan(0.5)], np.zeros(3), np.zeros(3))
    assert code == 2 and np.isnan(outputs).all()
    code, _ = compiled([0.0, 0.0, 0.2], np.zeros(3), np.zeros(3))
    assert code == 0


@pytest.fixture(scope="module")
def defaults(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Compiled]:
    """The C of the default robot of every architecture (its default actuation)."""
    return {
        arch: build(FamilyRobot.default(arch), tmp_path_factory.mktemp(arch))
        for arch in ARCHITECTURES
    }


def _python_refusal(robot: FamilyRobot, pose, velocity, acceleration) -> Exception | None:
    motion = Motion(t=[0.0], pose=[pose], velocity=[velocity], acceleration=[acceleration])
    try:
        family_inverse_dynamics(robot, motion)
    except (TrajectoryError, SingularPoseError, UnreachablePoseError) as refused:
        return refused
    return None


#: Rates and accelerations that overflow the dynamics of every architecture at home.
OVERFLOWING = [
    ([0.0, 0.0, 0.0], [1e308, 0.0, 0.0]),
    ([0.0, 0.0, 0.0], [0.0, -1e308, 0.0]),
    ([0.0, 0.0, 0.0], [1e308, 1e308, 1e308]),
    ([0.0, 0.0, 0.0], [-1e308, 1e308, 0.0]),
    ([1e200, 1e200, 1e200], [0.0, 0.0, 0.0]),  # their squares
]


@pytest.mark.parametrize("arch", ARCHITECTURES)
@pytest.mark.parametrize(("velocity", "acceleration"), OVERFLOWING)
def test_an_overflow_returns_5_never_ok(
    defaults: dict[str, Compiled], arch: str, velocity: list[float], acceleration: list[float]
) -> None:
    robot = FamilyRobot.default(arch)
    home = robot.home_poses.mean(axis=0)
    refused = _python_refusal(robot, home, velocity, acceleration)
    assert isinstance(refused, TrajectoryError) and "overflow" in str(refused)
    code, outputs = defaults[arch](home, velocity, acceleration)
    assert code == C_OVERFLOW == 5 and np.isnan(outputs).all()
    assert python_sample(robot, home, velocity, acceleration)[0] == C_OVERFLOW


@pytest.mark.parametrize("arch", ARCHITECTURES)
def test_every_architecture_refuses_a_non_finite_input(
    defaults: dict[str, Compiled], arch: str
) -> None:
    home = FamilyRobot.default(arch).home_poses.mean(axis=0)
    for where in range(9):
        for bad in (math.nan, math.inf):
            values = np.concatenate([home, np.zeros(6)])
            values[where] = bad
            code, outputs = defaults[arch](values[:3], values[3:6], values[6:])
            assert code == C_NOT_FINITE and np.isnan(outputs).all(), (where, bad)
            inputs = (values[:3], values[3:6], values[6:])
            assert python_sample(FamilyRobot.default(arch), *inputs)[0] == C_NOT_FINITE


#: A pose out of reach of the architectures whose legs have no unbounded prismatic joint to
#: reach everywhere (the other four, 3-PRP, 3-RPR, 3-PPR, 3-RPP, reach every position).
OUT_OF_REACH = {"3-RRR": [0.15, 0.0, 0.0], "3-PRR": [0.25, 0.0, 0.0], "3-RRP": [0.1, 0.0, 0.0]}


@pytest.mark.parametrize("arch", sorted(OUT_OF_REACH))
def test_every_architecture_refuses_a_pose_out_of_reach(
    defaults: dict[str, Compiled], arch: str
) -> None:
    pose = OUT_OF_REACH[arch]
    refused = _python_refusal(FamilyRobot.default(arch), pose, [0.0] * 3, [1e308, 0.0, 0.0])
    assert isinstance(refused, UnreachablePoseError)  # prp3's verdict, before the dynamics
    for acceleration in ([0.0] * 3, [1e308, 0.0, 0.0]):
        code, outputs = defaults[arch](pose, np.zeros(3), acceleration)
        assert code == C_UNREACHABLE and np.isnan(outputs).all()


@pytest.mark.parametrize("arch", ARCHITECTURES)
def test_every_architecture_computes_a_good_sample(
    defaults: dict[str, Compiled], arch: str
) -> None:
    # a sample near home, large but finite accelerations: OK and the family route's numbers
    robot = FamilyRobot.default(arch)
    home = robot.home_poses.mean(axis=0)
    cases = [
        (home + [0.01, -0.005, 0.02], [0.1, -0.2, 0.3], [2.0, -1.0, 5.0]),
        (home, [0.0, 0.0, 0.0], [1e300, -1e300, 0.0]),
    ]
    for pose, velocity, acceleration in cases:
        motion = Motion(t=[0.0], pose=[pose], velocity=[velocity], acceleration=[acceleration])
        want = expected(robot, motion)[0]
        code, got = defaults[arch](pose, velocity, acceleration)
        assert code == C_OK and np.isfinite(got).all()
        assert np.abs(got - want).max() <= 1e-12 * np.abs(want).max()


def test_a_singular_pose_with_an_overflow_returns_2(defaults: dict[str, Compiled]) -> None:
    # the singularity is found before the dynamics: its code, not the overflow's
    pose = [0.0, 0.0, math.pi / 3.0 - 5e-5]  # the 3-PRP: sin(phi - pi/3) ~ 0 (family.md section 6)
    refused = _python_refusal(FamilyRobot.default("3-PRP"), pose, [0.0] * 3, [1e308, 0.0, 0.0])
    assert isinstance(refused, SingularPoseError)
    code, outputs = defaults["3-PRP"](pose, np.zeros(3), [1e308, 0.0, 0.0])
    assert code == C_SINGULAR and np.isnan(outputs).all()


def test_every_return_code_is_in_the_header_with_its_meaning() -> None:
    header = family_c_inverse_dynamics(FamilyRobot.default("3-RRR")).header
    for name, value, _ in RETURN_CODES:
        assert re.search(rf"^#define {name} {value} /\* \S.* \*/$", header, re.M), name
    assert "#define PRP3_OVERFLOW 5 /* the inputs are finite, an output is not" in header
    assert "#define PRP3_OUTSIDE_STROKE 3 /* never returned" in header
    assert "#define PRP3_UNREACHABLE 4 /* a leg's closure has no real solution" in header


def test_source_is_strict_c99_with_only_math_h() -> None:
    code = family_c_inverse_dynamics(FamilyRobot.default("3-RPR"))
    check_strict_c99(code, "double tau[3], double joint[27]")
    assert "#define PRP3_UNREACHABLE 4" in code.header and "#define PRP3_SINGULAR 2" in code.header


def test_cli_export_c(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    robot_file = tmp_path / "robot.toml"
    robot_file.write_text('architecture = "3-PPR"\nactuated = 2\n[platform]\nmass = 5.0\n')
    out = tmp_path / "c"
    assert main(["export", "c", "--robot", str(robot_file), "--output", str(out)]) == 0
    said = capsys.readouterr().out
    assert "3-PPR" in said and "tau" in said
    assert sorted(p.name for p in out.iterdir()) == sorted(
        [".prp3-manifest.json", HEADER_NAME, SOURCE_NAME]
    )
    assert "3-PPR, actuated = 2" in (out / SOURCE_NAME).read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text('architecture = "3-PPR"\nactuated = 3\n')
    assert main(["export", "c", "--robot", str(bad), "--output", str(tmp_path / "no")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "actuated" in err and str(bad) in err
    assert not (tmp_path / "no").exists()
