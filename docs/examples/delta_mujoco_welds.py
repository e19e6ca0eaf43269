"""Why the Delta's platform turned on MuJoCo, and what holds it (docs/spatial.md §23, §16).

The MJCF of ``prp3.spatial_mjcf_model(delta())`` (each closing U in a body ``leg{i}_end``
of ``1e-12`` of the platform's mass, welded to the platform) is put in the state of
the circle of period 1 s at ``t = 0`` and driven open loop for 0.3 s by prp3's inverse
dynamics efforts of that circle (held over each step, RK4, ``solref = (2·dt, 1)``).
The 3-RUU keeps the platform parallel to the base, so any rotation is the welds'
giving way; the table is the largest rotation angle of the platform (rad) for each
MuJoCo setting.  ``python docs/examples/delta_mujoco_welds.py`` prints it (a few
seconds; it needs ``mujoco``).
"""

from __future__ import annotations

import re

import mujoco
import numpy as np

from prp3 import delta, spatial_inverse_dynamics, spatial_mjcf_model, spatial_motion

ROBOT = delta()
DURATION = 0.3


def _model(end_mass: float | None) -> mujoco.MjModel:
    text = spatial_mjcf_model(ROBOT)
    if end_mass is not None:  # the end bodies' inertial: mass and the matching inertia
        mass = end_mass * ROBOT.platform.mass
        inertia = mass * ROBOT.scale**2
        text = re.sub(
            r'(<body name="leg\d_end"[^\n]*\n(?:[^\n]*<joint[^\n]*\n)+\s*<inertial pos="0 0 0") '
            r'mass="[^"]+" diaginertia="[^"]+"',
            rf'\1 mass="{mass!r}" diaginertia="{inertia!r} {inertia!r} {inertia!r}"',
            text,
        )
    return mujoco.MjModel.from_xml_string(text)


def worst_rotation(
    step: float = 1e-3, *, end_mass: float | None = None, solimp: float | None = None,
    platform_weight: bool = False, integrator: str = "RK4", noslip: int = 0,
    iterations: int | None = None,
) -> float:  # fmt: skip
    """The largest rotation angle of the platform (rad) over the run, for one setting."""
    model = _model(end_mass)
    model.opt.timestep = step
    model.opt.integrator = getattr(mujoco.mjtIntegrator, f"mjINT_{integrator.upper()}")
    model.opt.noslip_iterations = noslip
    if iterations is not None:
        model.opt.iterations, model.opt.tolerance = iterations, 1e-14
    model.eq_solref[:] = (2.0 * step, 1.0)
    if solimp is not None:
        model.eq_solimp[:, :2] = solimp
    platform = model.body("platform").id
    if platform_weight:
        for i in (1, 2, 3):
            model.body_invweight0[model.body(f"leg{i}_end").id] = model.body_invweight0[platform]
    steps = round(DURATION / step)
    times = (np.arange(steps + 1) + 0.5) * step
    times[-1] = 0.0
    motion = spatial_motion(ROBOT, "circle", duration=1.0, times=np.sort(times))
    solution = spatial_inverse_dynamics(ROBOT, motion)
    data = mujoco.MjData(model)
    for i, leg in enumerate(ROBOT.legs):
        for c, coordinate in enumerate(leg.coordinates):
            joint = model.joint(f"leg{i + 1}_{coordinate}")
            data.qpos[joint.qposadr[0]] = solution.kinematics.q[0, i, c]
            data.qvel[joint.dofadr[0]] = solution.kinematics.dq[0, i, c]
    free = model.joint("platform")
    q0, v0 = int(free.qposadr[0]), int(free.dofadr[0])
    data.qpos[q0 : q0 + 3] = motion.position[0]
    data.qpos[q0 + 3 : q0 + 7] = (1.0, 0.0, 0.0, 0.0)  # the circle keeps R = I
    data.qvel[v0 : v0 + 3] = motion.velocity[0]
    worst = 0.0
    for k in range(steps):
        data.ctrl[:] = solution.tau[k + 1]
        mujoco.mj_step(model, data)
        w = min(1.0, abs(float(data.qpos[q0 + 3])))
        worst = max(worst, 2.0 * float(np.arccos(w)))
    return worst


SETTINGS = {
    "as compiled": {},
    "step 0.1 ms": {"step": 1e-4},
    "solimp 0.9999": {"solimp": 0.9999},
    "noslip_iterations 10": {"noslip": 10},
    "iterations 1000": {"iterations": 1000},
    "Euler integrator": {"integrator": "Euler"},
    "implicitfast integrator": {"integrator": "implicitfast"},
    "end mass 1e-6 of the platform's": {"end_mass": 1e-6},
    "end mass 1e-3 of the platform's": {"end_mass": 1e-3},
    "end bodies: the platform's inverse weight": {"platform_weight": True},
    "and solimp 0.9999 (the MuJoCo plant)": {"platform_weight": True, "solimp": 0.9999},
}


def main() -> None:
    print(f"{'MuJoCo setting':44s} rotation (rad)")
    for name, setting in SETTINGS.items():
        print(f"{name:44s} {worst_rotation(**setting):.1e}")  # type: ignore[arg-type]


if __name__ == "__main__":
    main()
