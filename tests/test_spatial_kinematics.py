"""The spatial model's geometry and kinematics (docs/spatial.md §2–§6), on the 6-UPS hexapod.

References are independent of the code under test: scipy's rotations, the
hexapod's closed-form leg (``c_U + q_P·u = p + R·c_A``) and parallel Jacobian
``(r_i × u_i, u_i)``, and five-point finite differences of the inverse geometry.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from prp3.errors import ParameterError, SingularPoseError, TrajectoryError, UnreachablePoseError
from prp3.spatial import geometry, kinematics
from prp3.spatial.geometry import inverse_geometry
from prp3.spatial.kinematics import spatial_kinematics
from prp3.spatial.model import Joint, hexapod
from prp3.spatial.motion import PlatformMotion, quaternion_motion, rpy_motion, rpy_rates
from prp3.spatial.rotations import (
    exp_rotation,
    log_rotation,
    matrix_quaternion,
    matrix_rpy,
    quaternion_matrix,
    rpy_matrix,
)
from spatial_strategies import (
    angular_velocity,
    derivative,
    hexapod_parallel_jacobian,
    hexapods,
    waves,
)

H = 1e-4
STEPS = np.array([-2.0, -1.0, 0.0, 1.0, 2.0]) * H


def _rz(a: np.ndarray) -> np.ndarray:
    return Rotation.from_euler("z", np.asarray(a)[..., None]).as_matrix()


def _ry(b: np.ndarray) -> np.ndarray:
    return Rotation.from_euler("y", np.asarray(b)[..., None]).as_matrix()


# ---------------------------------------------------------------- rotations


@given(st.lists(st.floats(-3.0, 3.0), min_size=3, max_size=3))
def test_rotations_agree_with_scipy(angles: list[float]) -> None:
    rpy = np.array(angles) * np.array([1.0, 0.5, 1.0])
    expected = Rotation.from_euler("xyz", rpy)  # extrinsic x, y, z: Rz·Ry·Rx
    matrix = expected.as_matrix()
    assert np.allclose(rpy_matrix(rpy), matrix, atol=1e-14)
    assert np.allclose(rpy_matrix(matrix_rpy(matrix)), matrix, atol=1e-12)
    x, y, z, w = expected.as_quat()
    quaternion = np.array([w, x, y, z]) * (1.0 if w >= 0 else -1.0)
    assert np.allclose(matrix_quaternion(matrix), quaternion, atol=1e-12)
    assert np.allclose(quaternion_matrix(quaternion), matrix, atol=1e-14)
    rotvec = expected.as_rotvec()
    assert np.allclose(exp_rotation(rotvec), matrix, atol=1e-14)
    assert np.allclose(log_rotation(matrix), rotvec, atol=1e-11)


def test_rotation_vectors_near_zero_and_near_pi() -> None:
    for rotvec in ([1e-9, -2e-9, 3e-10], [0.0, 0.0, math.pi - 1e-9], [math.pi, 0.0, 0.0]):
        matrix = Rotation.from_rotvec(rotvec).as_matrix()
        assert np.allclose(exp_rotation(np.array(rotvec)), matrix, atol=1e-15)
        back = log_rotation(matrix)
        assert np.allclose(Rotation.from_rotvec(back).as_matrix(), matrix, atol=1e-12)


@given(st.data())
def test_rpy_rates_are_the_derivative_of_the_rotation(data: st.DataObject) -> None:
    robot = hexapod()
    wave = data.draw(waves(robot))
    t = 0.4 + STEPS
    r = np.array([rpy_matrix(wave.rpy(np.array([s]))[0][0]) for s in t])
    angles, rates, accelerations = wave.rpy(np.array([0.4]))
    omega, alpha = rpy_rates(angles, rates, accelerations)
    assert np.allclose(angular_velocity(r, H), omega[0], atol=1e-9)
    omegas = np.array([rpy_rates(*wave.rpy(np.array([s])))[0][0] for s in t])
    assert np.allclose(derivative(omegas, H), alpha[0], atol=1e-8)


# ---------------------------------------------------------------- geometry


def _ups_reference(robot, motion, q):  # type: ignore[no-untyped-def]
    """The closure of every UPS leg written out with scipy's rotations."""
    for i, leg in enumerate(robot.legs):
        u_joint = leg.joints[0]
        cylinder = np.array(u_joint.rotation) @ _rz(q[:, i, 0]) @ _ry(q[:, i, 1])
        centre = np.array(u_joint.position) + q[:, i, 2, None] * cylinder[:, :, 0]
        attach = motion.position + motion.rotation @ np.array(leg.attachment_position)
        assert np.allclose(centre, attach, atol=1e-14)
        sphere = Rotation.from_rotvec(q[:, i, 3:]).as_matrix()
        assert np.allclose(
            cylinder @ sphere, motion.rotation @ np.array(leg.attachment_rotation), atol=1e-13
        )
        assert (q[:, i, 2] > 0).all() and (np.abs(q[:, i, 1]) < math.pi / 2).all()


@given(hexapods(), st.data())
def test_inverse_geometry_closes_every_leg(robot, data) -> None:  # type: ignore[no-untyped-def]
    wave = data.draw(waves(robot))
    motion = wave.motion(np.linspace(0.0, 2.0, 9))
    q = inverse_geometry(robot, motion)
    _ups_reference(robot, motion, q)


def test_home_is_the_zero_of_the_passive_joints() -> None:
    robot = hexapod()
    q = inverse_geometry(robot, PlatformMotion.at_rest(robot.home_position))
    lengths = np.linalg.norm(
        np.array([np.add(leg.attachment_position, robot.home_position) for leg in robot.legs])
        - np.array([leg.joints[0].position for leg in robot.legs]),
        axis=1,
    )
    assert np.allclose(q[0, :, 2], lengths, rtol=1e-15)
    assert np.allclose(q[0, :, 2], 0.1028367, atol=1e-7)  # docs/spatial.md §7
    assert np.abs(q[0, :, [0, 1, 3, 4, 5]]).max() < 1e-15


# ---------------------------------------------------------------- kinematics


@given(hexapods(), st.data())
def test_rates_and_accelerations_match_finite_differences(robot, data) -> None:  # type: ignore[no-untyped-def]
    wave = data.draw(waves(robot))
    t0 = data.draw(st.floats(0.0, 2.0))
    t = t0 + STEPS
    q = np.array([inverse_geometry(robot, wave.motion([s]))[0] for s in t])
    kin = spatial_kinematics(robot, wave.motion([t0]))
    # U and P: the derivatives of q
    assert np.allclose(derivative(q[..., :3], H), kin.dq[0, :, :3], rtol=1e-7, atol=1e-9)
    # S: ω_platform − ω_rod, from the rotations written out with scipy
    motions = [wave.motion([s]) for s in t]
    platform = np.array([m.rotation[0] for m in motions])
    rod = np.array(
        [
            [
                np.array(leg.joints[0].rotation) @ _rz(q[k, i, 0]) @ _ry(q[k, i, 1])
                for i, leg in enumerate(robot.legs)
            ]
            for k in range(5)
        ]
    )
    relative = angular_velocity(platform, H)[None] - angular_velocity(rod, H)
    assert np.allclose(relative, kin.dq[0, :, 3:], rtol=1e-7, atol=1e-9)
    rates = np.array([spatial_kinematics(robot, m).dq[0] for m in motions])
    assert np.allclose(derivative(rates, H), kin.ddq[0], rtol=1e-6, atol=1e-8)


@given(hexapods(), st.data())
def test_the_parallel_jacobian_is_the_hexapods_closed_form(robot, data) -> None:  # type: ignore[no-untyped-def]
    motion = data.draw(waves(robot)).motion(np.linspace(0.0, 1.0, 5))
    kin = spatial_kinematics(robot, motion)
    reference = hexapod_parallel_jacobian(robot, motion)
    assert np.allclose(kin.parallel_jacobian, reference, atol=1e-13)
    twist = np.concatenate([motion.omega, motion.velocity], axis=1)
    assert np.allclose(np.einsum("nlj,nj->nl", reference, twist), kin.dq[:, :, 2], atol=1e-13)
    scaled = reference.copy()
    scaled[..., :3] /= robot.scale
    assert np.allclose(kin.parallel_measure, np.linalg.det(scaled), rtol=1e-10)
    cos_b = np.cos(kin.q[..., 1])
    assert np.allclose(kin.leg_measure, (kin.q[..., 2] / robot.scale) ** 2 * cos_b, rtol=1e-10)


def test_one_sample_and_a_long_batch_by_the_same_code(monkeypatch: pytest.MonkeyPatch) -> None:
    robot = hexapod()
    from spatial_strategies import Wave

    wave = Wave(np.array([0.0, 0.0, 0.08]), np.full(3, 0.004), np.array([1.0, 2.0, 3.0]),
                np.zeros(3), np.full(3, 0.05), np.array([2.0, 1.0, 3.0]), np.ones(3))  # fmt: skip
    motion = wave.motion(np.linspace(0.0, 3.0, 23))
    monkeypatch.setattr(kinematics, "CHUNK", 5)
    monkeypatch.setattr(geometry, "CHUNK", 5)
    batch = spatial_kinematics(robot, motion)
    for k in (0, 4, 5, 11, 22):
        single = spatial_kinematics(robot, motion.chunk(k, k + 1))
        for name in ("q", "dq", "ddq", "parallel_jacobian", "leg_measure", "parallel_measure"):
            assert np.array_equal(getattr(batch, name)[k], getattr(single, name)[0]), name
    assert batch.q.dtype == np.float64 and batch.q.shape == (23, 6, 6)
    assert np.array_equal(inverse_geometry(robot, motion), batch.q)


# ---------------------------------------------------------------- refusals


def test_an_unreachable_sample_is_named_in_its_chunk(monkeypatch: pytest.MonkeyPatch) -> None:
    robot = hexapod()
    monkeypatch.setattr(kinematics, "CHUNK", 4)
    z = np.full(11, 0.08)
    z[9] = 0.2
    position = np.stack([np.zeros(11), np.zeros(11), z], axis=1)
    motion = PlatformMotion.of(
        np.arange(11) * 0.5, position, np.broadcast_to(np.eye(3), (11, 3, 3))
    )
    with pytest.raises(UnreachablePoseError) as caught:
        spatial_kinematics(robot, motion)
    error = caught.value
    assert (error.sample, error.time, error.leg) == (9, 4.5, "1")
    assert "P2 = 0.210179 m is outside its limits [0.085, 0.12]" in str(error)
    assert "\n" not in str(error)


@pytest.mark.parametrize(
    ("rpy", "reason"),
    [
        ([0.0, 0.0, 1.2], "|S3| ="),  # a yaw of 1.2 rad turns every S beyond π/3
        ([0.0, 0.9, 0.0], "outside its limits"),
    ],
)
def test_joint_limits_are_refused(rpy: list[float], reason: str) -> None:
    robot = hexapod(stroke=(0.01, 1.0))
    motion = rpy_motion([0.0], [0.0, 0.0, 0.08], [rpy])
    with pytest.raises(UnreachablePoseError, match=r"^sample 0, t = 0 s, leg \d: ") as caught:
        spatial_kinematics(robot, motion)
    assert reason in str(caught.value)


def test_a_serial_singular_pose_is_refused() -> None:
    robot = hexapod(scale=100.0)  # (q_P/ℓ)²·cos b ≈ 1e-6 < 1e-4 everywhere
    with pytest.raises(SingularPoseError) as caught:
        spatial_kinematics(robot, PlatformMotion.at_rest([0.0, 0.0, 0.08]))
    assert caught.value.leg == "1" and "serial singular: mu_leg = 1.05" in str(caught.value)


def test_a_parallel_singular_pose_is_refused() -> None:
    """The yaw where the closed-form Jacobian's determinant changes sign (found here)."""
    robot = hexapod(stroke=(0.01, 1.0), u_limit=1.5, s_limit=3.0)
    yaws = np.linspace(0.0, 2.0, 2001)
    motion = rpy_motion(yaws * 0.0 + np.arange(2001), np.tile([0.0, 0.0, 0.08], (2001, 1)),
                        np.stack([0 * yaws, 0 * yaws, yaws], axis=1))  # fmt: skip
    det = np.linalg.det(hexapod_parallel_jacobian(robot, motion))
    k = int(np.argmax(np.sign(det) != np.sign(det[0])))
    assert k > 0
    lo, hi = yaws[k - 1], yaws[k]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        m = rpy_motion([0.0], [0.0, 0.0, 0.08], [[0.0, 0.0, mid]])
        if np.sign(np.linalg.det(hexapod_parallel_jacobian(robot, m))[0]) == np.sign(det[0]):
            lo = mid
        else:
            hi = mid
    near = rpy_motion([0.0, 1.0], [[0.0, 0.0, 0.08]] * 2, [[0.0, 0.0, 0.0], [0.0, 0.0, lo]])
    with pytest.raises(SingularPoseError) as caught:
        spatial_kinematics(robot, near)
    assert caught.value.sample == 1 and "parallel singular: mu_par" in str(caught.value)
    away = rpy_motion([0.0], [0.0, 0.0, 0.08], [[0.0, 0.0, lo - 0.05]])
    assert spatial_kinematics(robot, away).parallel_measure[0] > 1e-4


@pytest.mark.parametrize(
    ("build", "message"),
    [
        (lambda: PlatformMotion.of([0.0, 0.0], [[0, 0, 0.08]] * 2, np.eye(3)[None].repeat(2, 0)),
         "sample 1: time must be strictly increasing"),
        (lambda: PlatformMotion.of([0.0], [0, 0, 0.08], [[1, 0, 0], [0, 1, 0], [0, 0, 1.001]]),
         "motion: sample 0: rotation is not a rotation matrix"),
        (lambda: PlatformMotion.of([0.0], [0, 0, 0.08], np.eye(3), omega=[0.0, None, 0.0]),
         "omega must be an array of real numbers"),
        (lambda: quaternion_motion([0.0], [0, 0, 0.08], [[1.0, 0.1, 0.0, 0.0]]),
         "motion: sample 0: quaternion is not a unit quaternion"),
        (lambda: rpy_motion([0.0, 1.0], [[0, 0, 0.08]] * 2, [[0, 0, 0], [0, math.inf, 0]]),
         "motion: sample 1: pitch of rpy is not finite (inf)"),
    ],
)  # fmt: skip
def test_bad_motions_are_refused_naming_the_sample(build, message: str) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(TrajectoryError) as caught:
        build()
    assert message in str(caught.value) and "\n" not in str(caught.value)


def test_bad_parameters_are_refused() -> None:
    with pytest.raises(ParameterError, match="joint rotation is not a rotation matrix"):
        Joint("R", (0.0, 0.0, 0.0), ((1, 0, 0), (0, 1, 0), (0, 0, -1)))
    with pytest.raises(ParameterError, match="principal moments"):
        hexapod(platform=__import__("prp3.spatial.model").spatial.model.Body(
            1.0, (0, 0, 0), ((1.0, 0, 0), (0, 0.1, 0), (0, 0, 0.1))))  # fmt: skip
    with pytest.raises(ParameterError, match="base_radius must be a positive"):
        hexapod(base_radius=-0.1)
    with pytest.raises(ParameterError, match="robot must be a SpatialRobot"):
        spatial_kinematics("6-UPS", PlatformMotion.at_rest([0, 0, 0.08]))  # type: ignore[arg-type]
