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

import math
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
from spatial_strategies import (
    ARCHITECTURES,
    assert_same_robot,
    robots_and_motions,
)

#: A round trip gives the robot back to this (relative; the rotations through rpy).
ROUND_TRIP = 1e-14
UNKNOWNS = {"6-UPS": 24, "3-RPS": 12, "3-RUU": 21}


def _state(
    pin: Any, model: Any, robot: SpatialRobot, solution: Any, motion: Any, n: int
) -> tuple[np.ndarray, ...]:
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
            q[joint.idx_q], v[joint.idx_v], a[joint.idx_v] = (
                kin.q[n, i, c],
                kin.dq[n, i, c],
                kin.ddq[n, i, c],
            )
    free = model.joints[model.getJointId("platform")]
    rotation = motion.rotation[n]
    w, x, y, z = matrix_quaternion(rotation)
    q[free.idx_q : free.idx_q + 7] = [*motion.position[n], x, y, z, w]
    v_l, w_l = rotation.T @ motion.velocity[n], rotation.T @ motion.omega[n]
    v[free.idx_v : free.idx_v + 6] = [*v_l, *w_l]
    a[free.idx_v : free.idx_v + 3] = rotation.T @ motion.acceleration[n] - np.cross(w_l, v_l)
    a[free.idx_v + 3 : free.idx_v + 6] = rotation.T @ motion.alpha[n]
    return q, v, a


def _closure_jacobian(
    pin: Any, model: Any, data: Any, robot: SpatialRobot
) -> tuple[np.ndarray, list[slice]]:
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
    ddq = np.linalg.solve(kkt, np.concatenate([generalised - bias, -np.concatenate(gamma)]))[
        : model.nv
    ]
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
        joint = model.joints[
            model.getJointId(f"leg{i + 1}_{leg.coordinates[leg.actuated_coordinate]}")
        ]
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
        assert np.allclose(x[:legs], solution.tau[n], rtol=0, atol=1e-8 * tau_scale), (
            x[:legs],
            solution.tau[n],
        )
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
    _check_architecture(
        robot.name, robot, complete_motion(robot, motion) if robot.parasitic else motion
    )


# ---------------------------------------------------------------- reading back
@settings(max_examples=10, deadline=None)
@given(st.sampled_from(sorted(ARCHITECTURES)).flatmap(lambda a: ARCHITECTURES[a]()))
def test_read_back_gives_the_same_robot(robot: SpatialRobot) -> None:
    assert_same_robot(
        spatial_urdf_robot(spatial_urdf_model(robot), spatial_urdf_closures(robot)),
        robot,
        ROUND_TRIP,
    )


def test_read_back_from_files_of_the_defaults_and_odd_names(tmp_path: Path) -> None:
    quoted = replace(hexapod(), name='my "hexapod" <1> & co')  # XML's special characters
    for k, robot in enumerate((hexapod(), three_rps(), delta(), quoted)):
        path = tmp_path / f"robot{k}.urdf"
        path.write_text(spatial_urdf_model(robot), encoding="utf-8")
        (tmp_path / f"robot{k}.yaml").write_text(spatial_urdf_closures(robot), encoding="utf-8")
        assert_same_robot(read_spatial_urdf(path), robot, ROUND_TRIP)
        other = tmp_path / f"closures{k}.txt"
        other.write_text(spatial_urdf_closures(robot), encoding="utf-8")
        assert_same_robot(read_spatial_urdf(path, other), robot, ROUND_TRIP)


def test_the_closures_follow_example_parallel_robots() -> None:
    """The side file's keys and values as Gepetto's loader reads them (``yaml.safe_load``)."""
    yaml = pytest.importorskip("yaml")
    content = yaml.safe_load(spatial_urdf_closures(three_rps()))
    assert content == {
        "closed_loop": [[f"closedloop{i}_A", f"closedloop{i}_B"] for i in (1, 2, 3)],
        "type": ["3D"] * 3,
        "name_mot": ["leg1_P2", "leg2_P2", "leg3_P2"],
    }


FOREIGN = '<robot name="arm"><link name="base"/></robot>\n'


@pytest.mark.parametrize(
    ("urdf", "closures", "words"),
    [
        (FOREIGN, None, "it has no <prp3_spatial> element"),
        ("<robot><link>", None, "not well-formed XML at line 1"),
        ("<mujoco/>", None, "the root element is <mujoco>"),
        (None, "closed_loop: [[a, b]]\n", "the closures have no closed_loop, type and name_mot"),
        (None, "closed_loop: [\n", "the closures are not YAML"),
        (
            None,
            "closed_loop: [['closedloop1_B', 'closedloop1_A']]\ntype: ['3D']\nname_mot: ['leg1_P2']\n",
            "closed_loop entry 1",
        ),
        (
            None,
            spatial_urdf_closures(three_rps()).replace("'3D', '3D', '3D'", "'3D', '6D', '3D'"),
            "the closure of leg 2 is '6D'; its cut joint needs '3D'",
        ),
        (
            None,
            spatial_urdf_closures(three_rps()).replace("leg3_P2", "leg3_R1"),
            "leg 3 is a RPS actuated at joint 1",
        ),
        (
            None,
            spatial_urdf_closures(three_rps()).replace("leg3_P2", "leg3_S3"),
            "the motor 'leg3_S3' of leg 3",
        ),
    ],
)
def test_a_foreign_pair_is_refused_in_one_line(
    tmp_path: Path, urdf: str | None, closures: str | None, words: str
) -> None:
    pytest.importorskip("yaml")
    path = tmp_path / "robot.urdf"
    path.write_text(spatial_urdf_model(three_rps()) if urdf is None else urdf, encoding="utf-8")
    text = spatial_urdf_closures(three_rps()) if closures is None else closures
    (tmp_path / "robot.yaml").write_text(text, encoding="utf-8")
    with pytest.raises(InputFileError) as info:
        read_spatial_urdf(path)
    message = str(info.value)
    assert "\n" not in message and words in message and "robot.urdf" in message


def test_a_urdf_without_its_closures_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "robot.urdf"
    path.write_text(spatial_urdf_model(delta()), encoding="utf-8")
    with pytest.raises(InputFileError, match=r"the closures' side file .*robot\.yaml is missing"):
        read_spatial_urdf(path)


def test_an_edited_prp3_urdf_is_refused_naming_the_element() -> None:
    robot = hexapod()
    text = spatial_urdf_model(robot).replace(
        'name="leg2_P2" type="prismatic"', 'name="leg2_P2" type="revolute"'
    )
    with pytest.raises(ParameterError, match="joint leg2_P2: type 'revolute'"):
        spatial_urdf_robot(text, spatial_urdf_closures(robot))
    text = spatial_urdf_model(robot).replace(
        '<link name="leg4_body2">', '<link name="leg4_body2_">'
    )
    with pytest.raises(ParameterError, match="leg 4"):
        spatial_urdf_robot(text, spatial_urdf_closures(robot))


def test_limits_round_trip_and_pinocchio_keeps_them() -> None:
    pin = pytest.importorskip("pinocchio")
    robot = delta()
    model = pin.buildModelFromXML(spatial_urdf_model(robot))
    joint = model.joints[model.getJointId("leg2_U3_b")]
    low, high = robot.legs[1].joints[2].limits[1]
    assert (model.lowerPositionLimit[joint.idx_q], model.upperPositionLimit[joint.idx_q]) == (
        low,
        high,
    )
    rps = spatial_urdf_robot(
        spatial_urdf_model(three_rps(s_limit=0.7)), spatial_urdf_closures(three_rps())
    )
    assert rps.legs[2].joints[2].limits == ((0.0, 0.7),)


def test_infinite_ranges_round_trip() -> None:
    robot = three_rps()
    legs = tuple(
        replace(leg, joints=(replace(leg.joints[0], limits=()),
                             replace(leg.joints[1], limits=((0.06, math.inf),)), leg.joints[2]))
        for leg in robot.legs
    )  # fmt: skip
    for changed in (replace(robot, legs=legs), replace(robot, legs=(legs[0], *robot.legs[1:]))):
        text = spatial_urdf_model(changed)
        assert 'type="continuous"' in text and "1e+300" in text
        assert_same_robot(
            spatial_urdf_robot(text, spatial_urdf_closures(changed)), changed, ROUND_TRIP
        )
    unbounded = replace(robot.legs[0].joints[1], limits=((-math.inf, math.inf),))
    slider = replace(robot, legs=tuple(replace(leg, joints=(leg.joints[0], unbounded, leg.joints[2]))
                                       for leg in robot.legs))  # fmt: skip
    back = spatial_urdf_robot(spatial_urdf_model(slider), spatial_urdf_closures(slider))
    assert back.legs[1].joints[1].limits == ((-math.inf, math.inf),)


@settings(max_examples=100, deadline=None)
@given(
    st.sampled_from([hexapod(), three_rps(), delta()]),
    st.integers(0, 10**6),
    st.sampled_from(["nan", "inf", "-1", "0", "1e400", "x", "", "1 2", '"', "<"]),
)
def test_a_mutated_urdf_gives_a_robot_or_one_project_error(
    robot: SpatialRobot, where: int, value: str
) -> None:
    """Any attribute value of a prp3 URDF replaced: a robot, or one ParameterError line."""
    pytest.importorskip("yaml")
    import re

    text = spatial_urdf_model(robot)
    spans = [(m.start(1), m.end(1)) for m in re.finditer(r'="([^"]*)"', text)]
    start, end = spans[where % len(spans)]
    try:
        spatial_urdf_robot(text[:start] + value + text[end:], spatial_urdf_closures(robot))
    except ParameterError as error:
        assert "\n" not in str(error)


# ---------------------------------------------------------------- the command line
@pytest.mark.parametrize("architecture", sorted(ARCHITECTURES))
def test_export_urdf_of_a_spatial_robot_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], architecture: str
) -> None:
    robot_file = tmp_path / "robot.toml"
    robot_file.write_text(f'architecture = "{architecture}"\n', encoding="utf-8")
    output = tmp_path / "robot.urdf"
    assert main(["export", "urdf", "--robot", str(robot_file), "--output", str(output)]) == 0
    out = capsys.readouterr().out
    assert str(output) in out and str(tmp_path / "robot.yaml") in out and architecture in out
    from prp3.io.spatial_robot import read_spatial_robot

    robot = read_spatial_robot(robot_file).robot
    assert output.read_text(encoding="utf-8") == spatial_urdf_model(robot)
    assert (tmp_path / "robot.yaml").read_text(encoding="utf-8") == spatial_urdf_closures(robot)
    if pytest.importorskip("yaml"):
        assert_same_robot(read_spatial_urdf(output), robot, ROUND_TRIP)


def test_export_urdf_refuses_bad_input_in_one_line_and_keeps_the_old_files(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    output = tmp_path / "robot.urdf"
    output.write_text("old", encoding="utf-8")
    (tmp_path / "robot.yaml").write_text("old", encoding="utf-8")
    bad = tmp_path / "bad.toml"
    bad.write_text('architecture = "3-RUU"\n[arm_body]\nmass = -1.0\n', encoding="utf-8")
    planar = tmp_path / "planar.toml"
    planar.write_text("", encoding="utf-8")
    for robot_file, words in ((bad, "arm_body.mass"), (planar, "takes a spatial robot file")):
        assert main(["export", "urdf", "--robot", str(robot_file), "--output", str(output)]) == 2
        err = capsys.readouterr().err.strip()
        assert "\n" not in err and words in err and str(robot_file) in err
    good = tmp_path / "good.toml"
    good.write_text('architecture = "6-UPS"\n', encoding="utf-8")
    assert main(["export", "urdf", "--robot", str(good), "--output", str(tmp_path / "x.yaml")]) == 2
    assert "ends in .yaml" in capsys.readouterr().err
    assert output.read_text(encoding="utf-8") == "old"
    assert (tmp_path / "robot.yaml").read_text(encoding="utf-8") == "old"
