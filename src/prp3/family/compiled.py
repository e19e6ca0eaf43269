"""The family's fast route compiled by numba: one loop over the samples (docs/family.md §5–§7).

The same mechanics as :mod:`prp3.family.mechanics` (the ``"numpy"`` engine),
per sample in scalar code that numba compiles to machine code (``cache=True``:
compiled once per machine, then loaded from the cache):

1. the path of §5 from each leg's home pose through the samples
   (:mod:`prp3.family.compiled_path`: its closed forms the trace of
   :func:`~prp3.family.sample_mechanics.path_candidates`, in the same generated
   module): the joint values ``q`` and the measures ``μ_leg``, ``μ_par`` at the
   samples, checked at every point;
2. at the samples, by the kernel generated from the one source on ``Ops``
   (:mod:`prp3.family.sample_mechanics`: :func:`~prp3.family.sample_mechanics.chain_of`
   and :func:`~prp3.family.sample_mechanics.sample_dynamics`, traced with the
   robot's numbers as inputs by :mod:`prp3.family.compiled_kernel`, one
   compiled function per architecture × actuation): the chain frames, ``J``,
   ``K = J⁻¹``, ``q̇ = K·t``, ``q̈ = K·(ṫ − J̇·q̇)``;
3. in the same kernel, the wrench each body needs, the actuator efforts by virtual work
   ``Σ_L τ_L·K_L[a, :] = w_platform + Σ_L K_Lᵀ·B_L`` and every joint force
   ``W_3 = K_Lᵀ·(τ_L·e_a − B_L)``, ``W_2 = N_2 + W_3``, ``W_1 = N_1 + W_2``.

The kernel never raises and never validates: it reports the first refusal
(pose out of range, unreachable, singular or crossed, results not finite) as
a status, and :func:`compiled_dynamics` raises from it exactly the error the
numpy engine raises (same class, message and fields).  The inputs are
checked once, at the public entry :func:`prp3.family.family_inverse_dynamics`.
Every output lies in one buffer allocated by numpy, the arrays of the same
size per sample side by side, so that the results are views taken by one
reshape per size.

>>> from prp3.model.motion import paper_motion
>>> from prp3.family.model import FamilyRobot
>>> from prp3.family.mechanics import family_kinematics, fast_dynamics
>>> robot, motion = FamilyRobot.default("3-RRR"), paper_motion("vertical", 5)
>>> compiled = compiled_dynamics(robot, motion)
>>> reference = fast_dynamics(family_kinematics(robot, motion))
>>> bool(np.allclose(compiled.tau, reference.tau, rtol=1e-12, atol=0))
True
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from prp3.errors import Prp3Error
from prp3.family.chain import ChainFrames
from prp3.family.compiled_kernel import (
    NOT_FINITE_DYN,
    NOT_FINITE_KIN,
    constants,
    structure_module,
)
from prp3.family.compiled_path import (
    STATUS_NOT_FINITE_DYN,
    STATUS_NOT_FINITE_KIN,
    STATUS_OK,
    STATUS_OUT_OF_RANGE,
    STATUS_SINGULAR_LEG,
    STATUS_SINGULAR_PAR,
    STATUS_UNREACHABLE,
    numba,
    pack,
)
from prp3.family.mechanics import (
    FamilyKinematics,
    FamilySolution,
    on_the_way,
    pose_bound_error,
    singular_error,
    unreachable_error,
)
from prp3.family.model import FamilyRobot
from prp3.model.motion import Motion
from prp3.validation import LEGS, require_finite

try:  # the threads of the 3-PRP's numba engine: its block, threshold and threading layer
    from prp3.engines.numba import BLOCK, PARALLEL_MIN_SAMPLES, parallel_layer
except ImportError:  # pragma: no cover - the numba extra is not installed: one thread
    BLOCK, PARALLEL_MIN_SAMPLES = 1, 0

    def parallel_layer() -> str | None:
        return None


__all__ = ["compiled_dynamics"]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

# ------------------------------------------------------------------ the buffer
#: The outputs of one sample by their number of doubles, in the buffer's order: first
#: those of the motion's batch shape (``()`` for one sample), ``q, dq, ddq, moment``
#: (9 each), ``mu_leg, tau, power`` (3), ``force`` (18), ``mu_par`` (1); then those of
#: shape ``(N, ...)`` always, the frames ``joint_angle, angle, end`` (9),
#: ``joint_origin, origin, axis`` (18) and ``jacobian, jacobian_inverse`` (27).
_GROUPS = ((9, 4), (3, 3), (18, 1), (1, 1), (9, 3), (18, 3), (27, 2))
_WIDTH = sum(size * count for size, count in _GROUPS)
#: After the outputs: the kernel's status (4, as doubles) and its ``info`` (4).
_TAIL = 8


def family_kernel(
    robot: FamilyRobot, pose: FloatArray, velocity: FloatArray, acceleration: FloatArray,
    buffer: FloatArray, threads: bool,
) -> int:  # fmt: skip
    """Every output at the samples into ``buffer``; the status.

    The structure's generated module (:func:`prp3.family.compiled_kernel.structure_module`)
    runs step 1, the path, by ``path`` (sequential; :mod:`prp3.family.compiled_path`),
    steps 2 and 3 by ``samples``, or ``samples_parallel`` on every thread when ``threads``.
    """
    ints, par = pack(robot)
    module = structure_module(robot.types, robot.actuated)
    c = constants(robot)
    status = int(module.path(ints, par, c, pose, buffer, _WIDTH))
    if status != STATUS_OK:
        return status
    run = module.samples_parallel if threads else module.samples
    n = pose.shape[0]
    flags = run(c, pose, velocity, acceleration, buffer, n, 0, n)
    if flags & NOT_FINITE_KIN:
        return STATUS_NOT_FINITE_KIN
    return STATUS_NOT_FINITE_DYN if flags & NOT_FINITE_DYN else STATUS_OK


# ------------------------------------------------------------------ the engine
def compiled_dynamics(robot: FamilyRobot, motion: Motion) -> FamilySolution:
    """The fast route by the compiled kernel: the same :class:`FamilySolution` as the numpy engine.

    ``robot`` and ``motion`` are taken as checked (by the public entry).  A
    refusal reported by the kernel is raised as the numpy engine raises it:
    :class:`~prp3.errors.TrajectoryError` (pose out of range, results not
    finite), :class:`~prp3.errors.UnreachablePoseError`,
    :class:`~prp3.errors.SingularPoseError` (the same message and fields).
    """
    if numba is None:  # pragma: no cover
        raise Prp3Error(
            'engine="numba" needs numba, which is not installed: pip install "prp3[numba]" '
            'or use engine="numpy"'
        )
    shape = motion.t.shape
    pose = motion.pose.reshape(-1, 3)
    n = pose.shape[0]
    buffer = np.empty(_WIDTH * n + _TAIL)  # allocated by numpy: huge pages for a large N
    status = family_kernel(
        robot, _c(pose), _c(motion.velocity.reshape(-1, 3)),
        _c(motion.acceleration.reshape(-1, 3)), buffer, uses_threads(n),
    )  # fmt: skip
    # the views by integer indexing (the cheapest views numpy makes)
    ranked = buffer[: 36 * n].reshape(4, *shape, 3, 3)
    q, dq, ddq, moment = ranked[0], ranked[1], ranked[2], ranked[3]
    at = 36 * n
    legs = buffer[at : at + 9 * n].reshape(3, *shape, 3)
    mu_leg, tau, power = legs[0], legs[1], legs[2]
    at += 9 * n
    force = buffer[at : at + 18 * n].reshape(*shape, 3, 3, 2)
    at += 18 * n
    mu_par = buffer[at : at + n].reshape(shape)
    at += n
    angles = buffer[at : at + 27 * n].reshape(3, n, 3, 3)
    at += 27 * n
    points = buffer[at : at + 54 * n].reshape(3, n, 3, 3, 2)
    at += 54 * n
    jacobians = buffer[at : at + 54 * n].reshape(2, n, 3, 3, 3)
    at += 54 * n
    if status != STATUS_OK:
        t = motion.t.reshape(-1)
        batch = [a.reshape(n, *a.shape[len(shape) :]) for a in (dq, ddq, tau, power, force, moment)]
        _refuse(robot, buffer[at:], pose, t, *batch)
    end = angles[2]
    frames = ChainFrames(
        points[0], angles[0], points[1], angles[1], points[2], end[:, :, :2], end[:, :, 2]
    )
    kin = FamilyKinematics(
        robot, motion, q, dq, ddq, mu_leg, mu_par, frames, jacobians[0], jacobians[1]
    )  # fmt: skip
    return FamilySolution(kin, q, dq, ddq, tau, power, force, moment, "fast")


def uses_threads(samples: int) -> bool:
    """Whether a batch of ``samples`` runs its steps 2 and 3 on every thread.

    As the 3-PRP's batches (:func:`prp3.engines.numba.batch_loops`): from
    :data:`~prp3.engines.numba.PARALLEL_MIN_SAMPLES` samples when numba's
    threading layer is thread-safe (:func:`~prp3.engines.numba.parallel_layer`);
    a function of ``samples`` and of what the process offers, never of earlier
    calls; both give the same numbers.
    """
    return samples >= PARALLEL_MIN_SAMPLES and parallel_layer() is not None


def _c(values: FloatArray) -> FloatArray:
    """``values`` as the kernel's one compiled signature takes it: C-contiguous, read-only."""
    flags = values.flags
    if flags.c_contiguous and not flags.writeable:
        return values
    out = np.ascontiguousarray(values, dtype=np.float64)
    if out is values:
        out = out.copy()
    out.flags.writeable = False
    return out


def _refuse(
    robot: FamilyRobot,
    tail: FloatArray,
    pose: FloatArray,
    t: FloatArray,
    dq: FloatArray,
    ddq: FloatArray,
    tau: FloatArray,
    power: FloatArray,
    force: FloatArray,
    moment: FloatArray,
) -> None:
    """Raise the numpy engine's error for the kernel's status (docs/family.md §5, §6)."""
    code, k, leg, exact = (int(v) for v in tail[:4])
    info = tail[4:8]
    if code == STATUS_OUT_OF_RANGE:
        raise pose_bound_error(robot, pose, t, k)
    if code == STATUS_UNREACHABLE:
        note = "" if exact else on_the_way(t, k)
        raise unreachable_error(robot, leg, info, note, k, t)
    if code in (STATUS_SINGULAR_LEG, STATUS_SINGULAR_PAR):
        home_leg, home_par = robot.home_measures
        name, at_home = (
            (f"mu_leg of leg {LEGS[leg]}", home_leg[leg]) if code == STATUS_SINGULAR_LEG
            else ("mu_par", home_par)
        )  # fmt: skip
        raise singular_error(
            name, float(info[3]), info, pose, t, k,
            LEGS[leg] if code == STATUS_SINGULAR_LEG else None, at_home,
        )  # fmt: skip
    require_finite({"dq": dq, "ddq": ddq}, (t.size,), "motion", t)
    finite = {"tau": tau, "p": power, "force": force, "moment": moment}  # p = τ·q̇a: may overflow
    require_finite(finite, (t.size,), "motion", t)
