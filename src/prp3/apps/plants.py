"""The simulated plants of the control loop: prp3's equations of motion or MuJoCo.

The plant holds each force of the controller until the next control instant
(zero order hold).  It is either prp3's own equations of motion
(``plant="prp3"``: ``q̈ = A(q)⁻¹·(f10 − b(q, q̇))`` of
:func:`prp3.analysis.equations_of_motion.platform_dynamics`, integrated over each step by
``scipy.integrate.solve_ivp`` (:data:`PLANT_RTOL`, :data:`PLANT_ATOL`),
or MuJoCo running the exported MJCF (``plant="mujoco"``,
:func:`prp3.apps.mjcf.mjcf_model`: its own RK4 integrator at ``1e-4 s`` and its
soft weld constraints), which is an independent simulation of the same robot.
:func:`check_plant` refuses a robot a plant would not simulate as it is.  The
closed loop that drives them is :func:`prp3.apps.control.track`.
"""

from __future__ import annotations

import importlib
import math
import warnings
from collections.abc import Callable
from dataclasses import replace
from types import ModuleType
from typing import Literal, Protocol

import numpy as np
from numpy.typing import NDArray

from prp3.analysis.forward import SINGULARITY_STOP
from prp3.engines.compiled_robot import compile_robot
from prp3.errors import ParameterError, Prp3Error
from prp3.family.forward import SINGULARITY_STOP as FAMILY_SINGULARITY_STOP
from prp3.family.forward import FamilyEffortModel, singularity_margin
from prp3.family.mechanics import family_kinematics
from prp3.family.model import FamilyRobot
from prp3.mechanics.kinematics import inverse_kinematics
from prp3.model.motion import Motion
from prp3.model.parameters import Limits
from prp3.model.robot import Robot

__all__ = [
    "PLANTS",
    "PLANT_ATOL",
    "PLANT_RTOL",
    "Plant",
    "check_plant",
]

FloatArray = NDArray[np.float64]
Plant = Literal["prp3", "mujoco"]
Status = Literal["completed", "singular", "stroke", "failed"]

#: The simulated robots :func:`prp3.apps.control.track` can drive.
PLANTS: tuple[Plant, ...] = ("prp3", "mujoco")
#: Tolerances of the prp3 plant's integration over each control step.
PLANT_RTOL: float = 1e-10
PLANT_ATOL: float = 1e-12
#: Runge-Kutta method of the prp3 plant (``scipy.integrate.solve_ivp``).
PLANT_METHOD: str = "RK45"

_THIRD_PI = math.pi / 3.0


def check_plant(robot: Robot | FamilyRobot, plant: Plant) -> None:
    """Refuse a robot the plant would not simulate as it is.

    * ``"mujoco"``: the exported MJCF (:func:`prp3.apps.mjcf.mjcf_model`) carries
      the payload (a body welded to the platform), viscous friction (joint
      damping) and the actuators' spring (the sliders' stiffness, springref
      and damping), and the plant applies the constant ``[load]`` as
      ``xfrc_applied``; MuJoCo has no counterpart of prp3's Coulomb law
      (its ``frictionloss`` is its own dry friction) or of the ``mu`` terms.
    * ``"prp3"``: the plant solves ``f10 = A(q)·q̈ + b(q, q̇)`` for ``q̈``; a
      friction proportional to the joint reactions (``mu``) makes ``f10``
      non-affine in ``q̈``.

    >>> from prp3.model.parameters import Friction, JointFriction
    >>> check_plant(Robot(friction=Friction(sleeve=JointFriction(coulomb=0.5))), "mujoco")
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: plant 'mujoco': friction.sleeve.coulomb = 0.5: MuJoCo has no counterpart of prp3's Coulomb friction law (its frictionloss is its own dry friction): simulate it with plant 'prp3'
    """
    if isinstance(robot, FamilyRobot):
        return  # no friction: affine efforts, and its MJCF carries every body and the payload
    if plant == "mujoco":
        for element in robot.elements:  # each element says what MuJoCo simulates otherwise
            element.check_mujoco_plant(robot)
    elif compile_robot(without_limits(robot)).parameters.has_mu:
        raise ParameterError(
            "plant 'prp3': a friction proportional to the joint reactions (mu) makes the "
            "forces non-affine in the acceleration, which the plant's equations of motion "
            "assume; set the friction's mu to 0"
        )


class PlantProtocol(Protocol):
    def measure(self) -> list[float]: ...
    def advance(
        self, start: float, stop: float, f10: tuple[float, float, float]
    ) -> tuple[Status, str] | None: ...


def without_limits(robot: Robot) -> Robot:
    return robot if robot.limits == Limits() else replace(robot, limits=Limits())


class Prp3Plant:
    """prp3's equations of motion ``q̈ = A⁻¹·(f10 − b)``, integrated step by step.

    ``A`` and ``b`` from four single-sample inverse dynamics (``f10`` is
    affine in ``q̈``, as in :func:`prp3.analysis.equations_of_motion.platform_dynamics`);
    for a family robot ``τ = A·ẍ + b`` of :func:`prp3.family.forward.platform_dynamics`
    and its singularity margin (docs/family.md §6).
    """

    def __init__(self, robot: Robot | FamilyRobot, reference: Motion) -> None:
        from scipy.integrate import solve_ivp

        self._solve_ivp = solve_ivp
        self.robot = robot
        self.effort: Callable[..., tuple[float, ...]]
        if isinstance(robot, FamilyRobot):
            self.effort = FamilyEffortModel(robot).actuator_sample_function()
        else:  # f10 alone, unchecked
            self.effort = compile_robot(without_limits(robot)).actuator_sample_function()
        self.state = np.concatenate([reference.pose[0], reference.velocity[0]])

    def margin(self, pose: list[float]) -> tuple[float, float, str]:
        """The singularity margin of ``pose``, the margin that stops the run, and its text."""
        if isinstance(self.robot, FamilyRobot):
            text = f"the smallest signed singularity measure < {FAMILY_SINGULARITY_STOP:g}"
            return singularity_margin(self.robot, pose), FAMILY_SINGULARITY_STOP, text
        value = abs(math.sin(pose[2] - _THIRD_PI))
        return value, SINGULARITY_STOP, f"|sin(phi - pi/3)| < {SINGULARITY_STOP:g}"

    def measure(self) -> list[float]:
        values: list[float] = self.state.tolist()
        return values

    def _rhs(self, force: FloatArray, state: FloatArray) -> FloatArray:
        x, y, p, vx, vy, vp = state.tolist()
        if not math.isfinite(x + y + p + vx + vy + vp) or self.margin([x, y, p])[0] < 1e-4:
            return np.full(6, np.nan)  # rejects the trial step (see forward_dynamics)
        f = self.effort
        try:
            b = f(x, y, p, vx, vy, vp, 0.0, 0.0, 0.0)
            columns = [
                f(x, y, p, vx, vy, vp, 1.0, 0.0, 0.0),
                f(x, y, p, vx, vy, vp, 0.0, 1.0, 0.0),
                f(x, y, p, vx, vy, vp, 0.0, 0.0, 1.0),
            ]
        except Prp3Error:  # a state the trial step wandered to: reject the trial step
            return np.full(6, np.nan)
        bias = np.array(b)
        A = np.array(columns).T - bias[:, None]
        try:
            acceleration = np.linalg.solve(A, force - bias)
        except np.linalg.LinAlgError:  # a state the step wandered to: reject the trial step
            return np.full(6, np.nan)
        return np.array([vx, vy, vp, *acceleration.tolist()])

    def advance(
        self, start: float, stop: float, f10: tuple[float, float, float]
    ) -> tuple[Status, str] | None:
        force = np.array(f10)
        with np.errstate(all="ignore"):
            solution = self._solve_ivp(
                lambda _t, state: self._rhs(force, state),
                (start, stop),
                self.state,
                method=PLANT_METHOD,
                rtol=PLANT_RTOL,
                atol=PLANT_ATOL,
                first_step=stop - start,
            )
        last = np.asarray(solution.y[:, -1], dtype=np.float64)
        if solution.status == 0 and np.isfinite(last).all():
            self.state = last
            return None
        if np.isfinite(last).all():
            x, y, phi = last[:3].tolist()
            margin, stop, text = self.margin([x, y, phi])
            if margin < stop:
                return "singular", (
                    f"stopped at t = {float(solution.t[-1]):.9g} s: the plant reached the "
                    f"singularity (x = {x:.6g} m, y = {y:.6g} m, phi = {phi:.9g} rad, {text})"
                )
        return "failed", (
            f"stopped: the prp3 plant's integration failed after t = {start!r} s: "
            f"{solution.message}"
        )


def _import_mujoco() -> ModuleType:
    try:
        return importlib.import_module("mujoco")
    except ImportError:
        raise Prp3Error(
            "plant 'mujoco' needs MuJoCo, which is not installed: pip install \"prp3[mujoco]\""
        ) from None


class MujocoPlant:
    """MuJoCo running the robot's MJCF (:func:`prp3.apps.mjcf.mjcf_model`, a family robot's
    :func:`prp3.family.mjcf.family_mjcf_model`), ``ctrl = f10`` (``tau``) held.

    Measured: ``G`` = the position of body ``platform_A`` (origin ``G``; of a family
    robot its inertial frame, the platform frame ``(G, φ)``, and ``φ`` its angle),
    ``φ`` = the hinge ``phi_A`` (its angle is the platform's), ``Ġ`` by
    ``mj_objectVelocity`` and ``φ̇`` the hinge's velocity.
    """

    def __init__(self, robot: Robot | FamilyRobot, reference: Motion) -> None:
        from prp3.apps.mjcf import TIMESTEP, MjcfWarning, mjcf_model
        from prp3.family.mjcf import family_mjcf_model, joint_names

        mujoco = _import_mujoco()
        self.mujoco = mujoco
        self.family = isinstance(robot, FamilyRobot)
        with warnings.catch_warnings():  # the constant [load]: applied below
            warnings.simplefilter("ignore", MjcfWarning)
            text = family_mjcf_model(robot) if isinstance(robot, FamilyRobot) else mjcf_model(robot)
            self.model = mujoco.MjModel.from_xml_string(text)
        self.data = mujoco.MjData(self.model)
        self.timestep = TIMESTEP
        if isinstance(robot, FamilyRobot):  # every leg's joints from home to the first sample
            kin = family_kinematics(robot, reference[0:1])
            for name, q, dq in zip(
                joint_names(robot), kin.q.reshape(9), kin.dq.reshape(9), strict=True
            ):
                joint = self.model.joint(name)
                self.data.qpos[int(joint.qposadr[0])] = q
                self.data.qvel[int(joint.dofadr[0])] = dq
            self.phi = float(reference.pose[0, 2])
        else:
            kin3 = inverse_kinematics(without_limits(robot), reference[0])
            geo = kin3.geometry
            self.data.qpos[:] = np.stack([geo.lambda10, geo.phi21, geo.lambda32], axis=-1).ravel()
            self.data.qvel[:] = np.stack(
                [kin3.dlambda10, kin3.dphi21, kin3.dlambda32], axis=-1
            ).ravel()
        self.body = int(self.model.body("platform_A").id)
        fx, fy = robot.load.force  # at G, the centre of mass of platform_A
        self.data.xfrc_applied[self.body] = (fx, fy, 0.0, 0.0, 0.0, robot.load.moment)
        self.velocity = np.zeros(6)
        mujoco.mj_forward(self.model, self.data)

    def measure(self) -> list[float]:
        mujoco, data = self.mujoco, self.data
        mujoco.mj_objectVelocity(
            self.model, data, mujoco.mjtObj.mjOBJ_BODY, self.body, self.velocity, 0
        )
        vx, vy = self.velocity[3:5].tolist()
        if self.family:  # the inertial frame of platform_A is the platform frame (G, φ)
            x, y = data.xipos[self.body, :2].tolist()
            frame = data.ximat[self.body]
            turned = math.atan2(float(frame[3]), float(frame[0]))
            self.phi += math.remainder(turned - self.phi, 2.0 * math.pi)  # continuous φ
            return [x, y, self.phi, vx, vy, float(self.velocity[2])]
        x, y = data.xpos[self.body, :2].tolist()
        return [x, y, float(data.qpos[1]), vx, vy, float(data.qvel[1])]

    def advance(
        self, start: float, stop: float, f10: tuple[float, float, float]
    ) -> tuple[Status, str] | None:
        mujoco, model, data = self.mujoco, self.model, self.data
        substeps = max(1, math.ceil((stop - start) / self.timestep - 1e-9))
        model.opt.timestep = (stop - start) / substeps
        data.ctrl[:] = f10
        for _ in range(substeps):
            mujoco.mj_step(model, data)
        mujoco.mj_forward(model, data)
        if not (np.isfinite(data.qpos).all() and np.isfinite(data.qvel).all()):
            return "failed", f"stopped: the MuJoCo plant diverged after t = {start!r} s"
        return None
