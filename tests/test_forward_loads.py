"""Forward dynamics with a payload, a constant load and joint friction.

Expected values are built independently of the code under test: the inverse
dynamics (three methods agree on it, tests/test_loads_friction.py) drives the
forward dynamics and must be reproduced; the payload's share of ``A = ∂f10/∂q̈``
is its rigid-body mass matrix written by hand, mapped by ``J⁻ᵀ``; the constant
load's share of ``b`` is statics (virtual work); pure viscous actuator friction
adds ``b_a·λ̇10`` to ``b``.
"""

from __future__ import annotations

import contextlib
import io
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from prp3 import Motion, Robot, inverse_dynamics, paper_motion
from prp3.analysis.equations_of_motion import open_loop_growth_rate, platform_dynamics
from prp3.analysis.force_histories import ActuatorForces
from prp3.analysis.forward import forward_dynamics
from prp3.cli import main
from prp3.engines.compiled_robot import compile_robot
from prp3.engines.sample_entries import sample_actuator_forces
from prp3.errors import ParameterError
from prp3.io.tables import write_table_csv
from prp3.mechanics.geometry import inverse_geometry
from prp3.mechanics.kinematics import jacobian
from prp3.model.motion import PAPER_MOTIONS
from prp3.model.parameters import Friction, JointFriction, Load, Payload, Spring, SpringParameters


def floats(low: float, high: float) -> st.SearchStrategy[float]:
    return st.floats(low, high, allow_nan=False, allow_infinity=False)


@st.composite
def smoothed_robots(draw: st.DrawFn) -> Robot:
    """The paper's robot with a random payload, load and smoothed viscous/Coulomb friction."""

    def joint() -> JointFriction:
        return JointFriction(
            viscous=draw(floats(0.0, 5.0)),
            coulomb=draw(floats(0.0, 3.0)),
            smoothing=draw(floats(0.05, 0.5)),
        )

    return Robot(
        payload=Payload(
            mass=draw(floats(0.0, 2.0)),
            com=(draw(floats(-0.1, 0.1)), draw(floats(-0.1, 0.1))),
            inertia=draw(floats(0.0, 0.01)),
        ),
        load=Load(force=(draw(floats(-10, 10)), draw(floats(-10, 10))), moment=draw(floats(-1, 1))),
        friction=Friction(joint(), joint(), joint()),
    )


def _exact_forces(robot: Robot, name: str):  # type: ignore[no-untyped-def]
    """f10(t) of the paper's motion (eq. 4) by the inverse dynamics at any t.

    The kernel's single-sample path, compiled once (the three methods agree on
    it, tests/test_loads_friction.py); Newton–Euler per call would take minutes.
    """
    star = np.array(PAPER_MOTIONS[name])
    w = math.pi / 3.0
    compiled = compile_robot(robot)

    def f10(t: float) -> np.ndarray:
        pose = star * (1.0 - math.cos(w * t))
        velocity = star * w * math.sin(w * t)
        acceleration = star * w * w * math.cos(w * t)
        return np.array(sample_actuator_forces(compiled, pose, velocity, acceleration))

    return f10


def test_the_kernel_forces_are_newton_euler_s() -> None:
    robot = Robot(load=Load((1.0, 2.0), 0.1), payload=Payload(0.3, (0.01, 0.02), 1e-3),
                  friction=Friction(sleeve=JointFriction(viscous=1.0, coulomb=0.5, smoothing=0.1)))  # fmt: skip
    w = math.pi / 3.0
    star = np.array(PAPER_MOTIONS["rotation"])
    motion = Motion(0.7, star * (1 - math.cos(0.7 * w)), star * w * math.sin(0.7 * w),
                    star * w * w * math.cos(0.7 * w))  # fmt: skip
    expected = inverse_dynamics(robot, motion, "newton-euler")[1].f10
    np.testing.assert_allclose(
        _exact_forces(robot, "rotation")(0.7), expected, rtol=1e-12, atol=1e-12
    )


@settings(max_examples=2, deadline=None)
@given(robot=smoothed_robots(), name=st.sampled_from(["vertical", "rotation"]))
def test_inverse_forces_with_loads_and_friction_drive_the_motion_back(
    robot: Robot, name: str
) -> None:
    # open loop diverges ~e^{6.2 t}: a 1.5 s window of the motion
    reference = paper_motion(name, samples=31)
    window = reference.t <= 1.0
    t = reference.t[window]
    result = forward_dynamics(
        robot, _exact_forces(robot, name), t, reference.pose[0], reference.velocity[0],
        rtol=1e-10, atol=1e-13,
    )  # fmt: skip
    assert result.status == "completed", result.message
    assert np.abs(result.motion.pose - reference.pose[window]).max() <= 1e-8
    assert np.abs(result.motion.velocity - reference.velocity[window]).max() <= 1e-8
    assert np.abs(result.motion.acceleration - reference.acceleration[window]).max() <= 1e-6
    assert result.force_residual <= 1e-9
    assert result.dynamics.fric10 is not None  # the friction columns are reported


def test_sampled_forces_of_a_loaded_robot_with_friction() -> None:
    robot = Robot(
        payload=Payload(0.5, (0.02, 0.0), 1e-3),
        load=Load((2.0, -3.0), 0.1),
        friction=Friction(
            actuator=JointFriction(viscous=2.0, coulomb=1.0, smoothing=0.01),
            revolute=JointFriction(viscous=0.01, coulomb=0.005, smoothing=0.05),
            sleeve=JointFriction(viscous=1.0, coulomb=0.5, smoothing=0.01),
        ),
    )
    # 61 samples: the spline is off the exact forces by ~1e-5 N, open loop grows it
    reference = paper_motion("vertical", samples=61)
    _, dyn = inverse_dynamics(robot, reference, "newton-euler")
    early = reference.t <= 1.0
    result = forward_dynamics(
        robot, ActuatorForces(reference.t, dyn.f10), reference.t[early], reference.pose[0],
        reference.velocity[0],
    )  # fmt: skip
    assert np.abs(result.motion.pose - reference.pose[early]).max() <= 1e-5
    np.testing.assert_allclose(result.dynamics.f10, dyn.f10[early], atol=1e-9)


# ------------------------------------------------------- the pieces by hand
def _J(pose: list[float]) -> np.ndarray:
    return np.asarray(jacobian(inverse_geometry(Robot(), pose)))


def test_payload_adds_its_rigid_body_mass_matrix() -> None:
    # A payload of mass mp with centre c (platform frame) and inertia Ip about it adds,
    # in q = (x, y, φ), the mass matrix [[mp, 0, −mp·c'y], [0, mp, mp·c'x],
    # [−mp·c'y, mp·c'x, Ip + mp|c|²]] with c' = Rot(φ)·c; so A = J⁻ᵀ·M gains J⁻ᵀ·M_p.
    pose, mp, c, Ip = [0.01, -0.02, 0.2], 0.7, (0.03, -0.02), 2e-3
    cx = math.cos(pose[2]) * c[0] - math.sin(pose[2]) * c[1]
    cy = math.sin(pose[2]) * c[0] + math.cos(pose[2]) * c[1]
    Mp = np.array(
        [
            [mp, 0.0, -mp * cy],
            [0.0, mp, mp * cx],
            [-mp * cy, mp * cx, Ip + mp * (c[0] ** 2 + c[1] ** 2)],
        ]
    )
    bare = platform_dynamics(Robot(), pose, [0.0, 0.0, 0.0])
    held = platform_dynamics(Robot(payload=Payload(mp, c, Ip)), pose, [0.0, 0.0, 0.0])
    expected = np.linalg.solve(_J(pose).T, Mp)
    np.testing.assert_allclose(held.force_matrix - bare.force_matrix, expected, atol=1e-12)
    np.testing.assert_allclose(held.mass_matrix - bare.mass_matrix, Mp, atol=1e-12)
    # its weight at rest: Jᵀ·Δb = mp·g·(0, 1, c'x)
    weight = mp * 9.81 * np.array([0.0, 1.0, cx])
    np.testing.assert_allclose(
        held.force_bias - bare.force_bias, np.linalg.solve(_J(pose).T, weight), atol=1e-12
    )


def test_constant_load_enters_the_bias_by_statics() -> None:
    # virtual work at rest: Jᵀ·Δf10 + (F_x, F_y, M_z) = 0
    pose, wrench = [-0.02, 0.01, -0.1], np.array([3.0, -4.0, 0.25])
    bare = platform_dynamics(Robot(), pose, [0.01, 0.02, -0.1])
    load = Load((3.0, -4.0), 0.25)
    loaded = platform_dynamics(Robot(load=load), pose, [0.01, 0.02, -0.1])
    np.testing.assert_allclose(loaded.force_matrix, bare.force_matrix, atol=1e-13)
    np.testing.assert_allclose(
        loaded.force_bias - bare.force_bias, -np.linalg.solve(_J(pose).T, wrench), atol=1e-12
    )


def test_viscous_actuator_friction_adds_b_times_the_actuator_rate() -> None:
    pose, velocity, b = [0.02, 0.0, 0.1], np.array([0.05, -0.03, 0.2]), 3.5
    bare = platform_dynamics(Robot(), pose, velocity)
    rubbed = platform_dynamics(
        Robot(friction=Friction(actuator=JointFriction(viscous=b))), pose, velocity
    )
    np.testing.assert_allclose(rubbed.force_matrix, bare.force_matrix, atol=1e-13)
    np.testing.assert_allclose(
        rubbed.force_bias - bare.force_bias, b * _J(pose) @ velocity, atol=1e-12
    )


# ---------------------------------------------------------------- refusals
@pytest.mark.parametrize("kind", ["actuator", "revolute", "sleeve"])
def test_exact_sign_coulomb_and_mu_terms_are_refused(kind: str) -> None:
    still = [0.0, 0.0, 0.0]
    exact = Robot(friction=Friction(**{kind: JointFriction(coulomb=1.0)}))  # type: ignore[arg-type]
    with pytest.raises(
        ParameterError, match=rf"friction\.{kind}\.coulomb = 1\.0 .*friction\.{kind}\.smoothing > 0"
    ):
        forward_dynamics(exact, lambda t: np.zeros(3), [0.0, 0.1], still, still)
    with pytest.raises(ParameterError, match=rf"friction\.{kind}\.coulomb"):
        platform_dynamics(exact, still, still)
    extra = {"pin_radius": 0.01} if kind == "revolute" else {}
    exact_mu = Robot(friction=Friction(**{kind: JointFriction(mu=0.1, **extra)}))  # type: ignore[arg-type]
    with pytest.raises(
        ParameterError, match=rf"friction\.{kind}\.mu = 0\.1 with smoothing = 0 \(the exact sign\)"
    ):
        forward_dynamics(exact_mu, lambda t: np.zeros(3), [0.0, 0.1], still, still)
    mu = Robot(friction=Friction(**{kind: JointFriction(mu=0.1, smoothing=0.1, **extra)}))  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="mu terms make f10 non-affine"):
        platform_dynamics(mu, still, still)  # no A·q̈ + b form; forward_dynamics iterates


def test_open_loop_growth_rate_ignores_friction_that_vanishes_at_rest() -> None:
    # s(0) = 0 and no viscous force at rest: the linearised motion there is the bare robot's
    sticky = Robot(
        friction=Friction(
            actuator=JointFriction(viscous=5.0, coulomb=1.0, mu=0.1, smoothing=0.01),
            sleeve=JointFriction(mu=0.2, smoothing=0.01),
        )
    )
    pose = [0.02, -0.01, 0.1]
    assert open_loop_growth_rate(sticky, pose) == open_loop_growth_rate(Robot(), pose) > 0.0


def test_mu_terms_drive_the_motion_back() -> None:
    """Forces of Newton–Euler with load-dependent friction integrate back to the planned motion.

    The μ terms make f10 non-linear in q̈ (the reactions depend on it): the
    forward dynamics solves for q̈ by chord iterations on the kernel's f10.
    Expected: the planned poses (the paper's law), to the integration and
    force-spline error; the same forces on the robot without μ terms go elsewhere.
    """
    smooth = {"smoothing": 0.01}
    robot = Robot(
        payload=Payload(mass=0.5),
        friction=Friction(
            actuator=JointFriction(viscous=2.0, coulomb=0.5, mu=0.05, **smooth),
            revolute=JointFriction(mu=0.05, pin_radius=0.01, **smooth),
            sleeve=JointFriction(viscous=1.0, mu=0.1, **smooth),
        ),
    )
    planned = paper_motion("vertical", samples=1501)[:51]  # 0.1 s, steps of 2 ms
    forces = ActuatorForces(
        t=planned.t, f10=inverse_dynamics(robot, planned, "newton-euler")[1].f10
    )
    start = (planned.pose[0], planned.velocity[0])
    back = forward_dynamics(robot, forces, planned.t, *start)
    assert back.status == "completed"
    assert np.abs(back.motion.pose - planned.pose).max() < 1e-8
    assert back.force_residual < 1e-9  # the kernel's f10 (μ solved) at the integrated states
    no_mu = replace(
        robot,
        friction=Friction(
            actuator=JointFriction(viscous=2.0, coulomb=0.5, **smooth),
            sleeve=JointFriction(viscous=1.0),
        ),
    )
    other = forward_dynamics(no_mu, forces, planned.t, *start)
    assert np.abs(other.motion.pose[-1] - planned.pose[other.motion.t.size - 1]).max() > 1e-6


def _cli(*args: object) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main([str(a) for a in args])
    return status, out.getvalue(), err.getvalue()


def test_cli_refuses_exact_sign_coulomb_in_one_line(tmp_path: Path) -> None:
    robot = tmp_path / "robot.toml"
    robot.write_text("[friction.sleeve]\ncoulomb = 0.5\n")
    forces = tmp_path / "forces.csv"
    write_table_csv(
        forces, {"t": np.array([0.0, 1.0]), **{f"f10_{leg}": np.zeros(2) for leg in "ABC"}}
    )
    status, out, err = _cli(
        "forward", "--robot", robot, "--forces", forces, "--output", tmp_path / "o"
    )
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and str(robot) in err and "friction.sleeve.smoothing > 0" in err
    assert not (tmp_path / "o").exists()


def test_cli_forward_reads_the_results_of_a_robot_with_friction(tmp_path: Path) -> None:
    robot = tmp_path / "robot.toml"
    robot.write_text(
        "[payload]\nmass = 0.5\n[load]\nforce = [1.0, -2.0]\n"
        "[friction.actuator]\nviscous = 2.0\ncoulomb = 1.0\nsmoothing = 0.01\n"
    )
    status, _, err = _cli(
        "simulate", "--robot", robot, "--motion", "vertical", "--samples", 31,
        "--output", tmp_path / "inv",
    )  # fmt: skip
    assert status == 0, err
    status, _, err = _cli(
        "forward", "--robot", robot, "--forces", tmp_path / "inv" / "results.csv",
        "--rtol", 1e-6, "--atol", 1e-9, "--output", tmp_path / "fwd",
    )  # fmt: skip
    # open loop with a coarse spline: it may drift into the singularity near the end
    assert status == 0 or (status == 1 and "singularity" in err), err
    header = (tmp_path / "fwd" / "results.csv").read_text().splitlines()[0].split(",")
    assert "fric10_A" in header
    table = np.genfromtxt(tmp_path / "fwd" / "results.csv", delimiter=",", names=True)
    reference = paper_motion("vertical", samples=31)
    early = reference.t <= 1.5  # a coarse spline and a loose tolerance, unstable open loop
    np.testing.assert_array_equal(table["t"][: early.sum()], reference.t[early])
    assert np.abs(table["y"][: early.sum()] - reference.pose[early, 1]).max() < 1e-3


def test_cli_forward_with_mu_terms_drives_the_motion_back(tmp_path: Path) -> None:
    """``prp3 simulate`` then ``prp3 forward`` of a robot with load-dependent friction (0.1 s)."""
    robot = tmp_path / "robot.toml"
    robot.write_text("[friction.sleeve]\nmu = 0.05\nsmoothing = 0.01\n")
    planned = paper_motion("vertical", samples=1501)[:51]  # 0.1 s, steps of 2 ms
    trajectory = tmp_path / "path.csv"
    columns = {"t": planned.t}
    for k, name in enumerate(("x", "y", "phi")):
        columns[name] = planned.pose[:, k]
        columns["d" + name] = planned.velocity[:, k]
        columns["dd" + name] = planned.acceleration[:, k]
    write_table_csv(trajectory, columns)
    args = ["--robot", robot]
    status, _, err = _cli("simulate", *args, "--trajectory", trajectory, "-o", tmp_path / "inv")
    assert status == 0, err
    results = tmp_path / "inv" / "results.csv"
    status, out, err = _cli("forward", *args, "--forces", results, "-o", tmp_path / "fwd")
    assert status == 0, err
    table = np.genfromtxt(tmp_path / "fwd" / "results.csv", delimiter=",", names=True)
    back = np.stack([table["x"], table["y"], table["phi"]], axis=-1)
    assert np.abs(back - planned.pose).max() < 1e-7  # the force spline of 2 ms steps
    assert "drift from the planned motion" in out


# --------------------------------------------------------- the actuator spring
@settings(max_examples=20, deadline=None)
@given(
    stiffness=floats(0.0, 2e3),
    rest=floats(-0.05, 0.05),
    damping=floats(0.0, 20.0),
    pose=st.tuples(floats(-0.05, 0.05), floats(-0.05, 0.05), floats(-0.3, 0.3)),
    velocity=st.tuples(floats(-0.5, 0.5), floats(-0.5, 0.5), floats(-1.0, 1.0)),
)
def test_the_spring_enters_b_as_its_own_force(
    stiffness: float,
    rest: float,
    damping: float,
    pose: tuple[float, float, float],
    velocity: tuple[float, float, float],
) -> None:
    # f10 = A·q̈ + b: the spring adds k·(λ10 − rest) + c·λ̇10 to b (λ10 by the closed-form
    # inverse geometry, λ̇10 = J·q̇), and nothing to A
    robot = Robot(spring=Spring(SpringParameters(stiffness, rest, damping)))
    q, qd = np.array(pose), np.array(velocity)
    with_spring, free = platform_dynamics(robot, q, qd), platform_dynamics(Robot(), q, qd)
    geometry = inverse_geometry(robot, q)
    expected = stiffness * (geometry.lambda10 - rest) + damping * (jacobian(geometry) @ qd)
    scale = np.abs(free.force_bias).max() + np.abs(expected).max()
    assert np.abs(with_spring.force_bias - free.force_bias - expected).max() <= 1e-13 * scale
    assert (
        np.abs(with_spring.force_matrix - free.force_matrix).max()
        <= 1e-13 * np.abs(free.force_matrix).max()
    )


def test_the_spring_forces_of_newton_euler_drive_the_motion_back() -> None:
    # forces of Newton–Euler (which adds the spring itself) integrate back to the plan;
    # the same forces on the robot without its spring go elsewhere
    robot = Robot(spring=Spring(SpringParameters(stiffness=800.0, rest=0.01, damping=5.0)))
    planned = paper_motion("vertical", samples=1501)[:51]  # 0.1 s, steps of 2 ms
    forces = ActuatorForces(
        t=planned.t, f10=inverse_dynamics(robot, planned, "newton-euler")[1].f10
    )
    start = (planned.pose[0], planned.velocity[0])
    back = forward_dynamics(robot, forces, planned.t, *start)
    assert back.status == "completed"
    assert np.abs(back.motion.pose - planned.pose).max() < 1e-8
    other = forward_dynamics(Robot(), forces, planned.t, *start)
    assert np.abs(other.motion.pose[-1] - planned.pose[other.motion.t.size - 1]).max() > 1e-6


def test_cli_forward_with_a_spring_drives_the_motion_back(tmp_path: Path) -> None:
    robot = tmp_path / "robot.toml"
    robot.write_text("[spring.actuator]\nstiffness = 500.0\nrest = -0.01\ndamping = 2.0\n")
    planned = paper_motion("vertical", samples=1501)[:51]
    trajectory = tmp_path / "path.csv"
    columns = {"t": planned.t}
    for k, name in enumerate(("x", "y", "phi")):
        columns[name] = planned.pose[:, k]
        columns["d" + name] = planned.velocity[:, k]
        columns["dd" + name] = planned.acceleration[:, k]
    write_table_csv(trajectory, columns)
    args = ["--robot", robot]
    status, _, err = _cli("simulate", *args, "--trajectory", trajectory, "-o", tmp_path / "inv")
    assert status == 0, err
    results = tmp_path / "inv" / "results.csv"
    status, _, err = _cli("forward", *args, "--forces", results, "-o", tmp_path / "fwd")
    assert status == 0, err
    table = np.genfromtxt(tmp_path / "fwd" / "results.csv", delimiter=",", names=True)
    back = np.stack([table["x"], table["y"], table["phi"]], axis=-1)
    assert np.abs(back - planned.pose).max() < 1e-7
