"""URDF of the spatial robots with their loop closures (docs/spatial.md §25), checked in Pinocchio.

For the 6-UPS, the 3-RPS and the Delta (3-RUU), random designs and motions
(hypothesis): Pinocchio's model built by its URDF parser (``pin.buildModelFromXML``)
from ``prp3.spatial_urdf_model`` is put in prp3's joint values, rates and
accelerations (the platform's ``floating`` joint, a free flyer, from the motion), and

* the frames of each closure pair of the side file (``closed_loop``) coincide: the
  points for ``3D``, the poses for ``6D``, to ``1e-12``;
* the closed chain's inverse dynamics: ``pin.rnea`` of the tree is ``B·τ + J_cᵀ·λ``,
  ``J_c`` the closure frames' Jacobians (``pin.getFrameJacobian``, the platform's
  frame minus the leg's, ``LOCAL_WORLD_ALIGNED``), one square solve for the efforts
  ``τ`` and the closing joints' wrenches ``λ``: prp3's ``tau`` and its reactions at
  the closing joints (S: force; U: force and moment) to ``1e-8`` relative;
* forward: Pinocchio's own constraint models built from the side file as
  example-parallel-robots does (``RigidConstraintModel`` 3D/6D between the two frames)
  and ``constraintDynamics`` give for prp3's ``tau`` prp3's accelerations;
* read back: ``read_spatial_urdf`` gives the same robot to round-off, refuses a
  foreign URDF or one without its closures in one line; ``prp3 export urdf`` writes
  the pair atomically and refuses bad input with one line, exit 2.
"""

from __future__ import annotations

from dataclasses import fields, is_dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from prp3 import (
    SpatialRobot,
    complete_motion,
    delta,
    hexapod,
    read_spatial_urdf,
    spatial_inverse_dynamics,
    spatial_urdf_closures,
    spatial_urdf_model,
    three_rps,
)
from prp3.apps.spatial_urdf import closure_frames, spatial_urdf_robot
from prp3.cli import main
from prp3.errors import InputFileError, ParameterError
from prp3.spatial.rotations import matrix_quaternion
from spatial_strategies import deltas, hexapods, rps_robots, waves

ARCHITECTURES = {"6-UPS": hexapods, "3-RPS": rps_robots, "3-RUU": deltas}
UNKNOWNS = {"6-UPS": 24, "3-RPS": 12, "3-RUU": 21}
TIMES = np.array([0.1, 0.45, 0.8])


def _flat(value: Any) -> list[Any]:
    if is_dataclass(value) and not isinstance(value, type):
        return [leaf for f in fields(value) for leaf in _flat(getattr(value, f.name))]
    if isinstance(value, tuple):
        return [leaf for item in value for leaf in _flat(item)]
    return [value]


def assert_same_robot(a: SpatialRobot, b: SpatialRobot, tol: float = 1e-14) -> None:
    left, right = _flat(a), _flat(b)
    assert len(left) == len(right)
    for x, y in zip(left, right, strict=True):
        if isinstance(x, float) and isinstance(y, float):
            assert x == y or abs(x - y) <= tol * max(1.0, abs(y)), (x, y)
        else:
            assert x == y


@st.composite
def robots_and_motions(draw: st.DrawFn, architecture: str) -> tuple[SpatialRobot, Any]:
    robot = draw(ARCHITECTURES[architecture]())
    motion = draw(waves(robot)).motion(TIMES)
    if robot.parasitic:
        motion = complete_motion(robot, motion)
    return robot, motion


def _state(pin: Any, model: Any, robot: SpatialRobot, solution: Any, motion: Any, n: int) -> tuple[np.ndarray, ...]:
    """Pinocchio's ``q, v, a`` of sample ``n``: prp3's joint values by name; the free flyer
    ``(p, quaternion xyzw)``, ``(Rᵀṗ, Rᵀω)``, ``(Rᵀp̈ − ω_l × v_l, Rᵀα)``."""
    q, v, a = pin.neutral(model), np.zeros(model.nv), np.zeros(model.nv)
    kin = solution.kinematics
    for i, leg in enumerate(robot.legs):
        for c, coordinate in enumerate(leg.coordinates):
            name = f"leg{i + 1}_{coordinate}"
            if not model.existJointName(name):
                assert coordinate.startswith("S")  # the cut S
                continue
            joint = model.joints[model.getJointId(name)]
            q[joint.idx_q], v[joint.idx_v], a[joint.idx_v] = kin.q[n, i, c], kin.dq[n, i, c], kin.ddq[n, i, c]
    free = model.joints[model.getJointId("platform")]
    rotation = motion.rotation[n]
    w, x, y, z = matrix_quaternion(rotation)
    q[free.idx_q : free.idx_q + 7] = [*motion.position[n], x, y, z, w]
    v_l, w_l = rotation.T @ motion.velocity[n], rotation.T @ motion.omega[n]
    v[free.idx_v : free.idx_v + 6] = [*v_l, *w_l]
    a[free.idx_v : free.idx_v + 3] = rotation.T @ motion.acceleration[n] - np.cross(w_l, v_l)
    a[free.idx_v + 3 : free.idx_v + 6] = rotation.T @ motion.alpha[n]
    return q, v, a


def _closure_jacobian(pin: Any, model: Any, data: Any, robot: SpatialRobot) -> tuple[np.ndarray, list[slice]]:
    rows, blocks, start = [], [], 0
    world = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    for leg_frame, platform_frame, kind in closure_frames(robot):
        parts = [pin.getFrameJacobian(model, data, model.getFrameId(f), world)
                 for f in (platform_frame, leg_frame)]  # fmt: skip
        j = parts[0] - parts[1]
        rows.append(j[:3] if kind == "3D" else j)
        blocks.append(slice(start, start + rows[-1].shape[0]))
        start += rows[-1].shape[0]
    return np.vstack(rows), blocks


def _forward_check(pin: Any, model: Any, robot: SpatialRobot, q: np.ndarray, v: np.ndarray,
                   a: np.ndarray, generalised: np.ndarray) -> None:  # fmt: skip
    """Pinocchio's constraint models from the side file (as example-parallel-robots builds
    them) and ``constraintDynamics``: the accelerations of prp3's efforts."""
    models = []
    for first, second, kind in closure_frames(robot):
        f1, f2 = model.frames[model.getFrameId(first)], model.frames[model.getFrameId(second)]
        contact = pin.ContactType.CONTACT_3D if kind == "3D" else pin.ContactType.CONTACT_6D
        models.append(pin.RigidConstraintModel(contact, model, f1.parentJoint, f1.placement,
                                               f2.parentJoint, f2.placement, pin.ReferenceFrame.LOCAL))  # fmt: skip
    data = model.createData()
    models = pin.StdVec_RigidConstraintModel(models)
    datas = pin.StdVec_RigidConstraintData([m.createData() for m in models])
    pin.initConstraintDynamics(model, data, models, datas)
    ddq = pin.constraintDynamics(model, data, q, v, generalised, models, datas)
    scale = max(float(np.abs(a).max()), float(np.linalg.norm(robot.gravity)) / robot.scale)
    assert np.allclose(ddq, a, rtol=0, atol=1e-8 * scale), np.abs(ddq - a).max()


def _kkt_check(pin: Any, model: Any, robot: SpatialRobot, q: np.ndarray, v: np.ndarray,
               a: np.ndarray, generalised: np.ndarray, j_c: np.ndarray) -> None:  # fmt: skip
    """The rigid constrained equations with Pinocchio's ``M`` (crba), bias (rnea at zero
    acceleration), ``J_c`` and ``J̇_c·v`` (the frames' classical accelerations at zero
    ``ddq``): for prp3's efforts, prp3's accelerations."""
    data = model.createData()
    mass = pin.crba(model, data, q)
    mass = np.triu(mass) + np.triu(mass, 1).T
    bias = pin.rnea(model, data, q, v, np.zeros(model.nv)).copy()
    pin.forwardKinematics(model, data, q, v, np.zeros(model.nv))
    pin.updateFramePlacements(model, data)
    world = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    gamma = []
    for first, second, kind in closure_frames(robot):
        acc = [pin.getFrameClassicalAcceleration(model, data, model.getFrameId(f), world).vector
               for f in (second, first)]  # fmt: skip
        gamma.append((acc[0] - acc[1])[:3] if kind == "3D" else acc[0] - acc[1])
    rows = j_c.shape[0]
    kkt = np.block([[mass, -j_c.T], [j_c, np.zeros((rows, rows))]])
    ddq = np.linalg.solve(kkt, np.concatenate([generalised - bias, -np.concatenate(gamma)]))[: model.nv]
    scale = max(float(np.abs(a).max()), float(np.linalg.norm(robot.gravity)) / robot.scale)
    assert np.allclose(ddq, a, rtol=0, atol=1e-8 * scale), np.abs(ddq - a).max()


def _check_architecture(architecture: str, robot: SpatialRobot, motion: Any) -> None:
    pin = pytest.importorskip("pinocchio")
    model = pin.buildModelFromXML(spatial_urdf_model(robot))
    model.gravity.linear = np.array(robot.gravity)
    data = model.createData()
    solution = spatial_inverse_dynamics(robot, motion)
    assert solution.force is not None and solution.moment is not None
    legs = len(robot.legs)
    b = np.zeros((model.nv, legs))
    for i, leg in enumerate(robot.legs):
        joint = model.joints[model.getJointId(f"leg{i + 1}_{leg.coordinates[leg.actuated_coordinate]}")]
        b[joint.idx_v, i] = 1.0
    tau_scale = float(np.abs(solution.tau).max())
    f_scale = float(np.abs(solution.force[:, :, -1]).max())
    m_scale = max(float(np.abs(solution.moment[:, :, -1]).max()), f_scale * robot.scale)
    for n in range(len(motion)):
        q, v, a = _state(pin, model, robot, solution, motion, n)
        pin.forwardKinematics(model, data, q, v, a)
        pin.updateFramePlacements(model, data)
        pin.computeJointJacobians(model, data, q)
        for first, second, kind in closure_frames(robot):
            p1, p2 = data.oMf[model.getFrameId(first)], data.oMf[model.getFrameId(second)]
            assert np.allclose(p1.translation, p2.translation, rtol=0, atol=1e-12 * robot.scale)
            if kind == "6D":
                assert np.allclose(p1.rotation, p2.rotation, rtol=0, atol=1e-12)
        j_c, blocks = _closure_jacobian(pin, model, data, robot)
        assert float(np.abs(j_c @ v).max()) < 1e-10 * max(1.0, float(np.abs(v).max()))
        system = np.hstack([b, j_c.T])
        assert system.shape == (UNKNOWNS[architecture],) * 2
        generalised = pin.rnea(model, data, q, v, a).copy()
        x = np.linalg.solve(system, generalised)
        assert np.allclose(x[:legs], solution.tau[n], rtol=0, atol=1e-8 * tau_scale), (x[:legs], solution.tau[n])
        for i, block in enumerate(blocks):
            w = x[legs:][block]
            assert np.allclose(w[:3], solution.force[n, i, -1], rtol=0, atol=1e-8 * f_scale)
            if w.shape[0] == 6:
                assert np.allclose(w[3:], solution.moment[n, i, -1], rtol=0, atol=1e-8 * m_scale)
        _kkt_check(pin, model, robot, q, v, a, b @ solution.tau[n], j_c)
        if architecture != "3-RUU":  # the Delta's cross and end links have no mass: NaN
            _forward_check(pin, model, robot, q, v, a, b @ solution.tau[n])


@settings(max_examples=8, deadline=None)
@given(robots_and_motions("6-UPS"))
def test_hexapod_in_pinocchio(case: tuple[SpatialRobot, Any]) -> None:
    _check_architecture("6-UPS", *case)


@settings(max_examples=8, deadline=None)
@given(robots_and_motions("3-RPS"))
def test_three_rps_in_pinocchio(case: tuple[SpatialRobot, Any]) -> None:
    _check_architecture("3-RPS", *case)


@settings(max_examples=8, deadline=None)
@given(robots_and_motions("3-RUU"))
def test_delta_in_pinocchio(case: tuple[SpatialRobot, Any]) -> None:
    _check_architecture("3-RUU", *case)


@pytest.mark.parametrize("robot", [hexapod(), three_rps(), delta()], ids=lambda r: r.name)
def test_default_designs_at_their_built_in_motions(robot: SpatialRobot) -> None:
    from prp3 import spatial_motion

    motion = spatial_motion(robot, "heave", 7, 1.0)
    _check_architecture(robot.name, robot, complete_motion(robot, motion) if robot.parasitic else motion)
