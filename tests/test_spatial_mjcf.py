"""MJCF of the spatial robots with the loops closed (docs/spatial.md §16), checked in MuJoCo.

For the 6-UPS, the 3-RPS and the Delta (3-RUU), random designs and motions
(hypothesis), MuJoCo's model written by ``prp3.spatial_mjcf_model`` is put in
the state of prp3's joint values, rates and accelerations (the §9 columns; the
platform's free joint from the motion), and:

* the bodies' frames MuJoCo composes are prp3's chain frames, every loop closes
  (the equality residuals ``efc_pos``) and its velocity too (``efc_J·qvel``);
* the inverse dynamics: MuJoCo's ``mj_inverse`` with the constraints disabled gives
  ``M·qacc + bias``; the actuator efforts and the closing joints' wrenches solve
  ``M·qacc + bias = B·τ + J_cᵀ·w``, ``J_c`` the closures' Jacobians from MuJoCo's
  ``mj_jac`` (the relative twist of the two sites; the connect's rows are
  ``efc_J``'s, the weld's span them).  They equal prp3's ``tau`` and the reaction
  at the closing joint (S: the force; U: force and moment) to 1e-8 relative;
* forward: the rigid constrained equations with MuJoCo's ``M``, bias, ``J_c`` and
  ``J̇_c·qvel`` (``mj_jacDot``) give, for prp3's ``tau``, prp3's accelerations to 1e-8;
* read back: ``read_spatial_mjcf`` gives the same robot to round-off over random
  designs, and refuses a foreign MJCF in one line; ``prp3 export mjcf`` of a spatial
  robot file writes the model atomically, refuses bad input with one line, exit 2.
"""

from __future__ import annotations

import math
import re
from dataclasses import replace
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
    read_spatial_mjcf,
    spatial_inverse_dynamics,
    spatial_mjcf_model,
    three_rps,
)
from prp3.apps.spatial_mjcf import spatial_mjcf_joint_names, spatial_mjcf_robot
from prp3.cli import main
from prp3.errors import InputFileError, ParameterError
from prp3.spatial.geometry import chain_frames
from prp3.spatial.model import Body
from prp3.spatial.rotations import matrix_quaternion
from spatial_strategies import (
    ARCHITECTURES,
    assert_same_robot,
    robots_and_motions,
)

#: A round trip gives the robot back to this (relative; the rotations through xyaxes).
ROUND_TRIP = 1e-15
#: The unknowns of the square solve of each architecture (docs/spatial.md §16).
UNKNOWNS = {"6-UPS": 24, "3-RPS": 12, "3-RUU": 21}


# ---------------------------------------------------------------- MuJoCo
class Closed:
    """MuJoCo's model of a robot in the states of prp3's solution of a motion."""

    def __init__(self, mujoco: Any, robot: SpatialRobot, motion: Any) -> None:
        self.mj = mujoco
        self.robot = robot
        self.model = mujoco.MjModel.from_xml_string(spatial_mjcf_model(robot))
        self.model.opt.jacobian = mujoco.mjtJacobian.mjJAC_DENSE
        self.data = mujoco.MjData(self.model)
        self.solution = spatial_inverse_dynamics(robot, motion)
        self.motion = motion

    def set_state(self, n: int) -> None:
        """qpos, qvel, qacc of sample ``n``: prp3's q, dq, ddq of every hinge and slide; the
        platform's free joint ``(p, quaternion)``, ``(v, Rᵀω)``, ``(a, Rᵀα)``."""
        m, d, kin, motion = self.model, self.data, self.solution.kinematics, self.motion
        names = spatial_mjcf_joint_names(self.robot)
        for i, leg in enumerate(self.robot.legs):
            for c, coordinate in enumerate(leg.coordinates):
                name = f"leg{i + 1}_{coordinate}"
                if name not in names:
                    continue  # a closing S: the connect
                joint = m.joint(name)
                d.qpos[joint.qposadr[0]] = kin.q[n, i, c]
                d.qvel[joint.dofadr[0]] = kin.dq[n, i, c]
                d.qacc[joint.dofadr[0]] = kin.ddq[n, i, c]
        free = m.joint("platform")
        q0, v0 = free.qposadr[0], free.dofadr[0]
        rotation = motion.rotation[n]
        d.qpos[q0 : q0 + 3] = motion.position[n]
        d.qpos[q0 + 3 : q0 + 7] = matrix_quaternion(rotation)
        d.qvel[v0 : v0 + 3] = motion.velocity[n]
        d.qvel[v0 + 3 : v0 + 6] = rotation.T @ motion.omega[n]
        d.qacc[v0 : v0 + 3] = motion.acceleration[n]
        d.qacc[v0 + 3 : v0 + 6] = rotation.T @ motion.alpha[n]
        self.qacc = d.qacc.copy()  # mj_forward overwrites qacc with its own
        self.mj.mj_forward(self.model, d)  # positions, velocities; efc_J with the equalities

    def closures(self) -> tuple[np.ndarray, np.ndarray, list[slice]]:
        """``J_c`` (rows: each leg's closure, the platform's site twist minus the proximal
        body's at the same point) and ``J̇_c·qvel``; the rows of each leg."""
        m, d, mj = self.model, self.data, self.mj
        rows, bias, blocks = [], [], []
        start = 0
        for i, leg in enumerate(self.robot.legs, 1):
            site = m.site(f"platform_leg{i}").id
            point = d.site_xpos[site].copy()
            other = m.body(f"leg{i}_body{len(leg.joints) - 1}" if leg.joints[-1].kind == "S"
                           else f"leg{i}_end").id  # fmt: skip
            parts, dots = [], []
            for body, sign in ((m.body("platform").id, 1.0), (other, -1.0)):
                jacp, jacr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
                mj.mj_jac(m, d, jacp, jacr, point, body)
                dp, dr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
                mj.mj_jacDot(m, d, dp, dr, point, body)
                parts.append(
                    sign * (jacp if leg.joints[-1].kind == "S" else np.vstack([jacp, jacr]))
                )
                dots.append(sign * (dp if leg.joints[-1].kind == "S" else np.vstack([dp, dr])))
            rows.append(parts[0] + parts[1])
            bias.append((dots[0] + dots[1]) @ d.qvel)
            blocks.append(slice(start, start + rows[-1].shape[0]))
            start += rows[-1].shape[0]
        return np.vstack(rows), np.concatenate(bias), blocks

    def actuation(self) -> np.ndarray:
        """``B`` (nv × legs): the motors' generalised forces per unit ctrl (gear 1)."""
        m = self.model
        b = np.zeros((m.nv, m.nu))
        for a in range(m.nu):
            b[m.jnt_dofadr[m.actuator_trnid[a, 0]], a] = m.actuator_gear[a, 0]
        return b

    def inverse(self) -> np.ndarray:
        """``M·qacc + bias`` from ``mj_inverse`` with the constraints disabled."""
        m, d, mj = self.model, self.data, self.mj
        flags = m.opt.disableflags
        m.opt.disableflags = flags | mj.mjtDisableBit.mjDSBL_CONSTRAINT
        d.qacc[:] = self.qacc
        mj.mj_inverse(m, d)
        m.opt.disableflags = flags
        return d.qfrc_inverse.copy()


def _check_architecture(architecture: str, robot: SpatialRobot, motion: Any) -> None:
    mujoco = pytest.importorskip("mujoco")
    closed = Closed(mujoco, robot, motion)
    m, d = closed.model, closed.data
    solution = closed.solution
    legs, joints = len(robot.legs), len(robot.legs[0].joints)
    frames = chain_frames(robot, solution.kinematics.q)
    tau_scale = float(np.abs(solution.tau).max())
    assert solution.force is not None and solution.moment is not None
    for n in range(len(motion)):
        closed.set_state(n)
        # the frames MuJoCo composes are prp3's; the loops close in position and velocity
        for i in range(legs):
            for k in range(joints - 1):
                body = m.body(f"leg{i + 1}_body{k + 1}").id
                assert np.allclose(d.xpos[body], frames.origin[n, i, k], rtol=0, atol=1e-13)
                assert np.allclose(d.xmat[body].reshape(3, 3), frames.rotation[n, i, k], atol=1e-12)
        equality = d.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY
        assert equality.sum() == d.nefc  # no joint limit is active at prp3's poses
        assert float(np.abs(d.efc_pos).max()) < 1e-12 * robot.scale
        j_c, jdot_qvel, blocks = closed.closures()
        efc_j = d.efc_J.reshape(d.nefc, m.nv)
        assert float(np.abs(j_c @ d.qvel).max()) < 1e-10 * max(1.0, float(np.abs(d.qvel).max()))
        for i, block in enumerate(blocks):
            mine, theirs = j_c[block], efc_j[d.efc_id == i]
            if robot.legs[i].joints[-1].kind == "S":  # connect: J(site1 body) − J(site2 body)
                assert np.allclose(-mine, theirs, rtol=0, atol=1e-12)
            else:  # weld: the same row space
                assert np.linalg.matrix_rank(np.vstack([mine, theirs]), tol=1e-9) == 6
        # inverse dynamics: M·qacc + bias = B·τ + J_cᵀ·w
        b = closed.actuation()
        system = np.hstack([b, j_c.T])
        assert system.shape == (UNKNOWNS[architecture],) * 2  # docs/spatial.md §16
        x = np.linalg.solve(system, closed.inverse())
        tau = x[:legs]
        assert np.allclose(tau, solution.tau[n], rtol=0, atol=1e-8 * tau_scale), (
            tau,
            solution.tau[n],
        )
        wrench = x[legs:]
        f_scale = float(np.abs(solution.force[:, :, -1]).max())
        for i, block in enumerate(blocks):
            w = wrench[block]
            assert np.allclose(w[:3], solution.force[n, i, -1], rtol=0, atol=1e-8 * f_scale)
            if w.shape[0] == 6:
                # of the moments, or of the forces times ℓ (a Delta at rest has none)
                m_scale = max(float(np.abs(solution.moment[:, :, -1]).max()), f_scale * robot.scale)
                assert np.allclose(w[3:], solution.moment[n, i, -1], rtol=0, atol=1e-8 * m_scale)
        # forward: the rigid constrained equations for prp3's τ give prp3's accelerations
        mass = np.zeros((m.nv, m.nv))
        mujoco.mj_fullM(m, d, mass)
        rows = j_c.shape[0]
        kkt = np.block([[mass, -j_c.T], [j_c, np.zeros((rows, rows))]])
        rhs = np.concatenate([b @ solution.tau[n] - d.qfrc_bias, -jdot_qvel])
        qacc = np.linalg.solve(kkt, rhs)[: m.nv]
        # of the motion's accelerations, or gravity's (g/ℓ) at rest
        scale = max(
            float(np.abs(closed.qacc).max()), float(np.linalg.norm(robot.gravity)) / robot.scale
        )
        assert np.allclose(qacc, closed.qacc, rtol=0, atol=1e-8 * scale), np.abs(
            qacc - closed.qacc
        ).max()


@settings(max_examples=8, deadline=None)
@given(robots_and_motions("6-UPS"))
def test_hexapod_in_mujoco(case: tuple[SpatialRobot, Any]) -> None:
    _check_architecture("6-UPS", *case)


@settings(max_examples=8, deadline=None)
@given(robots_and_motions("3-RPS"))
def test_three_rps_in_mujoco(case: tuple[SpatialRobot, Any]) -> None:
    _check_architecture("3-RPS", *case)


@settings(max_examples=8, deadline=None)
@given(robots_and_motions("3-RUU"))
def test_delta_in_mujoco(case: tuple[SpatialRobot, Any]) -> None:
    _check_architecture("3-RUU", *case)


@pytest.mark.parametrize("robot", [hexapod(), three_rps(), delta()], ids=lambda r: r.name)
def test_default_designs_at_their_built_in_motions(robot: SpatialRobot) -> None:
    from prp3 import spatial_motion

    motion = spatial_motion(robot, "heave", 7, 1.0)
    _check_architecture(
        robot.name, robot, complete_motion(robot, motion) if robot.parasitic else motion
    )


def test_mj_inverse_with_soft_equalities_is_not_the_rigid_solution() -> None:
    """Why the constraint forces are solved from ``J_c`` (docs/spatial.md §16): MuJoCo's own
    ``mj_inverse`` with the equalities active takes its constraint forces from the soft
    constraint model (the residual accelerations ``J·qacc`` against its reference), not from
    the rigid closure, and leaves the actuators an unbalanced generalised force."""
    mujoco = pytest.importorskip("mujoco")
    robot = hexapod()
    from prp3 import spatial_motion

    closed = Closed(mujoco, robot, spatial_motion(robot, "tilt", 5, 1.0))
    closed.set_state(1)
    d = closed.data
    d.qacc[:] = closed.qacc
    mujoco.mj_inverse(closed.model, d)
    b = closed.actuation()
    tau = closed.solution.tau[1]
    residual = d.qfrc_inverse - b @ tau  # would vanish with the rigid constraint forces
    assert float(np.abs(residual).max()) > 1e-6 * float(np.abs(tau).max())


# ---------------------------------------------------------------- reading back
@settings(max_examples=10, deadline=None)
@given(st.sampled_from(sorted(ARCHITECTURES)).flatmap(lambda a: ARCHITECTURES[a]()))
def test_read_back_gives_the_same_robot(robot: SpatialRobot) -> None:
    assert_same_robot(spatial_mjcf_robot(spatial_mjcf_model(robot)), robot, ROUND_TRIP)


def test_read_back_from_a_file_and_of_the_defaults(tmp_path: Path) -> None:
    quoted = replace(hexapod(), name='my "hexapod" <1> & co')  # XML's special characters
    for k, robot in enumerate((hexapod(), three_rps(), delta(), quoted)):
        path = tmp_path / f"model{k}.xml"
        path.write_text(spatial_mjcf_model(robot), encoding="utf-8")
        assert_same_robot(read_spatial_mjcf(path), robot, ROUND_TRIP)


FOREIGN = """<mujoco model="arm">
  <worldbody><body name="link"><joint type="hinge"/><geom size="0.1"/></body></worldbody>
</mujoco>
"""


@pytest.mark.parametrize(
    ("text", "words"),
    [
        (FOREIGN, "no <custom><text name='prp3_spatial'>"),
        ("<mujoco><worldbody>", "not well-formed XML at line 1"),
        ("<robot name='urdf'/>", "the root element is <robot>"),
    ],
)
def test_a_foreign_mjcf_is_refused_in_one_line(tmp_path: Path, text: str, words: str) -> None:
    path = tmp_path / "foreign.xml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InputFileError) as info:
        read_spatial_mjcf(path)
    message = str(info.value)
    assert "\n" not in message and words in message and "foreign.xml" in message


def test_an_edited_prp3_model_is_refused_naming_the_element() -> None:
    text = spatial_mjcf_model(hexapod()).replace(
        'name="leg2_P2" type="slide"', 'name="leg2_P2" type="hinge"'
    )
    with pytest.raises(ParameterError, match="leg2_body2"):
        spatial_mjcf_robot(text)
    text = spatial_mjcf_model(delta()).replace(
        '<motor name="actuator_3" joint="leg3_R1"', '<motor name="actuator_3" joint="leg3_U2_a"'
    )
    with pytest.raises(ParameterError, match="actuator_3 drives 'leg3_U2_a'"):
        spatial_mjcf_robot(text)


def test_bodies_mujoco_cannot_carry_are_refused() -> None:
    light = Body(0.0, (0.0, 0.0, 0.0), ((1e-6, 0, 0), (0, 1e-6, 0), (0, 0, 1e-6)), "rod")
    with pytest.raises(ParameterError, match=r"leg 1 body 2 \(rod\)\.mass = 0\.0 kg"):
        spatial_mjcf_model(hexapod(rod=light))
    flat = Body(1.0, (0.0, 0.0, 0.0), ((1e-3, 0, 0), (0, 0.0, 0), (0, 0, 1e-3)), "platform")
    with pytest.raises(ParameterError, match=r"platform\.inertia has the principal moment 0"):
        spatial_mjcf_model(hexapod(platform=flat))


def test_limits_round_trip_and_mujoco_keeps_them() -> None:
    mujoco = pytest.importorskip("mujoco")
    robot = delta()
    model = mujoco.MjModel.from_xml_string(spatial_mjcf_model(robot))
    joint = model.joint("leg2_U3_b")
    assert joint.limited[0] and tuple(joint.range) == robot.legs[1].joints[2].limits[1]
    rps = spatial_mjcf_robot(spatial_mjcf_model(three_rps(s_limit=0.7)))
    assert rps.legs[2].joints[2].limits == ((0.0, 0.7),)
    key = model.key("home")
    data = mujoco.MjData(model)
    data.qpos[:] = key.qpos
    mujoco.mj_forward(model, data)
    assert float(np.abs(data.efc_pos).max()) < 1e-13


# ---------------------------------------------------------------- the command line
def _robot_file(tmp_path: Path, architecture: str, extra: str = "") -> Path:
    path = tmp_path / f"{architecture}.toml"
    path.write_text(f'architecture = "{architecture}"\n{extra}', encoding="utf-8")
    return path


@pytest.mark.parametrize("architecture", sorted(ARCHITECTURES))
def test_export_mjcf_of_a_spatial_robot_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], architecture: str
) -> None:
    robot_file = _robot_file(
        tmp_path, architecture, "home_height = 0.09\n" if architecture == "6-UPS" else ""
    )
    output = tmp_path / "model.xml"
    assert main(["export", "mjcf", "--robot", str(robot_file), "--output", str(output)]) == 0
    out = capsys.readouterr().out
    assert str(output) in out and architecture in out
    from prp3.io.spatial_robot import read_spatial_robot

    assert_same_robot(read_spatial_mjcf(output), read_spatial_robot(robot_file).robot, ROUND_TRIP)
    assert main(["export", "mjcf", "--robot", str(robot_file)]) == 0
    assert capsys.readouterr().out == output.read_text(encoding="utf-8")


def test_export_mjcf_refuses_bad_input_in_one_line_and_keeps_the_old_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    output = tmp_path / "model.xml"
    output.write_text("old", encoding="utf-8")
    bad = _robot_file(tmp_path, "3-RUU", "[arm_body]\nmass = -1.0\n")
    assert main(["export", "mjcf", "--robot", str(bad), "--output", str(output)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "arm_body.mass" in err and str(bad) in err
    light = _robot_file(tmp_path, "6-UPS", "[rod]\nmass = 0.0\n")
    assert main(["export", "mjcf", "--robot", str(light), "--output", str(output)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "below MuJoCo's smallest mass" in err and str(light) in err
    assert output.read_text(encoding="utf-8") == "old"
    assert math.isfinite(1.0)


@settings(max_examples=100, deadline=None)
@given(
    st.sampled_from([hexapod(), three_rps(), delta()]),
    st.integers(0, 10**6),
    st.sampled_from(["nan", "inf", "-1", "0", "1e400", "x", "", "1 2", '"', "<"]),
)
def test_a_mutated_model_gives_a_robot_or_one_project_error(
    robot: SpatialRobot, where: int, value: str
) -> None:
    """Any attribute value of a prp3 model replaced: a robot, or one ParameterError line."""
    text = spatial_mjcf_model(robot)
    spans = [(m.start(1), m.end(1)) for m in re.finditer(r'="([^"]*)"', text)]
    start, end = spans[where % len(spans)]
    mutated = text[:start] + value + text[end:]
    try:
        spatial_mjcf_robot(mutated)
    except ParameterError as error:
        assert "\n" not in str(error)
