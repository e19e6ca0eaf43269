"""The "measured" column of docs/mujoco.md: the exported model driven by prp3's forces.

The MJCF model of ``prp3.mjcf_model`` is stepped by MuJoCo (RK4,
the timestep written in the model) from the planned state, its motors given
prp3's ``f10`` at the middle of each step, open loop; the error is
``|planned − simulated|`` of ``x, y`` (m) and ``φ`` (rad) after every step.
The runs are those ``tests/test_mjcf.py`` holds to its tolerances: the
paper's two motions for the default robot and one with centre-of-mass
offsets and another gravity, from ``t = 0`` over 1 s, 2 s and the whole
motion, and restarted from the plan at 1, 1.5, 2 and 2.5 s for 0.25 s.

``python docs/examples/mujoco_drift.py`` prints the table of the document
(``tests/test_docs.py`` compares them; it needs ``mujoco``).
"""

from __future__ import annotations

import math
import sys
import warnings

import mujoco
import numpy as np

from prp3 import (
    LEGS,
    PAPER_MOTIONS,
    Friction,
    JointFriction,
    LinkParameters,
    Load,
    MjcfWarning,
    Payload,
    PistonParameters,
    PlatformParameters,
    Robot,
    inverse_dynamics,
    law_motion,
    mjcf_model,
)

#: The robots of the runs: the paper's, and one with offsets and another gravity.
ROBOTS = {
    "default": Robot(),
    "offset": Robot(
        gravity=(3.0, -7.0),
        piston=PistonParameters(mass=1.2, inertia=0.4, com=(0.05, -0.02)),
        link=LinkParameters(mass=0.6, inertia=1e-3, com=(0.03, 0.04)),
        platform=PlatformParameters(mass=2.5, inertia=0.05),
    ),
}


def mujoco_model(robot: Robot) -> mujoco.MjModel:
    """The MuJoCo model of ``robot`` (prp3's MJCF, its warnings of unrepresented terms muted)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MjcfWarning)
        return mujoco.MjModel.from_xml_string(mjcf_model(robot))


#: MuJoCo's timestep as prp3 writes it in the model (s).
TIMESTEP: float = float(mujoco_model(Robot()).opt.timestep)


def drive(robot: Robot, motion_name: str, starts: list[float], duration: float) -> list[np.ndarray]:
    """Per start time, the pose error after every step, ``(steps, 3)``."""
    model = mujoco_model(robot)
    data = mujoco.MjData(model)
    names = [f"{kind}_{leg}" for leg in LEGS for kind in ("lambda10", "phi", "lambda32")]
    order = np.array([model.jnt_dofadr[model.joint(name).id] for name in names])
    half_steps = round(2 * 3.0 / TIMESTEP)  # the motion at every half step
    motion = law_motion(PAPER_MOTIONS[motion_name], samples=half_steps + 1, duration=3.0)
    kin, dyn = inverse_dynamics(robot, motion)
    geo = kin.geometry
    phi = np.broadcast_to(motion.pose[:, 2:3], geo.lambda10.shape)
    dphi = np.broadcast_to(motion.velocity[:, 2:3], geo.lambda10.shape)
    q = np.stack([geo.lambda10, phi, geo.lambda32], axis=-1).reshape(-1, 9)
    qd = np.stack([kin.dlambda10, dphi, kin.dlambda32], axis=-1).reshape(-1, 9)
    platform = model.body("platform_A").id
    steps = round(duration / TIMESTEP)
    wrench = model.numeric("prp3_load").data if model.nnumeric else np.zeros(3)
    errors = []
    for start in starts:
        k0 = round(start / TIMESTEP)
        mujoco.mj_resetData(model, data)
        # the constant load, which MJCF cannot carry, applied as documented
        data.xfrc_applied[platform] = (wrench[0], wrench[1], 0.0, 0.0, 0.0, wrench[2])
        data.time = start
        data.qpos[order] = q[2 * k0]
        data.qvel[order] = qd[2 * k0]
        pose = np.empty((steps, 3))
        for k in range(steps):
            data.ctrl[:] = dyn.f10[2 * (k0 + k) + 1]
            mujoco.mj_step(model, data)
            w, _, _, z = data.xquat[platform]
            pose[k] = (*data.xpos[platform, :2], 2.0 * math.atan2(z, w))
        planned = motion.pose[2 * k0 + 2 : 2 * (k0 + steps) + 1 : 2]
        errors.append(np.abs(pose - planned))
    return errors


def _e(value: float) -> str:
    mantissa, exponent = f"{value:.1e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def loads() -> None:
    """The first second of the vertical motion with a payload, a load and viscous friction."""
    payload = Payload(mass=0.5, com=(0.02, -0.01), inertia=1e-3)
    load = Load(force=(2.0, -5.0), moment=0.3)
    viscous = Friction(actuator=JointFriction(viscous=20.0),
                       revolute=JointFriction(viscous=0.05), sleeve=JointFriction(viscous=5.0))  # fmt: skip
    runs = {
        "the plain robot": Robot(),
        "a payload and a load": Robot(payload=payload, load=load),
        "and viscous friction in every joint": Robot(payload=payload, load=load, friction=viscous),
        "with Coulomb friction instead (2 N in the guides, 1 N in the sleeves)": Robot(
            payload=payload, load=load,
            friction=Friction(actuator=JointFriction(coulomb=2.0), sleeve=JointFriction(coulomb=1.0)),
        ),
    }  # fmt: skip
    for text, robot in runs.items():
        print(f"{text}: within {_e(float(drive(robot, 'vertical', [0.0], 1.0)[0].max()))}")


def main() -> None:
    if sys.argv[1:] == ["--loads"]:
        loads()
        return
    second = round(1.0 / TIMESTEP)
    whole = [drive(robot, name, [0.0], 3.0)[0] for robot in ROBOTS.values()
             for name in sorted(PAPER_MOTIONS)]  # fmt: skip
    windows = [error for name in sorted(PAPER_MOTIONS)
               for error in drive(ROBOTS["default"], name, [1.0, 1.5, 2.0, 2.5], 0.25)]  # fmt: skip
    one = max(float(e[:second].max()) for e in whole)
    two = max(float(e[: 2 * second].max()) for e in whole)
    metres = max(float(e[:, :2].max()) for e in whole)
    radians = max(float(e[:, 2].max()) for e in whole)
    window = max(float(e.max()) for e in windows)
    print("| run | tolerance | measured |")
    print("|---|---|---|")
    print(f"| from `t = 0`, up to 1 s | 1e-7 | ≤ {_e(one)} |")
    print(f"| from `t = 0`, up to 2 s | 1e-4 | ≤ {_e(two)} |")
    print(f"| from `t = 0`, whole motion (3 s) | 5e-3 m, 3e-2 rad | ≤ {_e(metres)} m, "
          f"≤ {_e(radians)} rad |")  # fmt: skip
    print(f"| restarted from the plan at 1, 1.5, 2, 2.5 s, for 0.25 s | 1e-8 | ≤ {_e(window)} |")


if __name__ == "__main__":
    main()
