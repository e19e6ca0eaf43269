"""Peer engines for the inverse-dynamics benchmark: MuJoCo and Pinocchio.

Each engine models the 3-PRP robot as a kinematic tree closed by loop
constraints and solves its closed-chain inverse dynamics exactly, per sample,
in a Python loop, as a user of the engine would:

* tree coordinates ``q = (λ10_i, φ, λ32_i)`` per leg ``i = A, B, C`` (9 joints:
  actuated piston slider, hinge of link 2 whose angle is the platform's ``φ``,
  slider of a platform third along ``d_i``), with ``q̇`` and ``q̈`` taken from
  :func:`prp3.inverse_kinematics` (vectorized, in :meth:`prepare`, untimed);
* ``τ = M(q)·q̈ + c(q, q̇)`` (mass matrix times acceleration plus bias forces:
  Coriolis, centrifugal, gravity) from the engine's recursive Newton–Euler
  algorithm;
* the loop-closure Jacobian ``J_c`` (6×9): the planar rows (``v_x, v_y, ω_z``)
  of the relative velocity of platform thirds B and C with respect to third A,
  from the engine's body/joint Jacobians;
* the 9×9 linear system ``τ = S·f10 + J_cᵀ·λ`` (``S`` selects the three
  actuated sliders) solved for the actuator forces ``f10`` and the six loop
  multipliers ``λ``.

The tree is exact: the platform is split into three thirds (``m3/3`` each,
centre at ``G``, ``I3/3``) welded together, one hanging on each leg.  The
MuJoCo model is the one ``prp3 export mjcf`` writes
(:func:`prp3.mjcf_model`), with its inertia floor for zero inertias;
the Pinocchio model is built in code with the same frames and the exact
inertias (Pinocchio accepts zero inertias).

``benchmarks/`` is not a package: import this file by path.  Both engines are
optional (``pip install .[bench]``); :func:`available_peers` returns the peers
whose engine imports.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

import prp3
from prp3 import LEGS, mjcf_model
from prp3.mechanics.geometry import ALPHA, LEG_AXIS, base_vertices

__all__ = ["MujocoPeer", "PinocchioPeer", "TreeMotion", "available_peers", "tree_motion"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class TreeMotion:
    """Tree coordinates of a motion, in an engine's joint order.

    Attributes
    ----------
    q, qd, qdd : ndarray, shape (N, 9) or (9,)
        Joint positions (m, rad), velocities and accelerations.
    """

    q: FloatArray
    qd: FloatArray
    qdd: FloatArray


def tree_motion(robot: prp3.Robot, motion: prp3.Motion) -> TreeMotion:
    """Tree coordinates in leg order ``(λ10_A, φ, λ32_A, λ10_B, φ, λ32_B, λ10_C, φ, λ32_C)``.

    The hinge of link 2 measures the platform angle ``φ`` (``φ21 = φ``, eq. 7),
    so its rate and acceleration are ``φ̇`` and ``φ̈``.
    """
    kin = prp3.inverse_kinematics(robot, motion)
    geo = kin.geometry
    batch = geo.lambda10.shape[:-1]

    def stack(*per_leg: FloatArray) -> FloatArray:
        return np.ascontiguousarray(np.stack(per_leg, axis=-1).reshape(*batch, 9))

    return TreeMotion(
        q=stack(geo.lambda10, geo.phi21, geo.lambda32),
        qd=stack(kin.dlambda10, kin.dphi21, kin.dlambda32),
        qdd=stack(kin.ddlambda10, kin.ddphi21, kin.ddlambda32),
    )


def _sample(prepared: TreeMotion, i: int) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Sample ``i`` of a batch; a single-sample motion has only sample 0."""
    q, qd, qdd = (a.reshape(-1, 9) for a in (prepared.q, prepared.qd, prepared.qdd))
    return q[i], qd[i], qdd[i]


def _loop_over(solve: Any, prepared: TreeMotion) -> FloatArray:
    q = prepared.q.reshape(-1, 9)
    qd = prepared.qd.reshape(-1, 9)
    qdd = prepared.qdd.reshape(-1, 9)
    out = np.empty((q.shape[0], 3))
    for k in range(q.shape[0]):
        out[k] = solve(q[k], qd[k], qdd[k])
    return out.reshape(*prepared.q.shape[:-1], 3)


class MujocoPeer:
    """Closed-chain inverse dynamics with MuJoCo, on the model of ``prp3 export mjcf``.

    Per sample: ``mj_kinematics``, ``mj_comPos``, ``mj_comVel``, then
    ``mj_rne`` with ``flg_acc = 1`` (``M·q̈ + c``, gravity included) and
    ``mj_jacBody`` of the three platform thirds; the soft-constraint machinery
    (``efc_*``, ``qfrc_constraint``) is not involved, so the answer is exact.
    """

    name = "mujoco"

    def __init__(self, robot: prp3.Robot) -> None:
        import mujoco

        self._mj = mujoco
        self.robot = robot
        self.model = mujoco.MjModel.from_xml_string(mjcf_model(robot))
        self.data = mujoco.MjData(self.model)
        m = self.model
        # qpos/dof address of each joint in leg order (all joints have one dof)
        names = [f"{kind}_{leg}" for leg in LEGS for kind in ("lambda10", "phi", "lambda32")]
        self._order = np.array([int(m.jnt_dofadr[m.joint(n).id]) for n in names])
        self._identity_order = bool((self._order == np.arange(9)).all())
        self._thirds = [int(m.body(f"platform_{leg}").id) for leg in LEGS]
        self._tau = np.zeros(m.nv)
        # Jacobians of the thirds: jac[k, :3] translation of its origin G, jac[k, 3:] rotation
        self._jac = np.zeros((3, 6, m.nv))
        # planar rows (v_x, v_y, ω_z) of third B minus third A, then of C minus A
        self._difference = np.zeros((6, 18))
        for r, row in enumerate((0, 1, 5)):
            for k in (1, 2):
                self._difference[3 * (k - 1) + r, 6 * k + row] = 1.0
                self._difference[3 * (k - 1) + r, row] = -1.0
        # τ = S·f10 + J_cᵀ·λ: columns 0-2 select the actuated dofs, 3-8 are J_cᵀ
        self._system = np.zeros((m.nv, 9))
        for i, leg in enumerate(LEGS):
            self._system[m.jnt_dofadr[m.joint(f"lambda10_{leg}").id], i] = 1.0

    def prepare(self, motion: prp3.Motion) -> TreeMotion:
        """Tree ``q, q̇, q̈`` of every sample, in MuJoCo's dof order (vectorized, untimed)."""
        tree = tree_motion(self.robot, motion)
        if self._identity_order:
            return tree
        inverse = np.argsort(self._order)
        return TreeMotion(
            q=tree.q[..., inverse], qd=tree.qd[..., inverse], qdd=tree.qdd[..., inverse]
        )

    def single(self, q: FloatArray, qd: FloatArray, qdd: FloatArray) -> FloatArray:
        """Actuator forces ``f10`` (3,) (N) of one tree state ``q, q̇, q̈`` (9,) each."""
        mj, m, d = self._mj, self.model, self.data
        d.qpos[:] = q
        d.qvel[:] = qd
        d.qacc[:] = qdd
        mj.mj_kinematics(m, d)
        mj.mj_comPos(m, d)
        mj.mj_comVel(m, d)
        tau = self._tau
        mj.mj_rne(m, d, 1, tau)  # M(q)·q̈ + c(q, q̇)
        jac = self._jac
        for k, body in enumerate(self._thirds):
            mj.mj_jacBody(m, d, jac[k, :3], jac[k, 3:], body)
        system = self._system
        system[:, 3:] = (self._difference @ jac.reshape(18, -1)).T  # J_cᵀ
        return np.linalg.solve(system, tau)[:3]

    def single_state(
        self, prepared: TreeMotion, i: int
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``(q, q̇, q̈)`` of sample ``i`` (untimed)."""
        return _sample(prepared, i)

    def forces(self, prepared: TreeMotion) -> FloatArray:
        """Actuator forces ``f10`` (N, 3) of every prepared sample (Python loop)."""
        return _loop_over(self.single, prepared)


def _rotation_z(angle: float) -> FloatArray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


class PinocchioPeer:
    """Closed-chain inverse dynamics with Pinocchio, its model built with ``pinocchio.Model``.

    Per sample: ``rnea`` (``M·q̈ + c``), then ``computeJointJacobians`` (it
    places the joints; ``rnea`` works in local frames and leaves ``data.oMi``
    alone), which returns ``data.J``: the motion subspace of every joint in the
    world frame.  The world-frame Jacobian of a platform third is ``data.J`` on
    the three joints of its leg (zero elsewhere), so the loop rows of third B
    relative to third A are ``+J`` on leg B's columns and ``−J`` on leg A's.
    (Equal twists at the world origin ⇔ equal twists at ``G``: these rows are
    an invertible recombination of those of ``getJointJacobian(...,
    LOCAL_WORLD_ALIGNED)``, the multipliers change, ``f10`` does not.)
    """

    name = "pinocchio"

    def __init__(self, robot: prp3.Robot) -> None:
        import pinocchio as pin

        self._pin = pin
        self.robot = robot
        self.model = self._build(pin, robot)
        self.data = self.model.createData()
        # joint order is leg order: λ10, φ, λ32 of A, then of B, then of C
        legs = np.repeat(np.arange(3), 3)
        # loop rows: third B minus third A, third C minus third A (shape (2, 1, 9))
        self._relative = np.stack([(legs == k).astype(float) - (legs == 0) for k in (1, 2)])[
            :, None, :
        ]
        self._system = np.zeros((9, 9))
        for i in range(3):
            self._system[3 * i, i] = 1.0  # joint order: λ10, φ, λ32 per leg

    @staticmethod
    def _build(pin: Any, robot: prp3.Robot) -> Any:
        """The tree of :mod:`prp3.apps.mjcf` with Pinocchio joints and exact inertias."""
        model = pin.Model()
        model.name = "prp3"
        gx, gy = robot.gravity
        model.gravity = pin.Motion(np.array([gx, gy, 0.0]), np.zeros(3))
        l0 = robot.l0
        piston_origin = base_vertices(robot) + (l0 / math.sqrt(3.0)) * LEG_AXIS
        c = 0.5 * l0 * np.array([1.0 / math.sqrt(3.0), 1.0])
        third_in_link = _rotation_z(math.pi / 3.0)[:2, :2] @ c  # G − P_i in link i's frame

        def inertia(mass: float, com: tuple[float, float], izz: float) -> Any:
            return pin.Inertia(mass, np.array([com[0], com[1], 0.0]), np.diag([izz, izz, izz]))

        for i, leg in enumerate(LEGS):
            alpha = float(ALPHA[i])
            origin = np.array([piston_origin[i, 0], piston_origin[i, 1], 0.0])
            piston = model.addJoint(
                0, pin.JointModelPX(), pin.SE3(_rotation_z(alpha), origin), f"lambda10_{leg}"
            )
            model.appendBodyToJoint(
                piston,
                inertia(robot.piston.mass, robot.piston.com, robot.piston.inertia),
                pin.SE3.Identity(),
            )
            link = model.addJoint(
                piston,
                pin.JointModelRZ(),
                pin.SE3(_rotation_z(-math.pi / 3.0), np.zeros(3)),  # hinge angle = φ
                f"phi_{leg}",
            )
            model.appendBodyToJoint(
                link,
                inertia(robot.link.mass, robot.link.com, robot.link.inertia),
                pin.SE3.Identity(),
            )
            third = model.addJoint(  # slides along d_i = link's x axis; origin at G
                link,
                pin.JointModelPX(),
                pin.SE3(np.eye(3), np.array([third_in_link[0], third_in_link[1], 0.0])),
                f"lambda32_{leg}",
            )
            model.appendBodyToJoint(
                third,
                inertia(robot.platform.mass / 3.0, (0.0, 0.0), robot.platform_inertia / 3.0),
                pin.SE3.Identity(),
            )
        return model

    def prepare(self, motion: prp3.Motion) -> TreeMotion:
        """Tree ``q, q̇, q̈`` of every sample (vectorized, untimed); joint order is leg order."""
        return tree_motion(self.robot, motion)

    def single(self, q: FloatArray, qd: FloatArray, qdd: FloatArray) -> FloatArray:
        """Actuator forces ``f10`` (3,) (N) of one tree state ``q, q̇, q̈`` (9,) each."""
        pin, model, data = self._pin, self.model, self.data
        tau = pin.rnea(model, data, q, qd, qdd)  # M(q)·q̈ + c(q, q̇)
        world = pin.computeJointJacobians(model, data, q)  # data.J, world frame
        system = self._system
        # planar rows (v_x, v_y, ω_z) of the twists of thirds B and C relative to A
        system[:, 3:] = (self._relative * world[[0, 1, 5]]).reshape(6, 9).T  # J_cᵀ
        return np.linalg.solve(system, tau)[:3]

    def single_state(
        self, prepared: TreeMotion, i: int
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``(q, q̇, q̈)`` of sample ``i`` (untimed)."""
        return _sample(prepared, i)

    def forces(self, prepared: TreeMotion) -> FloatArray:
        """Actuator forces ``f10`` (N, 3) of every prepared sample (Python loop)."""
        return _loop_over(self.single, prepared)


def available_peers(robot: prp3.Robot) -> list[MujocoPeer | PinocchioPeer]:
    """The peers whose engine imports (an engine that is not installed is skipped)."""
    peers: list[MujocoPeer | PinocchioPeer] = []
    for kind in (MujocoPeer, PinocchioPeer):
        try:
            peers.append(kind(robot))
        except ImportError:
            continue
    return peers
