"""The interface of a leg architecture: the four stages of the mechanics, and the 3-PRP's.

The paper's method serves any planar parallel robot with three identical legs,
and every route of prp3 runs the same four stages for one:

1. **inverse geometry** — the joint values of every leg at each pose
   (eqs. 7–10 for the 3-PRP);
2. **rates** — the joint velocities and accelerations (eqs. 11–18);
3. **body wrenches** — the wrench each body needs to follow the motion, the
   weights and the applied loads taken off (eqs. 19–22);
4. **virtual work** — the actuator efforts, then every joint force
   (eqs. 15, 16, 21, 23–25).

A leg architecture is an object with these four methods
(:class:`LegArchitecture`).  What the first three return is the
architecture's own — the 3-PRP's closed form gives a few scalars per leg
(:class:`~prp3.mechanics.joint_motion.KernelGeometry`, …), a general leg chain its
frames and 3×3 Jacobians (:class:`prp3.family.architecture.LegChain`) —; the
last returns the one common result, :class:`JointSolution`: the joint
motion, the actuator efforts and every joint force in the family's form
(docs/family.md: joints 1–3 of legs A, B, C; the force of the proximal on the
distal body in the fixed frame, its moment about ``O_k``).
:func:`solve_stages` runs the four stages of any architecture.

:class:`ClosedForm3PRP` is the 3-PRP of docs/model.md as one such
architecture: its stages are :mod:`prp3.mechanics.kernel`'s
(``kernel_geometry``, ``kernel_kinematics``, ``body_wrenches``,
``joint_forces``), run on numpy arrays; the family's 3-PRP conversion (piston
``q1 = λ10``, revolute ``q2 = φ``, sleeve ``q3 = λ32``) gives the common
result.  The other architectures implement the same interface on the leg
chain (:mod:`prp3.family.architecture`); the tests hold the two
implementations of the 3-PRP against each other stage by stage.

>>> import numpy as np
>>> from prp3.analysis.inverse_dynamics import inverse_dynamics
>>> from prp3.model.motion import paper_motion
>>> from prp3.model.robot import Robot
>>> motion = paper_motion("rotation", 31)
>>> solution = solve_stages(ClosedForm3PRP(Robot()), motion)
>>> solution.q.shape, solution.force.shape
((31, 3, 3), (31, 3, 3, 2))
>>> _, newton_euler = inverse_dynamics(Robot(), motion, "newton-euler")
>>> bool(np.allclose(solution.tau, newton_euler.f10, rtol=1e-12, atol=1e-12))
True
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from prp3.mechanics import kernel
from prp3.mechanics.joint_motion import (
    KernelGeometry,
    KernelKinematics,
    kernel_geometry,
    kernel_kinematics,
    rate_floor,
    rest_kinematics,
)
from prp3.mechanics.ops import NUMPY, Legs
from prp3.mechanics.parameters import KernelParameters, kernel_parameters
from prp3.mechanics.virtual_work import joint_forces
from prp3.mechanics.wrenches import BodyWrenches, body_wrenches, friction_forces
from prp3.model.motion import Motion
from prp3.model.robot import Robot
from prp3.pose_validation import check_pose_array
from prp3.validation import check_instance

__all__ = ["ClosedForm3PRP", "JointSolution", "LegArchitecture", "solve_stages"]

FloatArray = NDArray[np.float64]

#: The 3-PRP's leg axes ``α_i`` (eq. 1): ``e_i`` along the guide, ``n_i = Rot(π/2)·e_i``.
_ALPHA = np.array([np.pi / 3, np.pi, -np.pi / 3])


@dataclass(frozen=True)
class JointSolution:
    """What every architecture's virtual-work stage returns (the family's form).

    Batch ``N`` in front, then the legs A, B, C, then the joints 1–3.

    Attributes
    ----------
    q, dq, ddq : ndarray, shape ``(N, 3, 3)``
        Joint values (m or rad, R angles relative to the proximal body) and derivatives.
    tau : ndarray, shape ``(N, 3)``
        The actuator efforts (N or N·m).
    force : ndarray, shape ``(N, 3, 3, 2)``
        The force of the proximal on the distal body at each joint, fixed frame (N).
    moment : ndarray, shape ``(N, 3, 3)``
        Its moment about ``z0``, taken about the joint's origin ``O_k`` (N·m).
    """

    q: FloatArray
    dq: FloatArray
    ddq: FloatArray
    tau: FloatArray
    force: FloatArray
    moment: FloatArray


@runtime_checkable
class LegArchitecture(Protocol):
    """The four stages of the mechanics of a robot with three identical legs.

    Each stage receives the motion (validated: :class:`prp3.Motion`) and what
    the stages before it returned; :meth:`check` refuses what the closed form
    cannot take before stage 1 runs (the stages themselves do not validate).
    """

    @property
    def architecture(self) -> str:
        """The name, ``"3-PRP"``, ``"3-RRR"``, …"""

    def check(self, motion: Motion) -> None:
        """The refusals of the architecture's poses that come before stage 1."""

    def inverse_geometry(self, motion: Motion) -> Any:
        """Stage 1: the joint values of every leg at the poses."""

    def rates(self, motion: Motion, geometry: Any) -> Any:
        """Stage 2: the joint velocities and accelerations."""

    def body_wrenches(self, motion: Motion, kinematics: Any) -> Any:
        """Stage 3: the wrench each body needs, the weights and loads taken off."""

    def virtual_work(self, motion: Motion, kinematics: Any, wrenches: Any) -> JointSolution:
        """Stage 4: the actuator efforts by virtual work, then every joint force."""


def solve_stages(architecture: LegArchitecture, motion: Motion) -> JointSolution:
    """Run the four stages of ``architecture`` along ``motion`` (its ``N`` samples or one).

    Output rank follows the motion's: ``(N, 3, 3)`` or ``(3, 3)`` joint values, …
    """
    architecture = check_instance(
        "architecture",
        architecture,
        LegArchitecture,  # type: ignore[type-abstract]  # a runtime-checkable protocol
        "a leg architecture (four stages)",
    )
    motion = check_instance("motion", motion, Motion, "a prp3.Motion")
    architecture.check(motion)
    geometry = architecture.inverse_geometry(motion)
    kinematics = architecture.rates(motion, geometry)
    wrenches = architecture.body_wrenches(motion, kinematics)
    solution = architecture.virtual_work(motion, kinematics, wrenches)
    shape = motion.t.shape
    return JointSolution(
        **{
            name: np.reshape(getattr(solution, name), shape + trailing)
            for name, trailing in _TRAILING.items()
        }
    )


#: The shape of one sample of each field of :class:`JointSolution`.
_TRAILING: dict[str, tuple[int, ...]] = {
    "q": (3, 3),
    "dq": (3, 3),
    "ddq": (3, 3),
    "tau": (3,),
    "force": (3, 3, 2),
    "moment": (3, 3),
}


def _states(motion: Motion) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The pose, velocity and acceleration of ``motion`` as ``(N, 3)`` arrays."""
    return (
        motion.pose.reshape(-1, 3),
        motion.velocity.reshape(-1, 3),
        motion.acceleration.reshape(-1, 3),
    )


class ClosedForm3PRP:
    """The 3-PRP of docs/model.md: the kernel's closed form as a :class:`LegArchitecture`.

    Parameters
    ----------
    robot : Robot
        Every effect of the robot enters (the loads, the actuators' spring, the
        friction: its explicit part in stage 3, its implicit ``μ`` terms by
        :func:`prp3.mechanics.implicit_friction.solve_mu` in stage 4, as
        :func:`prp3.mechanics.kernel.dynamics` does).
    """

    architecture = "3-PRP"

    def __init__(self, robot: Robot) -> None:
        self.robot = check_instance("robot", robot, Robot, "a prp3.Robot")
        self.parameters = kernel_parameters(self.robot)

    def check(self, motion: Motion) -> None:
        """Bounds and the singular orientation ``sin(φ − π/3) = 0`` (eq. 10 divides by it)."""
        check_pose_array(_states(motion)[0], self.robot, "motion pose")

    def inverse_geometry(self, motion: Motion) -> KernelGeometry:
        """Eqs. (7)–(10): :func:`prp3.mechanics.joint_motion.kernel_geometry`."""
        x, y, phi = _states(motion)[0].T
        return kernel_geometry(NUMPY, self.parameters, x, y, phi)

    def rates(self, motion: Motion, geometry: KernelGeometry) -> KernelKinematics:
        """Eqs. (14), (17): :func:`prp3.mechanics.joint_motion.kernel_kinematics`."""
        _, velocity, acceleration = _states(motion)
        return kernel_kinematics(self.parameters, geometry, *velocity.T, *acceleration.T)

    def body_wrenches(self, motion: Motion, kinematics: KernelKinematics) -> BodyWrenches:
        """Eqs. (19), (20), (22): :func:`prp3.mechanics.wrenches.body_wrenches` (explicit friction)."""
        pose, velocity, acceleration = _states(motion)
        k, dphi = self.parameters, velocity[:, 2]
        floor = _floor(k, kinematics, pose, velocity)
        friction = friction_forces(NUMPY, k, rest_kinematics(kinematics, floor), dphi)
        ddx, ddy, ddphi = acceleration.T
        return body_wrenches(k, kinematics, ddx, ddy, dphi, ddphi, friction=friction)

    def virtual_work(
        self, motion: Motion, kinematics: KernelKinematics, wrenches: BodyWrenches
    ) -> JointSolution:
        """Eqs. (15), (16), (21), (23)–(25): :func:`prp3.mechanics.virtual_work.joint_forces`."""
        pose, velocity, acceleration = _states(motion)
        k = self.parameters
        if k.has_mu:  # the μ terms are implicit: stages 3 and 4 together, solved by Newton
            ddx, ddy, ddphi = acceleration.T
            floor = _floor(k, kinematics, pose, velocity)
            motion_rates = (ddx, ddy, velocity[:, 2], ddphi)
            f10, f21y, f21z, rest, *_ = kernel.dynamics(
                NUMPY, k, kinematics, motion_rates, floor=floor
            )
        else:
            f10, f21y, f21z, rest = joint_forces(k, kinematics, wrenches)
        assert rest is not None
        n10, m10, n32, m32 = (np.stack(np.broadcast_arrays(*v), axis=-1) for v in rest)
        return _family_form(
            kinematics, pose, velocity, acceleration, f10, f21y, f21z, n10, m10, n32, m32
        )


def _floor(
    k: KernelParameters,
    kin: KernelKinematics,
    pose: FloatArray,
    velocity: FloatArray,
) -> FloatArray:
    """:func:`prp3.mechanics.joint_motion.rate_floor` of the states (round-off joint rates)."""
    x, y, _ = pose.T
    dx, dy, dphi = velocity.T
    return np.asarray(rate_floor(NUMPY, k, kin.geometry, x, y, dx, dy, dphi))


def _family_form(
    kin: KernelKinematics,
    pose: FloatArray,
    velocity: FloatArray,
    acceleration: FloatArray,
    f10: Legs,
    f21y: Legs,
    f21z: Legs,
    n10: FloatArray,
    m10: FloatArray,
    n32: FloatArray,
    m32: FloatArray,
) -> JointSolution:
    """The 3-PRP's results as joints 1–3 of a leg chain (docs/family.md, the 3-PRP conversion).

    ``q = (λ10, φ, λ32)``; the guide's force ``f10·e + n10·n`` and moment ``m10``;
    the revolute's force ``f21y·n + f21z·e`` (no moment); the sleeve's force
    ``n32·d⊥`` and moment ``m32 − λ32·n32`` about ``O_3`` (``m32`` is about ``P_i``,
    ``O_3`` lies ``λ32`` along ``d_i``).
    """
    geo = kin.geometry
    samples = velocity.shape[0]
    phi = pose[:, 2]

    def legs(values: Legs) -> FloatArray:
        return np.stack(np.broadcast_arrays(*values), axis=-1) * np.ones((samples, 1))

    lam10, lam32 = legs(geo.lambda10), legs(geo.lambda32)
    turn = np.broadcast_to(phi[:, None], (samples, 3))
    q = np.stack([lam10, turn, lam32], axis=-1)
    dq = np.stack(
        [legs(kin.dlambda10), np.broadcast_to(velocity[:, 2:3], (samples, 3)), legs(kin.dlambda32)],
        -1,
    )
    ddq = np.stack(
        [
            legs(kin.ddlambda10),
            np.broadcast_to(acceleration[:, 2:3], (samples, 3)),
            legs(kin.ddlambda32),
        ],
        -1,
    )
    e = np.stack([np.cos(_ALPHA), np.sin(_ALPHA)], axis=-1)[None]  # (1, 3, 2)
    n = np.stack([-e[..., 1], e[..., 0]], axis=-1)
    angle = _ALPHA[None] + phi[:, None] - np.pi / 3  # d_i = Rot(α_i + φ − π/3)·x0
    d_perp = np.stack([-np.sin(angle), np.cos(angle)], axis=-1)
    tau = legs(f10)
    force = np.stack(
        [
            tau[..., None] * e + n10[..., None] * n,
            legs(f21y)[..., None] * n + legs(f21z)[..., None] * e,
            n32[..., None] * d_perp,
        ],
        axis=2,
    )
    moment = np.stack([m10, np.zeros_like(m10), m32 - lam32 * n32], axis=-1)
    return JointSolution(q=q, dq=dq, ddq=ddq, tau=tau, force=force, moment=moment)
