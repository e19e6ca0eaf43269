"""Forward dynamics of the spatial robots (docs/spatial.md §18).

* round trip: a built-in motion, its efforts by the inverse dynamics, integrated back from
  its first state: the motion comes back (to the integrator's tolerance);
* the efforts that hold the home pose keep the platform still;
* energy balance: for constant efforts the actuators' work is ``Σ τ_i·Δq_act,i`` (the
  actuated joint values of the integrated motion by the inverse geometry) and equals the
  change of kinetic (every body's velocity from the chain) plus potential energy;
* the mass matrix ``M = J_aᵀ·A`` is symmetric positive definite, ``½ ξ_fᵀ·M·ξ_f`` is the
  kinetic energy of the bodies, and ``A`` is the central difference of the Newton–Euler
  route (route (b), not the virtual work that builds ``A``) in the free accelerations;
* ``prp3 forward`` of a spatial robot file, and its refusals (one line, exit 2).
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from clitools import cli, one_line
from prp3.errors import ParameterError, SingularPoseError, TrajectoryError, UnreachablePoseError
from prp3.spatial.dynamics import body_wrenches
from prp3.spatial.forward import (
    hold_efforts,
    spatial_forward_dynamics,
    spatial_platform_dynamics,
    state_from_joints,
)
from prp3.spatial.geometry import inverse_geometry, leg_coordinates
from prp3.spatial.kinematics import chunk_kinematics, complete_motion, spatial_kinematics
from prp3.spatial.model import Body, SpatialRobot, delta, hexapod, three_rps
from prp3.spatial.motion import PlatformMotion, spatial_motion
from prp3.spatial.newton_euler import newton_euler_dynamics
from prp3.spatial.outputs import spatial_inverse_dynamics
from spatial_strategies import deltas, hexapods, rps_robots, waves

#: docs/spatial.md §18: the round trip's largest error of the position (in units of the
#: robot's scale) and of the rotation matrix over 0.3 s.
ROUND_TRIP = 1e-7

ROBOTS = {"6-UPS": hexapod, "3-RPS": three_rps, "3-RUU": delta}
#: The 3-RPS's tilt moves its parasitic yaw, x and y (completed, docs/spatial.md §11).
MOTIONS = {"6-UPS": "tilt", "3-RPS": "tilt", "3-RUU": "circle"}


def _energy(robot: SpatialRobot, motion: PlatformMotion) -> np.ndarray:
    """Kinetic + potential energy of every body ``(N,)``: velocities from the chain (§8)."""
    kin = chunk_kinematics(robot, motion)
    w = body_wrenches(robot, kin, motion)
    g = np.array(robot.gravity)
    total = np.zeros(len(motion))
    count = len(robot.legs[0].bodies)
    for i, leg in enumerate(robot.legs):
        for k, body in enumerate(leg.bodies):
            r = kin.frames.rotation[:, i, k]
            inertia = r @ np.array(body.inertia) @ np.swapaxes(r, 1, 2)
            omega, v = w.omega[:, i, k], w.centre_velocity[:, i, k]
            total += 0.5 * body.mass * np.einsum("ni,ni->n", v, v)
            total += 0.5 * np.einsum("ni,nij,nj->n", omega, inertia, omega)
            total -= body.mass * w.centre[:, i, k] @ g
    assert count == len(robot.legs[0].bodies)
    p = robot.platform
    inertia = motion.rotation @ np.array(p.inertia) @ np.swapaxes(motion.rotation, 1, 2)
    v = w.platform_velocity
    total += 0.5 * p.mass * np.einsum("ni,ni->n", v, v)
    total += 0.5 * np.einsum("ni,nij,nj->n", motion.omega, inertia, motion.omega)
    total -= p.mass * w.platform_centre @ g
    return total


# ---------------------------------------------------------------- round trip, hold


@pytest.mark.parametrize("architecture", sorted(ROBOTS))
def test_the_efforts_of_a_motion_give_the_motion_back(architecture):
    robot = ROBOTS[architecture]()
    whole = spatial_motion(robot, MOTIONS[architecture], 301, 3.0)  # as prp3 simulate's
    motion = complete_motion(robot, whole).chunk(0, 31)  # its first 0.3 s
    tau = spatial_inverse_dynamics(robot, motion, "virtual-work").tau
    run = spatial_forward_dynamics(
        robot, tau, motion.chunk(0, 1), 0.3, t_efforts=motion.t, samples=31
    )
    assert np.array_equal(run.motion.t, motion.t)
    position = np.abs(run.motion.position - motion.position).max() / robot.scale
    rotation = np.abs(run.motion.rotation - motion.rotation).max()
    assert position < ROUND_TRIP and rotation < ROUND_TRIP
    velocity = np.abs(run.motion.velocity - motion.velocity).max() / robot.scale
    assert velocity < 100 * ROUND_TRIP  # 1/s
    # the self-check: the Newton–Euler route on the integrated motion gives the efforts back
    assert run.effort_residual < 1e-9 * np.abs(tau).max()
    assert np.abs(run.solution.tau - tau).max() < 1e-6 * np.abs(tau).max()


@pytest.mark.parametrize("architecture", sorted(ROBOTS))
def test_the_hold_efforts_keep_the_home_pose(architecture):
    """Over 0.5 s: the home pose held by constant efforts is unstable (GROWTH), and the
    round-off of the first evaluation (an acceleration of 1e-13 rad/s² for the 3-RPS, its
    small inertia amplifying the round-off of ``τ − h``) grows by e^(12.1 * 0.5) = 400 at most."""
    robot = ROBOTS[architecture]()
    run = spatial_forward_dynamics(robot, hold_efforts(robot), duration=0.5, samples=11)
    assert np.abs(run.motion.position - robot.home_position).max() < 1e-10 * robot.scale
    assert np.abs(run.motion.rotation - np.array(robot.home_rotation)).max() < 1e-10
    assert np.abs(run.motion.velocity).max() < 1e-9 * robot.scale
    # the hold efforts are the statics at home by the other route (Newton–Euler)
    home = PlatformMotion.at_rest(robot.home_position, robot.home_rotation)
    expected = newton_euler_dynamics(robot, home).tau[0]
    assert np.abs(hold_efforts(robot) - expected).max() < 1e-12 * np.abs(expected).max()


# ---------------------------------------------------------------- energy


@pytest.mark.parametrize("architecture", sorted(ROBOTS))
@settings(max_examples=2, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_the_work_of_constant_efforts_is_the_change_of_energy(architecture, seed):
    robot = ROBOTS[architecture]()
    rng = np.random.default_rng(seed)
    hold = hold_efforts(robot)
    tau = hold * (1.0 + 0.05 * rng.uniform(-1.0, 1.0, hold.shape))
    run = spatial_forward_dynamics(robot, tau, duration=0.2, samples=5)
    motion = run.motion
    actuated = robot.legs[0].actuated_coordinate
    q = inverse_geometry(robot, motion)[:, :, actuated]
    work = tau @ (q[-1] - q[0])
    energy = _energy(robot, motion)
    scale = float(np.abs(tau) @ np.abs(q[-1] - q[0])) + 1e-300
    assert abs((energy[-1] - energy[0]) - work) < 1e-10 * scale
    assert abs(energy[-1] - energy[0]) > 1e-3 * scale  # the platform moved


# ---------------------------------------------------------------- the equations of motion

ROBOT_STRATEGIES = {"6-UPS": hexapods(), "3-RPS": rps_robots(), "3-RUU": deltas()}


@settings(max_examples=4, deadline=None)
@given(st.sampled_from(sorted(ROBOTS)), st.data())
def test_the_mass_matrix_is_the_kinetic_energy_and_the_slope_of_the_efforts(architecture, data):
    robot = data.draw(ROBOT_STRATEGIES[architecture])
    wave = data.draw(waves(robot, 0.5))
    motion = complete_motion(robot, wave.motion(np.array([0.1, 0.7])))
    dynamics = spatial_platform_dynamics(robot, motion)
    mass = dynamics.mass
    size = float(np.abs(mass).max())
    assert np.abs(mass - np.swapaxes(mass, 1, 2)).max() < 1e-10 * size
    assert (np.linalg.eigvalsh(mass) > 0.0).all()
    # ½ ξ_fᵀ M ξ_f is the kinetic energy: the energy at the twist minus at rest (same pose)
    free = [i for i in range(6) if i not in robot.parasitic_index]
    twist = np.concatenate([motion.omega, motion.velocity], axis=1)[:, free]
    rest = PlatformMotion.of(motion.t, motion.position, motion.rotation)
    zero_g = SpatialRobot(
        robot.name, robot.legs, robot.platform, (0.0, 0.0, 0.0), robot.home_position,
        robot.home_rotation, robot.scale, robot.parasitic,
    )  # fmt: skip
    kinetic = _energy(zero_g, complete_motion(robot, motion)) - _energy(zero_g, rest)
    quadratic = 0.5 * np.einsum("ni,nij,nj->n", twist, mass, twist)
    assert np.abs(kinetic - quadratic).max() < 1e-10 * max(float(np.abs(kinetic).max()), 1e-300)
    # A = ∂τ/∂a_f by central differences of the Newton–Euler route at a random acceleration
    base = np.concatenate([motion.alpha, motion.acceleration], axis=1)
    h = 1e-3
    for j, c in enumerate(free):
        plus, minus = base.copy(), base.copy()
        plus[:, c] += h
        minus[:, c] -= h
        moved = [
            PlatformMotion.of(
                motion.t,
                motion.position,
                motion.rotation,
                motion.omega,
                motion.velocity,
                a[:, :3],
                a[:, 3:],
            )
            for a in (plus, minus)
        ]
        tau = [newton_euler_dynamics(robot, complete_motion(robot, m)).tau for m in moved]
        slope = (tau[0] - tau[1]) / (2 * h)
        column = dynamics.effort_matrix[:, :, j]
        assert np.abs(slope - column).max() < 1e-7 * float(np.abs(dynamics.effort_matrix).max())


#: docs/spatial.md §18: the rates (1/s) of the linearised motion at the home pose held by
#: constant efforts, ``λ = ±sqrt(eig(∂a_f/∂x_f))``: real ones grow, imaginary ones oscillate.
GROWTH = {
    "6-UPS": [7.5, 10.2, 10.2, 10.9, 10.9, 12.3],
    "3-RPS": [3.9, 12.1, 12.1],
    "3-RUU": [6.4j, 6.4j, 5.5],
}


@pytest.mark.parametrize("architecture", sorted(ROBOTS))
def test_the_held_home_pose_is_unstable_at_the_rates_the_docs_give(architecture):
    robot = ROBOTS[architecture]()
    tau = hold_efforts(robot)
    free = [i for i in range(6) if i not in robot.parasitic_index]

    def acceleration(step: np.ndarray) -> np.ndarray:  # a_f at home moved by the free coordinates
        p, phi = np.array(robot.home_position), np.zeros(3)
        for j, c in enumerate(free):
            if c < 3:
                phi[c] += step[j]
            else:
                p[c - 3] += step[j]
        rotation = Rotation.from_rotvec(phi).as_matrix() @ np.array(robot.home_rotation)
        d = spatial_platform_dynamics(robot, PlatformMotion.of([0.0], p, rotation))
        return np.linalg.solve(d.effort_matrix[0], tau - d.effort_bias[0])

    h, eye = 1e-6, np.eye(len(free))
    stiffness = np.stack(
        [
            (acceleration(h * eye[j]) - acceleration(-h * eye[j])) / (2 * h)
            for j in range(len(free))
        ],
        axis=1,
    )
    rates = np.sqrt(np.linalg.eigvals(stiffness).astype(complex))
    rates = sorted(rates, key=lambda r: (abs(r.imag) < 1e-6, abs(r)))
    expected = sorted(np.array(GROWTH[architecture], dtype=complex),
                      key=lambda r: (abs(r.imag) < 1e-6, abs(r)))  # fmt: skip
    assert np.allclose(rates, expected, atol=0.051)


def test_a_state_comes_back_from_the_joint_values():
    robot = three_rps()
    motion = complete_motion(robot, spatial_motion(robot, "tilt", 7, 1.0))
    kin = spatial_kinematics(robot, motion)
    state = state_from_joints(robot, motion.t, kin.q, kin.dq)
    assert np.abs(state.position - motion.position).max() < 1e-14
    assert np.abs(state.rotation - motion.rotation).max() < 1e-14
    assert np.abs(state.omega - motion.omega).max() < 1e-13
    assert np.abs(state.velocity - motion.velocity).max() < 1e-14


# ---------------------------------------------------------------- refusals


def test_a_massless_robot_is_refused():
    none = Body(0.0, (0.0, 0.0, 0.0), ((0.0,) * 3,) * 3, "none")
    robot = hexapod(cylinder=none, rod=none, platform=none)
    with pytest.raises(ParameterError, match="mass matrix of the 6-UPS is singular"):
        spatial_forward_dynamics(robot, np.zeros(6), duration=0.1)


def test_a_stroke_end_and_a_singularity_are_refused_naming_the_time():
    robot = hexapod()
    with pytest.raises(
        UnreachablePoseError,
        match=r"reaches a joint limit at t = 0\.\d+ s: P2 of leg 1 = 0.12 m reaches its limit 0.12 m",
    ) as error:
        spatial_forward_dynamics(robot, 1.5 * hold_efforts(robot), duration=0.4, samples=3)
    assert error.value.time is not None and 0.05 < error.value.time < 0.4
    wide = three_rps(stroke=(0.01, 0.5), r_limit=1.5, s_limit=1.5)
    tau = 0.2 * hold_efforts(wide)
    tau[0] *= 1.1
    with pytest.raises(SingularPoseError, match=r"reaches a singularity at t = 0\.\d+ s") as found:
        spatial_forward_dynamics(wide, tau, duration=0.3, samples=3)
    assert found.value.time is not None and 0.1 < found.value.time < 0.3


def test_the_bounds_stop_the_integration_saying_which():
    robot = delta()
    with pytest.raises(TrajectoryError, match="stopped by its bound max_evaluations = 5"):
        spatial_forward_dynamics(robot, hold_efforts(robot), duration=1.0, max_evaluations=5)
    with pytest.raises(TrajectoryError, match="stopped by its bound max_seconds"):
        spatial_forward_dynamics(robot, hold_efforts(robot), duration=1.0, max_seconds=1e-9)


@pytest.mark.parametrize(
    ("change", "words"),
    [
        ({"efforts": np.zeros(5)}, "efforts must have shape (6,)"),
        ({"efforts": np.full(6, np.nan)}, "efforts must be finite"),
        ({"efforts": lambda t: [1.0]}, "must return 6 finite numbers"),
        ({"efforts": np.zeros((2, 6)), "t_efforts": [0.0, 0.1]}, "outside the efforts'"),
        ({"duration": 0.0}, "duration"),
        ({"samples": 1}, "samples"),
        ({"rtol": 1e-20}, "rtol must be at least"),
        ({"initial": PlatformMotion.at_rest([[0.0, 0.0, 0.08]] * 2)}, "initial must be one"),
        ({"initial": PlatformMotion.at_rest([0.0, 0.0, 0.3])}, "initial state"),
    ],
)
def test_bad_arguments_are_refused_naming_them(change, words):
    robot = hexapod()
    arguments = {"efforts": hold_efforts(robot), "duration": 0.5, **change}
    with pytest.raises((ParameterError, TrajectoryError, UnreachablePoseError)) as error:
        spatial_forward_dynamics(robot, **arguments)
    assert words in str(error.value) and "\n" not in str(error.value)


# ---------------------------------------------------------------- the command line


def _read_csv(path: Path) -> dict[str, np.ndarray]:
    with path.open(newline="") as stream:
        rows = list(csv.reader(stream))
    values = np.array([[float(v) for v in row] for row in rows[1:]])
    return {name: values[:, c] for c, name in enumerate(rows[0])}


def _robot_file(folder: Path, architecture: str) -> Path:
    path = folder / f"{architecture}.toml"
    path.write_text(f'architecture = "{architecture}"\n', encoding="utf-8")
    return path


def test_forward_hold_writes_the_columns_of_simulate_and_stays_at_home(capsys, tmp_path):
    robot_file = _robot_file(tmp_path, "6-UPS")
    status, out, err = cli(capsys, "forward", "--robot", robot_file, "--efforts", "hold",
                           "--duration", "0.2", "--samples", "5", "--plots",
                           "--output", tmp_path / "still")  # fmt: skip
    assert status == 0, err
    assert "gives back the efforts to" in out
    names = sorted(p.name for p in (tmp_path / "still").iterdir() if not p.name.startswith("."))
    assert names == [
        "efforts.png", "joint_reactions.png", "platform.png", "pose.png", "results.csv", "trajectory.csv",
    ]  # fmt: skip
    results = _read_csv(tmp_path / "still" / "results.csv")
    status, _, err = cli(capsys, "simulate", "--robot", robot_file, "--motion", "heave",
                         "--samples", "3", "--output", tmp_path / "sim")  # fmt: skip
    assert status == 0, err
    with (tmp_path / "sim" / "results.csv").open() as stream:
        assert list(results) == stream.readline().strip().split(",")
    robot = hexapod()
    home = spatial_kinematics(robot, PlatformMotion.at_rest(robot.home_position))
    for i in range(6):
        assert np.abs(results[f"q_{i + 1}_P2"] - home.q[0, i, 2]).max() < 1e-12
        assert np.abs(results[f"tau_{i + 1}"] - hold_efforts(robot)[i]).max() < 1e-12


def test_forward_of_a_results_file_gives_its_motion_back(capsys, tmp_path):
    robot_file = _robot_file(tmp_path, "3-RUU")
    status, _, err = cli(capsys, "simulate", "--robot", robot_file, "--motion", "circle",
                         "--samples", "301", "--output", tmp_path / "inv")  # fmt: skip
    assert status == 0, err
    lines = (tmp_path / "inv" / "results.csv").read_text().splitlines()
    efforts = tmp_path / "efforts.csv"
    efforts.write_text("\n".join(lines[:32]) + "\n")  # t = 0 .. 0.3 s
    status, out, err = cli(capsys, "forward", "--robot", robot_file, "--efforts", efforts,
                           "--output", tmp_path / "fwd")  # fmt: skip
    assert status == 0, err
    assert "drift from the planned motion" in out
    planned, back = _read_csv(efforts), _read_csv(tmp_path / "fwd" / "results.csv")
    assert np.array_equal(planned["t"], back["t"])
    for name in planned:
        if name.startswith("q_"):
            assert np.abs(back[name] - planned[name]).max() < 1e-7, name
    # trajectory.csv reads back in prp3 simulate and gives the efforts again
    status, _, err = cli(capsys, "simulate", "--robot", robot_file, "--trajectory",
                         tmp_path / "fwd" / "trajectory.csv", "--output", tmp_path / "again")  # fmt: skip
    assert status == 0, err
    again = _read_csv(tmp_path / "again" / "results.csv")
    for i in range(3):
        assert np.abs(again[f"tau_{i + 1}"] - planned[f"tau_{i + 1}"]).max() < 1e-6


@pytest.mark.parametrize(
    ("options", "words"),
    [
        (["--efforts", "hold", "--initial-pose", "0", "0", "0"], "--initial-pose applies to"),
        ([], "--efforts is required"),
        (["--efforts", "missing.csv"], "missing.csv"),
        (["--efforts", "{bad}"], "missing column(s) tau_3"),
        (["--efforts", "{table}", "--duration", "5"], "--duration 5.0: the motion's times"),
        (["--efforts", "hold", "--rtol", "1e-20"], "expected a number >="),
    ],
)
def test_forward_refuses_bad_input_in_one_line(capsys, tmp_path, options, words):
    (tmp_path / "bad.csv").write_text("t,tau_1,tau_2\n0,1,1\n1,1,1\n")
    (tmp_path / "table.csv").write_text("t,tau_1,tau_2,tau_3\n0,1,1,1\n1,1,1,1\n")
    options = [
        o.format(bad=tmp_path / "bad.csv", table=tmp_path / "table.csv") if "{" in o else o
        for o in options
    ]
    out = tmp_path / "out"
    status, _, err = cli(capsys, "forward", "--robot", _robot_file(tmp_path, "3-RUU"), *options,
                         "--output", out)  # fmt: skip
    assert status == 2
    assert words in one_line(err)
    assert not out.exists()


def test_a_refused_run_keeps_the_earlier_results(capsys, tmp_path):
    robot_file = _robot_file(tmp_path, "6-UPS")
    out = tmp_path / "out"
    status, _, err = cli(capsys, "forward", "--robot", robot_file, "--efforts", "hold",
                         "--duration", "0.1", "--samples", "3", "--output", out)  # fmt: skip
    assert status == 0, err
    before = (out / "results.csv").read_bytes()
    table = tmp_path / "push.csv"
    push = 1.5 * hold_efforts(hexapod())
    rows = [",".join(["t"] + [f"tau_{i + 1}" for i in range(6)])]
    rows += [",".join([str(t)] + [repr(float(v)) for v in push]) for t in (0.0, 0.4)]
    table.write_text("\n".join(rows) + "\n")
    status, _, err = cli(capsys, "forward", "--robot", robot_file, "--efforts", table,
                         "--output", out)  # fmt: skip
    assert status == 2
    assert "reaches a joint limit" in one_line(err) and "P2 of leg " in one_line(err)
    assert (out / "results.csv").read_bytes() == before


def test_the_planar_forward_refuses_the_spatial_options(capsys, tmp_path):
    status, _, err = cli(capsys, "forward", "--forces", "hold", "--output", tmp_path / "o")
    assert status == 2 and "applies to a spatial robot file" in one_line(err)
    status, _, err = cli(capsys, "forward", "--output", tmp_path / "o")
    assert status == 2 and "--forces FORCES.csv is required" in one_line(err)


def test_a_joint_limit_stops_the_motion_at_its_crossing():
    # The Delta falls with its motors idle until a forearm's U reaches its limit: the
    # terminal event of the limit margin finds the crossing in a few hundred evaluations
    # (it was an integrator shrinking its step onto the limit, tens of thousands); the
    # motion integrated to just before the reported time ends at the limit, and stays
    # within every limit on the way (checked by the inverse geometry of the reported
    # poses, independently of the event).
    robot = delta()
    with pytest.raises(UnreachablePoseError) as caught:
        spatial_forward_dynamics(robot, np.zeros(3), duration=1.0, max_evaluations=1500)
    message = str(caught.value)
    assert "reaches a joint limit" in message and "U2_a of leg 1" in message
    t_stop = caught.value.time
    assert t_stop is not None and 0.0 < t_stop < 1.0
    before = spatial_forward_dynamics(robot, np.zeros(3), duration=t_stop * (1 - 1e-6))
    motion = before.motion
    q = leg_coordinates(robot, motion.position, motion.rotation).q
    low, high = robot.legs[0].joints[1].limits[0]
    u2a = q[:, :, 1]  # the U2's first angle (after R1)
    assert ((u2a >= low) & (u2a <= high)).all()
    assert abs(float(np.abs(u2a[-1]).max()) - high) < 1e-4
