"""MuJoCo exchange: ``prp3.apps.mjcf.mjcf_model`` and ``prp3 export mjcf``.

Without MuJoCo: the XML is parsed with the standard library and its kinematic
tree is composed by hand (planar frames: position and angle about ``z``); the
frames must land where ``docs/model.md`` puts the joints and bodies, computed by the
independent reference model of ``strategies.py``.

With MuJoCo (``pytest.importorskip``):

(a) the model's mass matrix (``mj_fullM``), smooth forces (``qfrc_smooth``:
    bias, joint damping, the load applied as ``xfrc_applied``), its
    ``frictionloss`` levels as ideal dry friction and the weld Jacobian
    (``efc_J``) give prp3's actuator forces to 1e-8 relative (of the largest
    ``|f10|`` of the motion) along the paper's motions and random
    robots/motions, with and without payload, load and friction;
(b) a simulation driven by prp3's ``f10`` (RK4, timestep 1e-4 s) follows the
    planned platform pose; tolerances below, explained in ``docs/mujoco.md``.
"""

from __future__ import annotations

import math
import re
import subprocess
import sys
import warnings
import xml.etree.ElementTree as ET
from dataclasses import replace
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from prp3 import LinkParameters, Motion, PistonParameters, PlatformParameters, Robot
from prp3.analysis.inverse_dynamics import inverse_dynamics
from prp3.apps.mjcf import (
    INERTIA_FLOOR,
    MUJOCO_MIN_VALUE,
    TIMESTEP,
    MjcfWarning,
    mjcf_model,
    unrepresented,
)
from prp3.cli import main
from prp3.errors import ParameterError
from prp3.model.motion import PAPER_MOTIONS, law_motion, paper_motion
from prp3.model.parameters import Friction, JointFriction, Load, Payload, Spring, SpringParameters
from strategies import (
    REF_E,
    REF_N,
    AnalyticMotion,
    poses,
    ref_geometry,
    ref_joint,
    ref_rates,
    ref_slide,
    robots,
    scenarios,
    turn,
)

LEGS = ("A", "B", "C")

#: The paper's robot with non-zero centres of mass, another gravity and a
#: turning piston inertia (which must not matter: the piston only translates).
OFFSET_ROBOT = Robot(
    gravity=(3.0, -7.0),
    piston=PistonParameters(mass=1.2, inertia=0.4, com=(0.05, -0.02)),
    link=LinkParameters(mass=0.6, inertia=1e-3, com=(0.03, 0.04)),
    platform=PlatformParameters(mass=2.5, inertia=0.05),
)
#: Zero link and platform inertias: written with MuJoCo's inertia floor.
ZERO_INERTIA_ROBOT = Robot(
    link=LinkParameters(inertia=0.0, com=(0.02, -0.01)),
    platform=PlatformParameters(inertia=0.0),
)
#: The paper's robot carrying a payload off G (no load, no friction).
PAYLOAD_ROBOT = Robot(payload=Payload(mass=0.5, com=(0.02, -0.01), inertia=1e-3))
#: Offsets, a payload, a constant load and viscous + Coulomb friction in every joint.
LOADED_ROBOT = Robot(
    gravity=(3.0, -7.0),
    link=LinkParameters(mass=0.6, inertia=1e-3, com=(0.03, 0.04)),
    payload=Payload(mass=0.8, com=(-0.03, 0.05), inertia=0.0),
    load=Load(force=(2.0, -5.0), moment=0.3),
    friction=Friction(
        actuator=JointFriction(viscous=20.0, coulomb=2.0),
        revolute=JointFriction(viscous=0.05, coulomb=0.01),
        sleeve=JointFriction(viscous=5.0, coulomb=1.5),
    ),
)
ROBOTS = {
    "default": Robot(),
    "offset": OFFSET_ROBOT,
    "zero-inertia": ZERO_INERTIA_ROBOT,
    "payload": PAYLOAD_ROBOT,
    "loaded": LOADED_ROBOT,
}


# --------------------------------------------------------------- XML helpers
def _floats(text: str | None, default: tuple[float, ...]) -> np.ndarray:
    return np.array(default if text is None else [float(v) for v in text.split()])


def _bodies(root: ET.Element) -> dict[str, ET.Element]:
    return {body.get("name", ""): body for body in root.iter("body")}


def _planar_angle(quat: np.ndarray) -> float:
    """Angle about ``z`` of a quaternion ``(w, x, y, z)`` that must turn about ``z`` only."""
    assert quat[1] == 0.0 and quat[2] == 0.0
    assert math.isclose(float(np.linalg.norm(quat)), 1.0, rel_tol=1e-15, abs_tol=1e-15)
    return 2.0 * math.atan2(quat[3], quat[0])


def _rot(angle: float, vector: np.ndarray) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([c * vector[0] - s * vector[1], s * vector[0] + c * vector[1]])


def _frames(root: ET.Element, qpos: dict[str, float]) -> dict[str, tuple[np.ndarray, float]]:
    """World frame (origin, angle) of every body for joint values ``qpos``, composed by hand.

    MJCF: a body sits at ``pos``/``quat`` in its parent's frame; then its slide
    joint moves it along ``axis`` (body frame) by ``qpos`` and its hinge (at the
    body origin, axis ``z``) turns it by ``qpos``.
    """
    frames: dict[str, tuple[np.ndarray, float]] = {}

    def visit(element: ET.Element, origin: np.ndarray, angle: float) -> None:
        for body in element.findall("body"):
            pos = _floats(body.get("pos"), (0.0, 0.0, 0.0))
            assert pos[2] == 0.0
            o = origin + _rot(angle, pos[:2])
            a = angle + _planar_angle(_floats(body.get("quat"), (1.0, 0.0, 0.0, 0.0)))
            for joint in body.findall("joint"):
                axis = _floats(joint.get("axis"), (0.0, 0.0, 1.0))
                value = qpos[joint.get("name", "")]
                if joint.get("type") == "slide":
                    assert axis[2] == 0.0
                    o = o + _rot(a, axis[:2]) * value
                else:
                    assert joint.get("type") == "hinge"
                    assert joint.get("pos") is None and axis.tolist() == [0.0, 0.0, 1.0]
                    a = a + value
            frames[body.get("name", "")] = (o, a)
            visit(body, o, a)

    visit(root.find("worldbody"), np.zeros(2), 0.0)  # type: ignore[arg-type]
    return frames


def _inertial(body: ET.Element) -> tuple[float, np.ndarray, np.ndarray]:
    inertial = body.find("inertial")
    assert inertial is not None
    return (
        float(inertial.get("mass", "nan")),
        _floats(inertial.get("pos"), (0.0, 0.0, 0.0)),
        _floats(inertial.get("diaginertia"), (math.nan,) * 3),
    )


# ------------------------------------------------------ structure (no MuJoCo)
def test_model_structure() -> None:
    root = ET.fromstring(mjcf_model(Robot()))
    assert root.tag == "mujoco"
    joints = {j.get("name", ""): j for j in root.iter("joint") if j.get("name")}
    assert sorted(joints) == sorted(
        f"{kind}_{leg}" for leg in LEGS for kind in ("lambda10", "phi", "lambda32")
    )
    for leg in LEGS:
        assert joints[f"lambda10_{leg}"].get("type") == "slide"
        assert joints[f"phi_{leg}"].get("type") == "hinge"
        assert joints[f"lambda32_{leg}"].get("type") == "slide"
    # each leg is a chain piston → link → platform third hanging from the world
    world = root.find("worldbody")
    assert world is not None
    assert [b.get("name") for b in world.findall("body")] == [f"piston_{leg}" for leg in LEGS]
    bodies = _bodies(root)
    for leg in LEGS:
        assert [b.get("name") for b in bodies[f"piston_{leg}"].findall("body")] == [f"link_{leg}"]
        assert [b.get("name") for b in bodies[f"link_{leg}"].findall("body")] == [f"platform_{leg}"]
        assert bodies[f"platform_{leg}"].findall("body") == []
    # motors on the three base sliders: ctrl is the force f10 in N, unlimited
    motors = root.findall("actuator/motor")
    assert [(m.get("joint"), float(m.get("gear", "nan"))) for m in motors] == [
        (f"lambda10_{leg}", 1.0) for leg in LEGS
    ]
    assert all(m.get("ctrllimited") == "false" and m.get("ctrlrange") is None for m in motors)
    # two welds glue thirds B and C to third A, at their common origin G
    welds = root.findall("equality/weld")
    assert [(w.get("body1"), w.get("body2")) for w in welds] == [
        ("platform_A", "platform_B"),
        ("platform_A", "platform_C"),
    ]
    assert all(_floats(w.get("relpose"), ()).tolist() == [0, 0, 0, 1, 0, 0, 0] for w in welds)
    # no joint limits, no passive forces, no contacts
    assert all(j.get("range") is None and j.get("limited") is None for j in root.iter("joint"))
    assert all(g.get("contype") is None for g in world.iter("geom"))  # default contype=0
    default_geom = root.find("default/geom")
    assert default_geom is not None
    assert default_geom.get("contype") == "0" and default_geom.get("conaffinity") == "0"
    assert root.find("option/flag") is not None
    assert root.find("option/flag").get("contact") == "disable"  # type: ignore[union-attr]
    assert root.find("compiler").get("angle") == "radian"  # type: ignore[union-attr]
    assert root.find("compiler").get("inertiafromgeom") == "false"  # type: ignore[union-attr]


@pytest.mark.parametrize("gravity", [(0.0, -9.81), (0.0, 0.0), (1.5, -2.25)])
def test_gravity_and_options(gravity: tuple[float, float]) -> None:
    root = ET.fromstring(mjcf_model(Robot(gravity=gravity)))
    option = root.find("option")
    assert option is not None
    assert _floats(option.get("gravity"), ()).tolist() == [gravity[0], gravity[1], 0.0]
    assert float(option.get("timestep", "nan")) == TIMESTEP
    assert option.get("integrator") == "RK4"


def test_masses_and_inertias_are_written_exactly() -> None:
    # m3/3 and I3/3 with awkward values must be written with full precision
    robot = Robot(
        piston=PistonParameters(mass=0.1 + 0.2, com=(1.0 / 3.0, -2.0 / 7.0)),
        link=LinkParameters(mass=2.0 / 3.0, inertia=1.0 / 7.0, com=(0.1, 1e-17)),
        platform=PlatformParameters(mass=1.0, inertia=0.1),
    )
    bodies = _bodies(ET.fromstring(mjcf_model(robot)))
    for leg in LEGS:
        mass, com, inertia = _inertial(bodies[f"piston_{leg}"])
        assert mass == 0.1 + 0.2
        assert com.tolist() == [1.0 / 3.0, -2.0 / 7.0, 0.0]
        mass, com, inertia = _inertial(bodies[f"link_{leg}"])
        assert mass == 2.0 / 3.0 and inertia[2] == 1.0 / 7.0
        assert com.tolist() == [0.1, 1e-17, 0.0]
        mass, com, inertia = _inertial(bodies[f"platform_{leg}"])
        assert mass == 1.0 / 3.0 and inertia[2] == 0.1 / 3.0
        assert com.tolist() == [0.0, 0.0, 0.0]


@given(robot=robots())
def test_inertial_parameters(robot: Robot) -> None:
    bodies = _bodies(ET.fromstring(mjcf_model(robot)))
    m1, m2, m3 = robot.piston.mass, robot.link.mass, robot.platform.mass
    # I3 of docs/model.md: the given value, else the uniform plate m3·l²/12 with l = l0·√3
    i3 = robot.platform.inertia
    if i3 is None:
        i3 = m3 * 3.0 * robot.l0**2 / 12.0
    masses = [_inertial(bodies[name])[0] for name in bodies]
    assert math.isclose(sum(masses), 3 * m1 + 3 * m2 + m3, rel_tol=1e-14)
    floor = {
        name: max(INERTIA_FLOOR * mass * robot.l0**2, MUJOCO_MIN_VALUE)
        for name, mass in zip(bodies, masses, strict=True)
    }
    for leg in LEGS:
        for name, izz in (
            (f"piston_{leg}", robot.piston.inertia),
            (f"link_{leg}", robot.link.inertia),
            (f"platform_{leg}", i3 / 3.0),
        ):
            _, _, inertia = _inertial(bodies[name])
            # MuJoCo needs positive moments satisfying the triangle inequality
            assert (inertia > 0).all()
            assert inertia[0] + inertia[1] >= inertia[2]
            assert inertia[0] + inertia[2] >= inertia[1]
            assert inertia[1] + inertia[2] >= inertia[0]
            assert math.isclose(inertia[2], max(izz, floor[name]), rel_tol=1e-15)


@given(pose=poses(), robot=robots(gravity=st.just((0.0, -9.81))))
def test_frames_follow_the_closure(pose: np.ndarray, robot: Robot) -> None:
    # Put the joints at λ10, φ, λ32 of the reference inverse geometry (eq. 10):
    # the three platform thirds must all land on G with angle φ, the pistons on
    # P_i with x along e_i, the links on P_i with x along d_i, and each body's
    # centre of mass where docs/model.md puts it.
    l0 = robot.l0
    pose = pose * l0 / 0.3  # poses() is scaled for l0 = 0.3
    ref = ref_geometry(l0, pose)
    qpos = {}
    for i, leg in enumerate(LEGS):
        qpos[f"lambda10_{leg}"] = float(ref.lambda10[i])
        qpos[f"phi_{leg}"] = float(pose[2])
        qpos[f"lambda32_{leg}"] = float(ref.lambda32[i])
    root = ET.fromstring(mjcf_model(robot))
    frames = _frames(root, qpos)
    bodies = _bodies(root)
    tol = 1e-13 * l0
    d = ref_slide(pose[2])
    for i, leg in enumerate(LEGS):
        origin, angle = frames[f"platform_{leg}"]
        np.testing.assert_allclose(origin, pose[:2], rtol=0, atol=tol)
        assert abs(math.remainder(angle - pose[2], 2 * math.pi)) < 1e-13
        origin, angle = frames[f"piston_{leg}"]
        np.testing.assert_allclose(origin, ref.joint[i], rtol=0, atol=tol)
        np.testing.assert_allclose(_rot(angle, np.array([1.0, 0.0])), REF_E[i], atol=1e-14)
        origin, angle = frames[f"link_{leg}"]
        np.testing.assert_allclose(origin, ref.joint[i], rtol=0, atol=tol)
        np.testing.assert_allclose(_rot(angle, np.array([1.0, 0.0])), d[i], atol=1e-13)
        # centres of mass: piston P_i + c1·(e_i, n_i); link P_i + c2·(d_i, d⊥_i); thirds G
        c1, c2 = robot.piston.com, robot.link.com
        for name, expected in (
            (f"piston_{leg}", ref.joint[i] + c1[0] * REF_E[i] + c1[1] * REF_N[i]),
            (f"link_{leg}", ref.joint[i] + c2[0] * d[i] + c2[1] * turn(d[i])),
            (f"platform_{leg}", pose[:2]),
        ):
            origin, angle = frames[name]
            com = origin + _rot(angle, _inertial(bodies[name])[1][:2])
            np.testing.assert_allclose(com, expected, rtol=0, atol=tol)


def test_central_configuration_is_qpos_zero() -> None:
    # At qpos = 0 the pistons sit at P_i(λ10 = 0) = B_i0 + (l0/√3)·e_i and the thirds at O.
    robot = Robot(l0=0.45)
    root = ET.fromstring(mjcf_model(robot))
    names = [j.get("name", "") for j in root.iter("joint") if j.get("name")]
    frames = _frames(root, dict.fromkeys(names, 0.0))
    for i, leg in enumerate(LEGS):
        np.testing.assert_allclose(
            frames[f"piston_{leg}"][0], ref_joint(0.45, np.zeros(3))[i], atol=1e-16
        )
        np.testing.assert_allclose(frames[f"platform_{leg}"][0], [0.0, 0.0], atol=1e-16)


@pytest.mark.parametrize(
    ("robot", "name"),
    [
        (Robot(piston=PistonParameters(mass=1e-16)), "piston.mass"),
        (Robot(link=LinkParameters(mass=5e-16)), "link.mass"),
        (Robot(platform=PlatformParameters(mass=2.9e-15)), "platform.mass / 3"),
    ],
)
def test_masses_too_small_for_mujoco_are_refused(robot: Robot, name: str) -> None:
    with pytest.raises(ParameterError, match=f"robot: {name} = .* below MuJoCo's smallest"):
        mjcf_model(robot)


def test_tiny_masses_and_inertias_still_load(mujoco: ModuleType) -> None:
    # the smallest accepted mass, and a positive inertia below MuJoCo's limit
    robot = Robot(
        piston=PistonParameters(mass=1e-15, inertia=2e-16),
        link=LinkParameters(inertia=2e-16),
        platform=PlatformParameters(mass=6e-15, inertia=0.0),
    )
    model = mujoco.MjModel.from_xml_string(mjcf_model(robot))
    assert model.body_inertia[1:].min() >= MUJOCO_MIN_VALUE
    assert model.body_mass[1:].min() >= MUJOCO_MIN_VALUE


def test_library_does_not_import_mujoco() -> None:
    code = (
        "import sys, prp3, prp3.apps.mjcf, prp3.cli; "
        "prp3.apps.mjcf.mjcf_model(prp3.Robot()); "
        "assert sys.modules.get('mujoco') is None and sys.modules.get('pinocchio') is None"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


# ----------------------------------------------------------------------- CLI
def test_cli_writes_to_stdout(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["export", "mjcf"]) == 0
    captured = capsys.readouterr()
    assert captured.out == mjcf_model(Robot()) and captured.err == ""


def test_cli_robot_and_output(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    robot_file = tmp_path / "robot.toml"
    robot_file.write_text("l0 = 0.4\ngravity = [0.0, 0.0]\n[link]\ncom = [0.01, 0.0]\n")
    output = tmp_path / "prp3.xml"
    assert main(["export", "mjcf", "--robot", str(robot_file), "--output", str(output)]) == 0
    report = capsys.readouterr().out  # says what it wrote, as every command does
    assert report.startswith(f"prp3 export mjcf: MuJoCo MJCF model of the robot of {robot_file}")
    assert report.endswith(f"bytes\nfiles written:\n  {output}\n")
    assert f", {output.stat().st_size} bytes" in report
    expected = Robot(l0=0.4, gravity=(0.0, 0.0), link=LinkParameters(com=(0.01, 0.0)))
    assert output.read_text(encoding="utf-8") == mjcf_model(expected)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["prp3.xml", "robot.toml"]


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (["export"], "required: FORMAT"),
        (["export", "sdf"], "invalid choice: 'sdf'"),
        (["export", "mjcf", "--robot", "{tmp}/missing.toml"], "missing.toml: cannot read"),
        (["export", "mjcf", "--robot", "{tmp}/bad.toml"], "unknown key 'l1'"),
        (["export", "mjcf", "--output", "{tmp}"], "is a directory"),
        (["export", "mjcf", "--output", "{tmp}/no/such/dir/x.xml"], "cannot write"),
    ],
)
def test_cli_errors(
    arguments: list[str], message: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "bad.toml").write_text("l1 = 0.3\n")
    argv = [a.replace("{tmp}", str(tmp_path)) for a in arguments]
    try:
        status = main(argv)
    except SystemExit as exit_:  # argparse usage errors
        status = int(exit_.code or 0)
    assert status == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1 and "Traceback" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]  # nothing written


def test_cli_help_has_an_example(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exit_:
        main(["export", "mjcf", "--help"])
    assert exit_.value.code == 0
    out = capsys.readouterr().out
    assert "prp3 export mjcf --robot" in out and "--output FILE" in out


# ------------------------------------------------------------ with MuJoCo: (a)
@pytest.fixture(scope="module")
def mujoco() -> ModuleType:
    module: ModuleType = pytest.importorskip("mujoco")
    return module


def _tree_state(robot: Robot, motion: Motion) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``q, q̇, q̈`` (N, 9) in leg order (λ10, φ, λ32) from the reference model."""
    rates = ref_rates(robot.l0, motion.pose, motion.velocity, motion.acceleration)
    geo = ref_geometry(robot.l0, motion.pose)
    phi = np.broadcast_to(motion.pose[:, 2:3], geo.lambda10.shape)
    dphi = np.broadcast_to(motion.velocity[:, 2:3], geo.lambda10.shape)
    ddphi = np.broadcast_to(motion.acceleration[:, 2:3], geo.lambda10.shape)

    def stack(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
        return np.stack([a, b, c], axis=-1).reshape(-1, 9)

    return (
        stack(geo.lambda10, phi, geo.lambda32),
        stack(rates.dlambda10, dphi, rates.dlambda32),
        stack(rates.ddlambda10, ddphi, rates.ddlambda32),
    )


def _load(mujoco: ModuleType, robot: Robot) -> tuple[Any, Any, np.ndarray]:
    """Model, data and the dof address of each tree coordinate in leg order."""
    with warnings.catch_warnings():  # the constant load: applied below as xfrc_applied
        warnings.simplefilter("ignore", MjcfWarning)
        text = mjcf_model(robot)
    model = mujoco.MjModel.from_xml_string(text)
    model.opt.jacobian = mujoco.mjtJacobian.mjJAC_DENSE
    data = mujoco.MjData(model)
    names = [f"{kind}_{leg}" for leg in LEGS for kind in ("lambda10", "phi", "lambda32")]
    order = np.array([model.jnt_dofadr[model.joint(n).id] for n in names])
    return model, data, order


def _mujoco_forces(
    mujoco: ModuleType, robot: Robot, motion: Motion
) -> tuple[np.ndarray, float, float]:
    """f10 (N, 3) from MuJoCo's dynamics; largest weld position and velocity residual.

    ``τ = M·q̈ − qfrc_smooth + c·sign(q̇)``: ``qfrc_smooth`` holds the bias
    forces, the joint damping and the constant load applied as documented
    (``xfrc_applied`` of ``platform_A``, read from the model's ``prp3_load``);
    ``c`` are the model's ``frictionloss`` levels taken as ideal dry friction
    (MuJoCo's own friction is a soft constraint).  ``τ = S·f10 + J_cᵀ·λ`` with
    the planar rows of the weld Jacobian is solved per sample.
    """
    model, data, order = _load(mujoco, robot)
    q, qd, qdd = _tree_state(robot, motion)
    nv = model.nv
    # actuators from the model: transmission joint and gear → selection S (nv × nu)
    selection = np.zeros((nv, model.nu))
    for a in range(model.nu):
        selection[model.jnt_dofadr[model.actuator_trnid[a, 0]], a] = model.actuator_gear[a, 0]
    third = model.body("platform_A").id
    constant = np.array(model.numeric("prp3_load").data) if model.nnumeric else np.zeros(3)
    mass = np.zeros((nv, nv))
    forces = np.empty((len(q), 3))
    worst_pos = worst_vel = 0.0
    for k in range(len(q)):
        data.qpos[order] = q[k]
        data.qvel[order] = qd[k]
        wrench = constant + (0.0 if motion.load is None else motion.load[k])
        data.xfrc_applied[third] = (wrench[0], wrench[1], 0.0, 0.0, 0.0, wrench[2])
        mujoco.mj_forward(model, data)  # positions, velocities, smooth forces, constraints
        mujoco.mj_fullM(model, data, mass)
        acceleration = np.empty(nv)
        acceleration[order] = qdd[k]
        tau = mass @ acceleration - data.qfrc_smooth + model.dof_frictionloss * np.sign(data.qvel)
        welds = np.flatnonzero(data.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY)
        assert len(welds) == 12
        jac = data.efc_J[: data.nefc * nv].reshape(data.nefc, nv)[welds]
        # per weld: rows (x, y, z) of translation, then 3 of rotation; planar rows are
        # x, y and rotation about z; the other three are zero (no out-of-plane dof)
        planar = [0, 1, 5, 6, 7, 11]
        assert not jac[[2, 3, 4, 8, 9, 10]].any()
        system = np.hstack([selection, jac[planar].T])
        solution = np.linalg.solve(system, tau)
        forces[k] = solution[:3]
        worst_pos = max(worst_pos, float(np.abs(data.efc_pos[welds]).max()))
        worst_vel = max(worst_vel, float(np.abs(jac @ data.qvel).max()))
    return forces, worst_pos, worst_vel


def _relative_error(actual: np.ndarray, expected: np.ndarray, robot: Robot) -> float:
    """Largest error over the largest ``|f10|`` (at least 1e-6 N per kg of robot)."""
    mass = 3 * robot.piston.mass + 3 * robot.link.mass + robot.platform.mass
    scale = max(float(np.abs(expected).max()), 1e-6 * mass)
    return float(np.abs(actual - expected).max() / scale)


def test_mujoco_loads_the_model(mujoco: ModuleType) -> None:
    robot = OFFSET_ROBOT
    model, data, _ = _load(mujoco, robot)
    assert (model.nq, model.nv, model.nu, model.neq) == (9, 9, 3, 2)
    expected_mass = 3 * robot.piston.mass + 3 * robot.link.mass + robot.platform.mass
    assert math.isclose(float(model.body_mass.sum()), expected_mass, rel_tol=1e-14)
    assert "payload" not in [model.body(b).name for b in range(model.nbody)]
    assert not model.dof_damping.any() and not model.dof_frictionloss.any() and not model.nnumeric
    np.testing.assert_array_equal(model.opt.gravity, [3.0, -7.0, 0.0])
    mujoco.mj_forward(model, data)  # qpos0: the central configuration closes the loops
    assert np.abs(data.efc_pos).max() < 1e-15


@pytest.mark.parametrize("motion_name", sorted(PAPER_MOTIONS))
@pytest.mark.parametrize("robot_name", sorted(ROBOTS))
def test_mujoco_inverse_dynamics_matches_prp3(
    mujoco: ModuleType, robot_name: str, motion_name: str
) -> None:
    # (a): τ = M(q)·q̈ + c(q, q̇) = S·f10 + J_cᵀ·λ solved for (f10, λ) per sample
    robot = ROBOTS[robot_name]
    motion = paper_motion(motion_name, samples=61)
    forces, worst_pos, worst_vel = _mujoco_forces(mujoco, robot, motion)
    # the reference state closes the loops in MuJoCo's model (positions and velocities)
    assert worst_pos < 1e-14 and worst_vel < 1e-14
    _, dyn = inverse_dynamics(robot, motion)
    # measured ≤ 1e-15 (default, offset, payload, loaded) and ≲ 1e-12 with the inertia floor
    assert _relative_error(forces, dyn.f10, robot) < (
        1e-8 if robot_name == "zero-inertia" else 1e-13
    )


@settings(max_examples=15)
@given(scenario=scenarios())
def test_mujoco_inverse_dynamics_random(
    mujoco: ModuleType, scenario: tuple[Robot, AnalyticMotion]
) -> None:
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 7))
    forces, worst_pos, _ = _mujoco_forces(mujoco, robot, motion)
    assert worst_pos < 1e-13 * robot.l0
    _, dyn = inverse_dynamics(robot, motion)
    assert _relative_error(forces, dyn.f10, robot) < 1e-8


@st.composite
def loaded(draw: st.DrawFn, robot: Robot) -> Robot:
    """``robot`` with a random payload, constant load and viscous + Coulomb friction."""

    def number(low: float, high: float) -> float:
        return draw(st.floats(low, high, allow_nan=False, allow_infinity=False))

    def joint(scale: float) -> JointFriction:
        return JointFriction(viscous=number(0.0, 20.0 * scale), coulomb=number(0.0, 3.0 * scale))

    l0 = robot.l0
    return Robot(
        l0=l0,
        gravity=robot.gravity,
        piston=robot.piston,
        link=robot.link,
        platform=robot.platform,
        payload=Payload(
            mass=number(0.0, 2.0),
            com=(number(-l0, l0) / 3, number(-l0, l0) / 3),
            inertia=number(0.0, 0.01),
        ),
        load=Load(force=(number(-10.0, 10.0), number(-10.0, 10.0)), moment=number(-1.0, 1.0)),
        friction=Friction(actuator=joint(1.0), revolute=joint(l0 / 10), sleeve=joint(1.0)),
    )


@settings(max_examples=10)
@given(scenario=scenarios(), data=st.data())
def test_mujoco_inverse_dynamics_random_loads_and_friction(
    mujoco: ModuleType, scenario: tuple[Robot, AnalyticMotion], data: st.DataObject
) -> None:
    # payload, constant [load], a time-varying TRAJ wrench, viscous and Coulomb friction
    robot, analytic = scenario
    robot = data.draw(loaded(robot))
    plain = analytic.motion(np.linspace(0.0, analytic.duration, 7))
    wrench = data.draw(
        st.lists(
            st.floats(-5.0, 5.0, allow_nan=False, allow_infinity=False), min_size=21, max_size=21
        )
    )
    motion = Motion(
        plain.t, plain.pose, plain.velocity, plain.acceleration, load=np.reshape(wrench, (7, 3))
    )
    forces, worst_pos, _ = _mujoco_forces(mujoco, robot, motion)
    assert worst_pos < 1e-13 * robot.l0
    _, dyn = inverse_dynamics(robot, motion)
    assert _relative_error(forces, dyn.f10, robot) < 1e-8


def test_export_names_what_mujoco_cannot_represent() -> None:
    robot = Robot(
        load=Load(force=(0.0, -5.0)),
        friction=Friction(
            actuator=JointFriction(coulomb=2.0, mu=0.05),
            revolute=JointFriction(mu=0.1),  # no pin radius: no μ term
            sleeve=JointFriction(coulomb=1.0, smoothing=0.01, mu=0.2),
        ),
    )
    with pytest.warns(MjcfWarning) as record:
        text = mjcf_model(robot)
    assert len(record) == 1
    message = str(record[0].message)
    assert "the load-dependent friction friction.actuator.mu;" in message
    assert "the load-dependent friction friction.sleeve.mu;" in message
    assert "friction.revolute" not in message
    assert "smoothing friction.sleeve.smoothing" in message
    assert "data.xfrc_applied[platform_A] = (0, -5.0, 0, 0, 0, 0)" in message
    assert '<numeric name="prp3_load" data="0 -5.0 0"/>' in text
    # smoothing without a Coulomb level changes nothing: no warning
    quiet = Robot(friction=Friction(actuator=JointFriction(viscous=1.0, smoothing=0.1)))
    assert unrepresented(quiet) == [] and unrepresented(Robot()) == []
    assert 'damping="1.0"' in mjcf_model(quiet) and mjcf_model(quiet).count("frictionloss=") == 1


def test_payload_and_friction_in_the_xml() -> None:
    root = ET.fromstring(
        mjcf_model(
            Robot(
                payload=Payload(mass=0.5, com=(0.02, -0.01), inertia=1e-3),
                friction=LOADED_ROBOT.friction,
            )
        )
    )
    (payload,) = [b for b in root.iter("body") if b.get("name") == "payload"]
    parents = {child: parent for parent in root.iter() for child in parent}
    assert parents[payload].get("name") == "platform_A"
    assert payload.find("joint") is None  # welded to the platform
    np.testing.assert_array_equal(_floats(payload.get("pos"), ()), [0.02, -0.01, 0.0])
    inertial = payload.find("inertial")
    assert inertial is not None and inertial.get("mass") == "0.5"
    assert inertial.get("diaginertia") == "0.001 0.001 0.001"
    expected = {"lambda10": ("20.0", "2.0"), "phi": ("0.05", "0.01"), "lambda32": ("5.0", "1.5")}
    for joint in root.iter("joint"):
        name = joint.get("name")
        if name:
            kind = re.sub("_[ABC]$", "", name)
            assert (joint.get("damping"), joint.get("frictionloss")) == expected[kind]


def test_cli_warns_in_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    robot_file = tmp_path / "robot.toml"
    robot_file.write_text("[friction.sleeve]\nmu = 0.1\n")
    with warnings.catch_warnings():  # as outside pytest (whose filter makes warnings errors)
        warnings.simplefilter("always")
        assert main(["export", "mjcf", "--robot", str(robot_file)]) == 0
    err = capsys.readouterr().err
    assert err.startswith("prp3 export mjcf: warning: the MuJoCo model leaves out")
    assert "friction.sleeve.mu" in err and err.count("\n") == 1


# ------------------------------------------------------------ with MuJoCo: (b)
def _drive(
    mujoco: ModuleType, robot: Robot, motion_name: str, starts: list[float], duration: float
) -> list[np.ndarray]:
    """Simulate from the planned state at each start time for ``duration`` seconds.

    The motors get prp3's ``f10`` at the middle of each step (RK4 holds ctrl over
    the step).  Returns, per start, the pose error ``|planned − simulated|``
    (x, y in m, φ in rad) after every step, shape (steps, 3).
    """
    model, data, order = _load(mujoco, robot)
    dt = model.opt.timestep
    half_steps = round(2 * 3.0 / dt)  # the paper's motion at every half step
    motion = law_motion(PAPER_MOTIONS[motion_name], samples=half_steps + 1, duration=3.0)
    _, dyn = inverse_dynamics(robot, motion)
    q, qd, _ = _tree_state(robot, motion)
    third = model.body("platform_A").id
    steps = round(duration / dt)
    errors = []
    wrench = model.numeric("prp3_load").data if model.nnumeric else np.zeros(3)
    for start in starts:
        k0 = round(start / dt)
        mujoco.mj_resetData(model, data)
        data.xfrc_applied[third] = (wrench[0], wrench[1], 0.0, 0.0, 0.0, wrench[2])
        data.time = start
        data.qpos[order] = q[2 * k0]
        data.qvel[order] = qd[2 * k0]
        pose = np.empty((steps, 3))
        for k in range(steps):
            data.ctrl[:] = dyn.f10[2 * (k0 + k) + 1]  # f10 at the middle of the step
            mujoco.mj_step(model, data)
            quat = data.xquat[third]
            pose[k] = (*data.xpos[third, :2], 2.0 * math.atan2(quat[3], quat[0]))
        planned = motion.pose[2 * k0 + 2 : 2 * (k0 + steps) + 1 : 2]
        errors.append(np.abs(pose - planned))
    return errors


@pytest.mark.parametrize("motion_name", sorted(PAPER_MOTIONS))
@pytest.mark.parametrize("robot_name", ["default", "offset"])
def test_simulation_follows_the_plan(mujoco: ModuleType, robot_name: str, motion_name: str) -> None:
    # (b), open loop over the whole motion from the exact initial state.  The
    # force-driven mechanism is unstable (saddle of rate ≈ 6.2 1/s about the
    # held pose, see docs/mujoco.md): the weld compliance (≈ 2e-10 m) seeds an
    # error that grows ×30 every 0.5 s.  Measured (both robots, both motions):
    # ≤ 1.1e-8 up to 1 s, ≤ 6.2e-6 up to 2 s, ≤ 7.5e-4 m and ≤ 6.2e-3 rad at 3 s.
    (error,) = _drive(mujoco, ROBOTS[robot_name], motion_name, [0.0], 3.0)
    steps_per_second = round(1.0 / TIMESTEP)
    assert error[:steps_per_second].max() < 1e-7
    assert error[: 2 * steps_per_second].max() < 1e-4
    assert error[:, :2].max() < 5e-3  # m
    assert error[:, 2].max() < 3e-2  # rad


@pytest.mark.parametrize("motion_name", sorted(PAPER_MOTIONS))
def test_simulation_windows_follow_the_plan(mujoco: ModuleType, motion_name: str) -> None:
    # (b), restarted from the planned state at 1, 1.5, 2 and 2.5 s for 0.25 s
    # (the full run above covers the first second tightly): over a window the
    # instability amplifies by ≈ 5 only, so the local exactness of the forces
    # shows where the full run has drifted.  Measured ≤ 1e-9 (m and rad).
    errors = _drive(mujoco, Robot(), motion_name, [1.0, 1.5, 2.0, 2.5], 0.25)
    assert max(float(e.max()) for e in errors) < 1e-8


def test_simulation_with_payload_load_and_damping(mujoco: ModuleType) -> None:
    # (b) for the first second with a payload, the load as xfrc_applied and viscous
    # friction as joint damping.  Measured (vertical motion): 2.4e-8 with payload and
    # load, 3.8e-9 with damping added (the plain robot: 1.1e-8).  With Coulomb friction
    # (frictionloss, MuJoCo's soft dry friction) instead the error reaches about 0.06.
    robot = Robot(
        payload=Payload(mass=0.5, com=(0.02, -0.01), inertia=1e-3),
        load=Load(force=(2.0, -5.0), moment=0.3),
        friction=Friction(
            actuator=JointFriction(viscous=20.0),
            revolute=JointFriction(viscous=0.05),
            sleeve=JointFriction(viscous=5.0),
        ),
    )
    (error,) = _drive(mujoco, robot, "vertical", [0.0], 1.0)
    assert error.max() < 1e-7


@settings(max_examples=10)
@given(
    scenario=scenarios(),
    stiffness=st.floats(0.0, 3e3),
    rest=st.floats(-0.05, 0.05),
    damping=st.floats(0.0, 30.0),
    viscous=st.floats(0.0, 10.0),
)
def test_mujoco_carries_the_actuator_spring_with_its_own_joint_stiffness(
    mujoco: ModuleType,
    scenario: tuple[Robot, AnalyticMotion],
    stiffness: float,
    rest: float,
    damping: float,
    viscous: float,
) -> None:
    # the spring element writes MuJoCo's stiffness, springref and damping on the lambda10
    # sliders (damping added to the guide's viscous friction); MuJoCo's passive forces
    # (qfrc_smooth) then give prp3's f10 in every method
    robot, analytic = scenario
    robot = replace(
        robot,
        spring=Spring(SpringParameters(stiffness=stiffness, rest=rest, damping=damping)),
        friction=Friction(actuator=JointFriction(viscous=viscous)),
    )
    model, _, order = _load(mujoco, robot)
    sliders = order[0::3]
    np.testing.assert_array_equal(model.jnt_stiffness[[0, 3, 6]], stiffness)
    np.testing.assert_array_equal(model.dof_damping[sliders], damping + viscous)
    np.testing.assert_array_equal(model.qpos_spring[sliders], rest if stiffness else 0.0)
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 7))
    forces, worst_pos, _ = _mujoco_forces(mujoco, robot, motion)
    assert worst_pos < 1e-13 * robot.l0
    for method in ("fast", "paper", "newton-euler"):
        _, dyn = inverse_dynamics(robot, motion, method=method)  # type: ignore[arg-type]
        assert _relative_error(forces, dyn.f10, robot) < 1e-8, method


def test_the_spring_in_the_xml_and_nothing_left_out() -> None:
    robot = Robot(spring=Spring(SpringParameters(stiffness=250.0, rest=0.02, damping=1.5)))
    assert unrepresented(robot) == []
    root = ET.fromstring(mjcf_model(robot))
    for joint in root.iter("joint"):
        name = joint.get("name")
        if name is None:  # the <default> joint
            continue
        spring = (joint.get("stiffness"), joint.get("springref"), joint.get("damping"))
        assert spring == (("250.0", "0.02", "1.5") if name.startswith("lambda10") else (None,) * 3)


@settings(max_examples=10)
@given(
    scenario=scenarios(),
    revolute=st.tuples(st.floats(0.0, 20.0), st.floats(-0.5, 0.5), st.floats(0.0, 2.0)),
    sleeve=st.tuples(st.floats(0.0, 500.0), st.floats(-0.1, 0.1), st.floats(0.0, 20.0)),
)
def test_mujoco_carries_the_springs_of_the_passive_joints(
    mujoco: ModuleType,
    scenario: tuple[Robot, AnalyticMotion],
    revolute: tuple[float, float, float],
    sleeve: tuple[float, float, float],
) -> None:
    # [spring.revolute] on the phi_i hinges and [spring.sleeve] on the lambda32_i sliders:
    # MuJoCo's own joint stiffness, springref and damping (qpos = phi, lambda32) act as
    # prp3's springs, independently of prp3's kernel; every method gives MuJoCo's f10
    robot, analytic = scenario
    robot = replace(
        robot,
        spring=Spring(
            revolute=SpringParameters(*revolute, kind="revolute"),
            sleeve=SpringParameters(*sleeve, kind="sleeve"),
        ),
    )
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 7))
    forces, worst_pos, _ = _mujoco_forces(mujoco, robot, motion)
    assert worst_pos < 1e-13 * robot.l0
    for method in ("fast", "paper", "newton-euler"):
        _, dyn = inverse_dynamics(robot, motion, method=method)  # type: ignore[arg-type]
        assert _relative_error(forces, dyn.f10, robot) < 1e-8, method


def test_the_passive_springs_in_the_xml() -> None:
    robot = Robot(
        spring=Spring(
            revolute=SpringParameters(3.0, 0.25, 0.5, kind="revolute"),
            sleeve=SpringParameters(40.0, 0.01, 2.0, kind="sleeve"),
        )
    )
    assert unrepresented(robot) == []
    root = ET.fromstring(mjcf_model(robot))
    expected = {"phi": ("3.0", "0.25", "0.5"), "lambda32": ("40.0", "0.01", "2.0")}
    for joint in root.iter("joint"):
        name = joint.get("name")
        if name is None:
            continue
        spring = (joint.get("stiffness"), joint.get("springref"), joint.get("damping"))
        assert spring == expected.get(name.rsplit("_", 1)[0], (None,) * 3), name
