"""The family's mechanics against independent computations (docs/family.md §5–§10).

The reference below is written from docs/family.md alone, in another
formulation than any route of ``prp3.family``: each leg is a product of 3×3
homogeneous matrices ``T = S·P₁M₁(q₁)·P₂M₂(q₂)·P₃M₃(q₃)`` (placements ``P_k``,
joint motions ``M_k = exp(q_k ξ_k)``), whose first and second time derivatives
follow from ``dM/dq = M·ξ`` and the product rule.  From the reported columns
(q, dq, ddq and the joint forces) it rebuilds: the closure and its first two
derivatives (the pose, velocity and acceleration of the platform), the
Newton–Euler balance of all 7 bodies, the joint semantics, and the energy
balance.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st
from numpy.typing import NDArray

from prp3 import Motion, Robot, inverse_dynamics, paper_motion
from prp3.errors import ParameterError, Prp3Error, SingularPoseError, UnreachablePoseError
from prp3.family import (
    ARCHITECTURES,
    FAMILY_COLUMNS,
    Body,
    FamilyRobot,
    PlatformBody,
    family_inverse_dynamics,
    family_results_table,
)
from prp3.io.results import results_table
from prp3.model.parameters import Load, Payload
from strategies import FAMILY_ALLOWED
from strategies import family_designs as designs
from strategies import family_motions as motions

FloatArray = NDArray[np.float64]
LEGS = "ABC"
XI_R = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
XI_P = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]])

ALLOWED = FAMILY_ALLOWED


# ---------------------------------------------------------------- the reference
def homogeneous(a: float, b: float, gamma: float) -> FloatArray:
    c, s = math.cos(gamma), math.sin(gamma)
    return np.array([[c, -s, a], [s, c, b], [0.0, 0.0, 1.0]])


def motion_matrix(kind: str, q: float) -> FloatArray:
    if kind == "R":
        return homogeneous(0.0, 0.0, q)
    return homogeneous(q, 0.0, 0.0)


def leg_frames(
    robot: FamilyRobot, leg: int, q: FloatArray, dq: FloatArray, ddq: FloatArray
) -> dict[str, list[FloatArray]]:
    """``T, Ṫ, T̈`` of F_1, F_2, F_3, E and the joint frames J_1..J_3 of one sample."""
    types = robot.types
    place = [homogeneous(*p) for p in (robot.leg.joint1, robot.leg.joint2, robot.leg.joint3)]
    start = homogeneous(0.0, 0.0, 2.0 * math.pi * leg / 3.0)
    xi = [XI_R if t == "R" else XI_P for t in types]
    m = [motion_matrix(types[k], q[k]) for k in range(3)]
    a = [place[k] @ m[k] for k in range(3)]
    da = [place[k] @ m[k] @ xi[k] * dq[k] for k in range(3)]
    dda = [place[k] @ m[k] @ (xi[k] @ xi[k] * dq[k] ** 2 + xi[k] * ddq[k]) for k in range(3)]
    out: dict[str, list[FloatArray]] = {"T": [], "dT": [], "ddT": [], "J": []}
    for upto in range(1, 4):
        t = start.copy()
        for k in range(upto):
            t = t @ a[k]
        d1 = np.zeros((3, 3))
        d2 = np.zeros((3, 3))
        for i in range(upto):
            term1 = start.copy()
            term2 = start.copy()
            for k in range(upto):
                term1 = term1 @ (da[k] if k == i else a[k])
                term2 = term2 @ (dda[k] if k == i else a[k])
            d1 += term1
            d2 += term2
            for j in range(i + 1, upto):
                term = start.copy()
                for k in range(upto):
                    term = term @ (da[k] if k in (i, j) else a[k])
                d2 += 2.0 * term
        out["T"].append(t)
        out["dT"].append(d1)
        out["ddT"].append(d2)
        before = start.copy()
        for k in range(upto - 1):
            before = before @ a[k]
        out["J"].append(before @ place[upto - 1])
    end = homogeneous(*robot.leg.attachment)
    out["T"].append(out["T"][2] @ end)
    out["dT"].append(out["dT"][2] @ end)
    out["ddT"].append(out["ddT"][2] @ end)
    return out


def cross2(a: FloatArray, b: FloatArray) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


def perp2(v: FloatArray) -> FloatArray:
    return np.array([-v[1], v[0]])


def check_sample(robot: FamilyRobot, row: dict[str, float], motion: Motion, k: int) -> float:
    """Rebuild every check of docs/family.md §10 at sample ``k``; return the energy rate residual."""
    pose, vel, acc = motion.pose[k], motion.velocity[k], motion.acceleration[k]
    g = np.array(robot.gravity)
    scale = 1.0 + max(
        abs(row[f"{n}{j}_{leg}"]) for n in ("fx", "fy", "m") for j in (1, 2, 3) for leg in LEGS
    )
    act = robot.actuated - 1
    energy_rate = 0.0
    platform_force = np.zeros(2)
    platform_moment = 0.0
    centre = pose[:2]
    for leg_index, leg in enumerate(LEGS):
        q = np.array([row[f"q{j}_{leg}"] for j in (1, 2, 3)])
        dq = np.array([row[f"dq{j}_{leg}"] for j in (1, 2, 3)])
        ddq = np.array([row[f"ddq{j}_{leg}"] for j in (1, 2, 3)])
        frames = leg_frames(robot, leg_index, q, dq, ddq)
        t_e, dt_e, ddt_e = frames["T"][3], frames["dT"][3], frames["ddT"][3]
        # closure and its derivatives: E is the platform frame turned by σ_j
        np.testing.assert_allclose(t_e[:2, 2], centre, atol=1e-12)
        turned = math.atan2(t_e[1, 0], t_e[0, 0]) - pose[2] - 2 * math.pi * leg_index / 3
        assert abs(math.remainder(turned, 2 * math.pi)) < 1e-12
        np.testing.assert_allclose(dt_e[:2, 2], vel[:2], atol=1e-11 * (1 + np.abs(vel).max()))
        np.testing.assert_allclose(ddt_e[:2, 2], acc[:2], atol=1e-10 * (1 + np.abs(acc).max()))
        omega = dt_e[1, 0] * t_e[0, 0] - dt_e[0, 0] * t_e[1, 0]
        assert omega == pytest.approx(vel[2], abs=1e-11 * (1 + abs(vel[2])))
        forces = [np.array([row[f"fx{j}_{leg}"], row[f"fy{j}_{leg}"]]) for j in (1, 2, 3)]
        moments = [row[f"m{j}_{leg}"] for j in (1, 2, 3)]
        origins = [frames["T"][j][:2, 2] for j in range(3)]
        tau = row[f"tau_{leg}"]
        # joint semantics
        for j in range(3):
            u = frames["J"][j][:2, 0]
            want = tau if j == act else 0.0
            if robot.types[j] == "R":
                assert moments[j] == pytest.approx(want, abs=1e-11 * scale)
            else:
                assert float(forces[j] @ u) == pytest.approx(want, abs=1e-11 * scale)
        assert row[f"p_{leg}"] == pytest.approx(
            tau * dq[act], abs=1e-12 * scale * (1 + abs(dq[act]))
        )
        # the balance of link 1 and link 2 (moments about the mass centre)
        rate = 0.0
        for body_index, body in enumerate((robot.link1, robot.link2)):
            t, dt, ddt = (frames[n][body_index] for n in ("T", "dT", "ddT"))
            com = np.array([*body.com, 1.0])
            c, v, a = (t @ com)[:2], (dt @ com)[:2], (ddt @ com)[:2]
            w = float(sum(dq[i] for i in range(body_index + 1) if robot.types[i] == "R"))
            alpha = float(sum(ddq[i] for i in range(body_index + 1) if robot.types[i] == "R"))
            f_in, f_out = forces[body_index], forces[body_index + 1]
            m_in = moments[body_index] + cross2(origins[body_index] - c, f_in)
            m_out = moments[body_index + 1] + cross2(origins[body_index + 1] - c, f_out)
            np.testing.assert_allclose(f_in - f_out, body.mass * (a - g), atol=1e-10 * scale)
            assert m_in - m_out == pytest.approx(body.inertia * alpha, abs=1e-10 * scale)
            rate += body.mass * float(v @ (a - g)) + body.inertia * w * alpha
        energy_rate += rate
        platform_force += forces[2]
        platform_moment += moments[2] + cross2(origins[2] - centre, forces[2])
    # the platform with its payload, plus the load
    phi, w, alpha = pose[2], vel[2], acc[2]
    r = np.array([[math.cos(phi), -math.sin(phi)], [math.sin(phi), math.cos(phi)]]) @ np.array(
        robot.payload.com
    )
    v_pl = vel[:2] + w * perp2(r)
    a_pl = acc[:2] + alpha * perp2(r) - w * w * r
    mp, ip, mpl, ipl = (
        robot.platform.mass,
        robot.platform.inertia,
        robot.payload.mass,
        robot.payload.inertia,
    )
    need_f = mp * (acc[:2] - g) + mpl * (a_pl - g)
    need_m = (ip + ipl) * alpha + mpl * cross2(r, a_pl - g)
    load_f, load_m = np.array(robot.load.force), robot.load.moment
    np.testing.assert_allclose(platform_force + load_f, need_f, atol=1e-10 * scale)
    assert platform_moment + load_m == pytest.approx(need_m, abs=1e-10 * scale)
    energy_rate += mp * float(vel[:2] @ (acc[:2] - g)) + (ip + ipl) * w * alpha
    energy_rate += mpl * float(v_pl @ (a_pl - g))
    power = sum(row[f"p_{leg}"] for leg in LEGS) + float(load_f @ vel[:2]) + load_m * w
    return (power - energy_rate) / scale


# ---------------------------------------------------------------- strategies
def _f(low: float, high: float) -> st.SearchStrategy[float]:
    return st.floats(low, high, allow_nan=False, allow_infinity=False)


def solve_all(robot: FamilyRobot, motion: Motion) -> dict[str, dict[str, FloatArray]]:
    try:
        return {
            m: family_results_table(family_inverse_dynamics(robot, motion, m))  # type: ignore[arg-type]
            for m in ("fast", "paper", "newton-euler")
        }
    except (SingularPoseError, UnreachablePoseError):
        assume(False)
        raise


# ---------------------------------------------------------------- the properties
@given(data=st.data())
def test_routes_agree_and_balances_hold(data: st.DataObject) -> None:
    """The three routes agree to 1e-10; every balance rebuilt from the columns holds."""
    robot = data.draw(designs())
    centre = robot.home_poses.mean(axis=0)
    motion = data.draw(motions(centre))
    tables = solve_all(robot, motion)
    fast = tables["fast"]
    scale = 1.0 + max(float(np.abs(v).max()) for v in fast.values())
    for method in ("paper", "newton-euler"):
        for name in FAMILY_COLUMNS:
            np.testing.assert_allclose(
                tables[method][name],
                fast[name],
                rtol=0,
                atol=1e-10 * scale,
                err_msg=f"{method} {name}",
            )
    residuals = []
    for k in range(motion.samples):
        row = {name: float(fast[name][k]) for name in FAMILY_COLUMNS}
        residuals.append(check_sample(robot, row, motion, k))
    assert max(abs(r) for r in residuals) < 1e-10


@st.composite
def unusual_designs(draw: st.DrawFn) -> FamilyRobot:
    """Valid designs away from the defaults (docs/family.md §2, §5): every architecture and
    allowed actuation, other ``home`` joint values (the legs' home poses off the origin and
    apart), placements moved and turned, a scale from 0.05 to 2, massless bodies, gravity
    in the plane along ``−y`` or ``+x``, oblique, or none (the plane horizontal)."""
    arch, act = draw(st.sampled_from(ALLOWED))
    base = FamilyRobot.default(arch, act)
    step = [0.25 if kind == "R" else 0.04 for kind in base.types]
    h0, h1, h2 = (h + draw(_f(-d, d)) for h, d in zip(base.leg.home, step, strict=True))

    def moved(p: tuple[float, float, float]) -> tuple[float, float, float]:
        return (p[0] + draw(_f(-0.05, 0.05)), p[1] + draw(_f(-0.05, 0.05)),
                p[2] + draw(_f(-0.3, 0.3)))  # fmt: skip

    leg = replace(
        base.leg,
        joint1=moved(base.leg.joint1),
        joint2=moved(base.leg.joint2),
        joint3=moved(base.leg.joint3),
        attachment=moved(base.leg.attachment),
        home=(h0, h1, h2),
        scale=draw(_f(0.05, 2.0)),
    )

    def mass(high: float) -> float:
        return draw(st.sampled_from([0.0, draw(_f(0.01, high))]))

    def body(name: str) -> Body:
        com = (draw(_f(-0.3, 0.3)), draw(_f(-0.3, 0.3)))
        return Body(mass(3.0), com, mass(0.02), name=name)

    gravity = draw(st.sampled_from([(0.0, 0.0), (0.0, -9.81), (9.81, 0.0), (-6.9367, -6.9367)]))
    try:
        return FamilyRobot(
            architecture=arch,
            actuated=act,
            leg=leg,
            link1=body("link1"),
            link2=body("link2"),
            platform=PlatformBody(mass(5.0), mass(0.1)),
            payload=Payload(mass(2.0), (draw(_f(-0.2, 0.2)), draw(_f(-0.2, 0.2))), mass(0.01)),
            load=Load((draw(_f(-20, 20)), draw(_f(-20, 20))), draw(_f(-2, 2))),
            gravity=gravity,
        )
    except ParameterError:
        assume(False)
        raise


@given(data=st.data())
def test_routes_agree_at_unusual_designs(data: st.DataObject) -> None:
    """Away from the defaults the three routes and both engines of the fast route agree to
    1e-10, and every balance rebuilt from the columns (independent of the routes) holds."""
    robot = data.draw(unusual_designs())
    motion = data.draw(motions(robot.home_poses.mean(axis=0)))
    tables = solve_all(robot, motion)
    tables["numpy"] = family_results_table(family_inverse_dynamics(robot, motion, engine="numpy"))
    fast = tables["fast"]
    scale = 1.0 + max(float(np.abs(v).max()) for v in fast.values())
    for method in ("paper", "newton-euler", "numpy"):
        for name in FAMILY_COLUMNS:
            np.testing.assert_allclose(
                tables[method][name], fast[name], rtol=0, atol=1e-10 * scale,
                err_msg=f"{method} {name}",
            )  # fmt: skip
    for k in range(motion.samples):
        row = {name: float(fast[name][k]) for name in FAMILY_COLUMNS}
        assert abs(check_sample(robot, row, motion, k)) < 1e-10


@pytest.mark.parametrize(("arch", "act"), ALLOWED)
def test_every_actuation_balances(arch: str, act: int) -> None:
    """Each allowed actuation of each default design, a loaded, moving platform."""
    robot = replace(
        FamilyRobot.default(arch, act),
        payload=Payload(0.5, (0.02, -0.01), 1e-3),
        load=Load((3.0, -2.0), 0.4),
    )
    t = np.linspace(0.0, 1.0, 5)[:, None]
    amp, w = np.array([0.01, 0.015, 0.05]), np.array([2.0, 3.0, 1.5])
    motion = Motion(
        t=t[:, 0],
        pose=amp * np.sin(w * t),
        velocity=amp * w * np.cos(w * t),
        acceleration=-amp * w * w * np.sin(w * t),
    )
    tables = solve_all(robot, motion)
    for name in FAMILY_COLUMNS:
        np.testing.assert_allclose(tables["paper"][name], tables["fast"][name], atol=1e-10)
        np.testing.assert_allclose(tables["newton-euler"][name], tables["fast"][name], atol=1e-10)
    for k in range(motion.samples):
        row = {name: float(tables["fast"][name][k]) for name in FAMILY_COLUMNS}
        assert abs(check_sample(robot, row, motion, k)) < 1e-11


def test_branch_is_continuous_from_home() -> None:
    """Joint values start at home, vary continuously, and their rates match finite differences."""
    for arch in ARCHITECTURES:
        robot = FamilyRobot.default(arch)
        motion = paper_motion("rotation", 601)
        table = family_results_table(family_inverse_dynamics(robot, motion))
        h = float(motion.t[1] - motion.t[0])
        for leg in LEGS:
            for j in (1, 2, 3):
                q = table[f"q{j}_{leg}"]
                assert q[0] == pytest.approx(robot.leg.home[j - 1], abs=1e-12)
                np.testing.assert_allclose(
                    np.gradient(q, h)[1:-1], table[f"dq{j}_{leg}"][1:-1], atol=2e-4
                )
                dq = table[f"dq{j}_{leg}"]
                np.testing.assert_allclose(
                    np.gradient(dq, h)[1:-1], table[f"ddq{j}_{leg}"][1:-1], atol=2e-3
                )


def test_r_angles_are_not_wrapped() -> None:
    """A 3-RRR turning its platform by more than π/2 keeps q continuous (no 2π jumps)."""
    robot = FamilyRobot.default("3-RRR")
    t = np.linspace(0.0, 1.0, 201)
    phi = 0.4 * t
    pose = np.stack([np.zeros_like(t), np.zeros_like(t), phi], -1)
    motion = Motion(
        t=t, pose=pose, velocity=np.gradient(pose, t, axis=0), acceleration=np.zeros_like(pose)
    )
    table = family_results_table(family_inverse_dynamics(robot, motion))
    for leg in LEGS:
        total = table[f"q1_{leg}"] + table[f"q2_{leg}"] + table[f"q3_{leg}"]
        np.testing.assert_allclose(total, phi, atol=1e-12)  # Γ = 0 for the default 3-RRR
        for j in (1, 2, 3):
            assert np.abs(np.diff(table[f"q{j}_{leg}"])).max() < 0.05


# ---------------------------------------------------------------- the margins of §3
#: docs/family.md §3: min μ_leg / min μ_par along the paper's motions (301 samples), signs from home.
MARGINS = {
    ("3-PRP", 1): ((0.866, 0.650), (0.500, 0.339)),
    ("3-PRP", 3): ((0.866, 0.662), (0.500, 0.339)),
    ("3-RPR", 2): ((0.783, 0.978), (0.943, 0.975)),
    ("3-RRR", 1): ((0.423, 0.947), (0.234, 0.998)),
    ("3-PRR", 1): ((0.651, 0.948), (0.662, 0.998)),
    ("3-PPR", 1): ((1.000, 0.998), (1.000, 0.845)),
    ("3-RPP", 2): ((1.000, 0.995), (1.000, 0.934)),
    ("3-RRP", 1): ((0.441, 0.980), (0.667, 0.646)),
}
#: The "other actuations" column: the smallest of both measures over both motions.
LOWER = {
    ("3-RPR", 1): 0.546,
    ("3-RPR", 3): 0.783,
    ("3-RRR", 2): 0.234,
    ("3-RRR", 3): 0.234,
    ("3-PRR", 3): 0.651,
    ("3-PPR", 2): 0.739,
    ("3-RPP", 3): 0.610,
    ("3-RRP", 3): 0.441,
}


def _margins(arch: str, act: int, motion: str) -> tuple[float, float]:
    from prp3.family import family_kinematics

    robot = FamilyRobot.default(arch, act)
    kin = family_kinematics(robot, paper_motion(motion, 301))
    leg0, par0 = robot.home_measures
    return float((np.sign(leg0) * kin.mu_leg).min()), float((np.sign(par0) * kin.mu_par).min())


@pytest.mark.parametrize(("arch", "act"), sorted(MARGINS))
def test_singularity_margins_of_the_table(arch: str, act: int) -> None:
    for motion, expected in zip(("vertical", "rotation"), MARGINS[arch, act], strict=True):
        got = _margins(arch, act, motion)
        assert got == pytest.approx(expected, abs=5e-4), (motion, got)


@pytest.mark.parametrize(("arch", "act"), sorted(LOWER))
def test_other_actuations_margins(arch: str, act: int) -> None:
    smallest = min(min(_margins(arch, act, m)) for m in ("vertical", "rotation"))
    assert smallest == pytest.approx(LOWER[arch, act], abs=5e-4)


# ---------------------------------------------------------------- refusals
def test_prr_actuated_2_rotation_crosses_a_parallel_singularity() -> None:
    motion = paper_motion("rotation", 301)
    with pytest.raises(SingularPoseError) as info:
        family_inverse_dynamics(FamilyRobot.default("3-PRR", 2), motion)
    error = info.value
    assert error.sample is not None and error.pose is not None and "mu_par" in str(error)
    crossing = math.atan(0.5)
    assert motion.pose[error.sample - 1, 2] < crossing < motion.pose[error.sample, 2] + 1e-3
    assert error.time == pytest.approx(float(motion.t[error.sample]))


def test_prp_refuses_the_far_side_of_phi_pi_3() -> None:
    """docs/family.md §8: the family takes only the home side of φ = π/3 (docs/model.md takes both)."""
    t = np.linspace(0.0, 1.0, 11)
    pose = np.stack([0 * t, 0 * t, 1.2 + 0.1 * t], -1)  # wholly beyond φ = π/3
    motion = Motion(t=t, pose=pose, velocity=np.gradient(pose, t, axis=0), acceleration=0 * pose)
    with pytest.raises(SingularPoseError, match="mu_leg of leg A"):
        family_inverse_dynamics(FamilyRobot.default("3-PRP"), motion)  # crossed since home
    # docs/model.md accepts it: |sin(φ − π/3)| >= 1e-4 at every sample and no crossing
    # between two samples (a motion that crosses is refused in model form too)
    inverse_dynamics(Robot(), motion)
    crossing = Motion(t=t, pose=np.stack([0 * t, 0 * t, 1.3 * t], -1),
                      velocity=np.stack([0 * t, 0 * t, 1.3 + 0 * t], -1), acceleration=0 * pose)  # fmt: skip
    with pytest.raises(SingularPoseError, match="crosses the singular orientation"):
        inverse_dynamics(Robot(), crossing)


def test_unreachable_pose_is_named() -> None:
    motion = Motion.at_rest([[0.0, 0.0, 0.0], [0.6, 0.0, 0.0]], t=[0.0, 1.0])
    with pytest.raises(UnreachablePoseError, match="cannot reach") as info:
        family_inverse_dynamics(FamilyRobot.default("3-RRR"), motion)
    error = info.value
    assert error.sample == 1 and error.leg in tuple(LEGS) and error.time == 1.0
    assert "on the way from sample 0 (t = 0 s) to sample 1 (t = 1 s)" in str(error)
    assert error.pose is not None
    assert 0.0 < error.pose[0] < 0.6  # the straight path leaves the workspace before the sample
    single = Motion.at_rest([0.6, 0.0, 0.0])
    with pytest.raises(UnreachablePoseError, match="cannot reach"):
        family_inverse_dynamics(FamilyRobot.default("3-RRR"), single)


def test_a_crossing_between_samples_is_refused() -> None:
    """Two samples on either side of the 3-PRR's parallel singularity at φ = atan(1/2)."""
    motion = Motion.at_rest([[0.0, 0.0, 0.0], [0.0, 0.0, 0.3], [0.0, 0.0, 0.7]], t=[0.0, 1.0, 2.0])
    between = r"on the way from sample 1 \(t = 1 s\) to sample 2 \(t = 2 s\)"  # both named
    with pytest.raises(SingularPoseError, match=between) as info:
        family_inverse_dynamics(FamilyRobot.default("3-PRR", 2), motion)
    assert info.value.sample == 2 and "mu_par" in str(info.value)
    assert info.value.pose is not None and 0.3 < info.value.pose[2] < 0.7


def test_a_coarse_rotation_keeps_the_branch() -> None:
    """One sample far from home: the path is followed in sub-steps, R angles stay continuous."""
    robot = FamilyRobot.default("3-RPR")
    coarse = family_inverse_dynamics(robot, Motion.at_rest([0.0, 0.0, 0.25]))
    t = np.linspace(0.0, 1.0, 101)
    pose = np.stack([0 * t, 0 * t, 0.25 * t], -1)
    fine = family_inverse_dynamics(robot, Motion.at_rest(pose, t=t))
    np.testing.assert_allclose(coarse.q, fine.q[-1], atol=1e-12)


def test_poses_out_of_range_are_refused() -> None:
    for pose in ([1e300, 0.0, 0.0], [0.0, 0.0, 1e10]):
        with pytest.raises(Prp3Error, match="robot lengths") as info:
            family_inverse_dynamics(
                FamilyRobot.default("3-RRR"), Motion.at_rest([[0, 0, 0], pose], t=[0, 1])
            )
        assert info.value.sample == 1


@pytest.mark.parametrize(("arch", "act"), [("3-PRP", 2), ("3-PPR", 3), ("3-RPP", 1), ("3-RRP", 2)])
def test_refused_actuations(arch: str, act: int) -> None:
    with pytest.raises(ParameterError) as info:
        FamilyRobot.default(arch, act)
    assert info.value.key in ("actuated", "leg.home")


def test_time_varying_load_refused() -> None:
    motion = Motion(
        t=[0.0, 1.0],
        pose=np.zeros((2, 3)),
        velocity=np.zeros((2, 3)),
        acceleration=np.zeros((2, 3)),
        load=np.zeros((2, 3)),
    )
    with pytest.raises(Prp3Error, match="model-form robot files"):
        family_inverse_dynamics(FamilyRobot.default("3-RRR"), motion)


def test_single_sample_rank() -> None:
    solution = family_inverse_dynamics(
        FamilyRobot.default("3-RPR"), Motion.at_rest([0.01, 0.0, 0.02])
    )
    assert (
        solution.tau.shape == (3,)
        and solution.force.shape == (3, 3, 2)
        and solution.q.shape == (3, 3)
    )


# ---------------------------------------------------------------- §8: the 3-PRP equals docs/model.md
ALPHA = np.array([math.pi / 3, math.pi, -math.pi / 3])


@given(data=st.data())
def test_prp_family_form_equals_model(data: st.DataObject) -> None:
    draw = data.draw
    piston = (draw(_f(0.1, 3.0)), (draw(_f(-0.1, 0.1)), draw(_f(-0.1, 0.1))), draw(_f(0, 0.01)))
    link = (draw(_f(0.1, 3.0)), (draw(_f(-0.1, 0.1)), draw(_f(-0.1, 0.1))), draw(_f(0, 0.01)))
    platform = (draw(_f(0.1, 5.0)), draw(_f(0.0, 0.1)))
    payload = Payload(
        draw(_f(0.0, 2.0)), (draw(_f(-0.1, 0.1)), draw(_f(-0.1, 0.1))), draw(_f(0, 0.01))
    )
    load = Load((draw(_f(-20, 20)), draw(_f(-20, 20))), draw(_f(-2, 2)))
    gravity = (draw(_f(-10, 10)), draw(_f(-10, 10)))
    model = Robot.from_mapping(
        {
            "piston": {"mass": piston[0], "com": list(piston[1]), "inertia": piston[2]},
            "link": {"mass": link[0], "com": list(link[1]), "inertia": link[2]},
            "platform": {"mass": platform[0], "inertia": platform[1]},
            "gravity": list(gravity),
        }
    )
    model = replace(model, payload=payload, load=load)
    family = FamilyRobot.from_mapping(
        {
            "architecture": "3-PRP",
            "actuated": 1,
            "link1": {"mass": piston[0], "com": list(piston[1]), "inertia": piston[2]},
            "link2": {"mass": link[0], "com": list(link[1]), "inertia": link[2]},
            "platform": {"mass": platform[0], "inertia": platform[1]},
            "payload": {"mass": payload.mass, "com": list(payload.com), "inertia": payload.inertia},
            "load": {"force": list(load.force), "moment": load.moment},
            "gravity": list(gravity),
        }
    )
    motion = draw(motions(np.zeros(3), samples=5))
    ours = family_results_table(family_inverse_dynamics(family, motion))
    theirs = results_table(*inverse_dynamics(model, motion))
    phi = motion.pose[:, 2]
    scale = 1.0 + max(float(np.abs(v).max()) for v in theirs.values())

    def col(leg: str, name: str) -> FloatArray:
        return theirs[f"{name}_{leg}"][:, None]

    def close(a: FloatArray, b: FloatArray, what: str) -> None:
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-10 * scale, err_msg=what)

    for i, leg in enumerate(LEGS):
        e = np.stack([np.cos(ALPHA[i]) + 0 * phi, np.sin(ALPHA[i]) + 0 * phi], -1)
        n = np.stack([-e[:, 1], e[:, 0]], -1)
        d = np.stack(
            [np.cos(ALPHA[i] + phi - math.pi / 3), np.sin(ALPHA[i] + phi - math.pi / 3)], -1
        )
        dp = np.stack([-d[:, 1], d[:, 0]], -1)
        close(ours[f"q1_{leg}"], theirs[f"lambda10_{leg}"], "q1")
        close(ours[f"q2_{leg}"], phi, "q2")
        close(ours[f"q3_{leg}"], theirs[f"lambda32_{leg}"], "q3")
        close(ours[f"dq1_{leg}"], theirs[f"dlambda10_{leg}"], "dq1")
        close(ours[f"ddq3_{leg}"], theirs[f"ddlambda32_{leg}"], "ddq3")
        close(ours[f"tau_{leg}"], theirs[f"f10_{leg}"], "tau")
        close(ours[f"p_{leg}"], theirs[f"p10_{leg}"], "p")
        f1 = col(leg, "f10") * e + col(leg, "n10") * n
        close(np.stack([ours[f"fx1_{leg}"], ours[f"fy1_{leg}"]], -1), f1, "f1")
        close(ours[f"m1_{leg}"], theirs[f"m10_{leg}"], "m1")
        f2 = col(leg, "f21y") * n + col(leg, "f21z") * e
        close(np.stack([ours[f"fx2_{leg}"], ours[f"fy2_{leg}"]], -1), f2, "f2")
        close(ours[f"m2_{leg}"], 0 * phi, "m2")
        close(np.stack([ours[f"fx3_{leg}"], ours[f"fy3_{leg}"]], -1), col(leg, "n32") * dp, "f3")
        close(
            ours[f"m3_{leg}"],
            theirs[f"m32_{leg}"] - theirs[f"lambda32_{leg}"] * theirs[f"n32_{leg}"],
            "m3",
        )
