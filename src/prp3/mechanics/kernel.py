"""The one numeric kernel: the paper's closed form, assembled once for every fast path.

:func:`solve` evaluates, for one platform state, the inverse geometry (eq. 10)
and the conditions of connectivity (eqs. 14, 17) of
:mod:`prp3.mechanics.joint_motion`, the wrench each body needs (eqs. 19, 20,
22) of :mod:`prp3.mechanics.wrenches` and the principle of virtual work with
the recursion of chain A and the virtual velocities (eqs. 15, 16, 21, 23–25)
of :mod:`prp3.mechanics.virtual_work`, plus the remaining joint reactions from
the balance of each piston and link 2; with ``μ`` terms of friction, the
implicit problem of :mod:`prp3.mechanics.implicit_friction`.  The stages use
only ``+ − × ÷`` and the functions of an :class:`~prp3.mechanics.ops.Ops`, so
the very same source runs on

* plain floats with :data:`~prp3.mechanics.ops.MATH` — one sample of the numpy engine;
* 1-D float64 arrays with :data:`~prp3.mechanics.ops.NUMPY` — the numpy engine
  (:func:`prp3.engines.select.run_numpy`: chunks of samples, memory bounded);
* machine code: :mod:`prp3.engines.numba` compiles the stages' very functions
  with numba (the default engine), so the stages it compiles
  (:func:`~prp3.mechanics.joint_motion.kernel_geometry`,
  :func:`~prp3.mechanics.joint_motion.kernel_kinematics`,
  :func:`~prp3.mechanics.wrenches.body_wrenches`,
  :func:`~prp3.mechanics.virtual_work.joint_forces`) keep to arithmetic, the
  :class:`~prp3.mechanics.ops.Ops` functions, tuples and named tuples — no
  lists, generators, ``isinstance`` or ``getattr`` by name (a test of each
  engine against the kernel on arrays fails otherwise);
* sympy expressions with :func:`~prp3.mechanics.ops.sympy_ops` —
  :func:`symbolic_solution`, from which the regressor and generated C code
  are derived.

It does not validate: callers check their input first (finite, not singular,
inside the stroke).  The independent references are :mod:`prp3.references.paper` (the
paper's 3×3 matrices as printed) and :func:`prp3.references.newton_euler.newton_euler`.

Examples
--------
>>> from prp3.mechanics.ops import MATH
>>> from prp3.mechanics.parameters import kernel_parameters
>>> from prp3.model.robot import Robot
>>> params = kernel_parameters(Robot())
>>> sol = solve(MATH, params, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
>>> [round(f, 4) for f in sol.f10]      # static central configuration
[31.8589, -8.4957, -23.3632]
"""

from __future__ import annotations

from typing import Any, NamedTuple

from prp3.mechanics.implicit_friction import solve_mu
from prp3.mechanics.joint_motion import (
    KernelKinematics,
    kernel_geometry,
    kernel_kinematics,
    rate_floor,
    rest_kinematics,
)
from prp3.mechanics.ops import Legs, Ops, Value, sympy_ops
from prp3.mechanics.parameters import KernelParameters, kernel_parameters, symbolic_parameters
from prp3.mechanics.virtual_work import joint_forces
from prp3.mechanics.wrenches import KernelFriction, body_wrenches, friction_forces
from prp3.model.robot import Robot

__all__ = [
    "STATE_SYMBOLS",
    "KernelSolution",
    "dynamics",
    "solve",
    "symbolic_solution",
]


class KernelSolution(NamedTuple):
    """Joint motion and joint forces of one state; every field ``(A, B, C)``.

    Reactions are ``None`` unless requested.  Units and signs as
    :class:`prp3.mechanics.forces.InverseDynamics`.
    """

    lambda10: Legs
    dlambda10: Legs
    ddlambda10: Legs
    lambda32: Legs
    dlambda32: Legs
    ddlambda32: Legs
    f10: Legs
    p10: Legs
    f21y: Legs
    f21z: Legs
    n10: Legs | None
    m10: Legs | None
    n32: Legs | None
    m32: Legs | None
    friction: KernelFriction | None = None
    iterations: Value | None = None
    near_lock: Value | None = None


def solve(
    ops: Ops,
    k: KernelParameters,
    x: Value,
    y: Value,
    phi: Value,
    dx: Value,
    dy: Value,
    dphi: Value,
    ddx: Value,
    ddy: Value,
    ddphi: Value,
    *,
    reactions: bool = True,
    load: tuple[Value, Value, Value] | None = None,
) -> KernelSolution:
    """Joint motion and joint forces of one state (or of a chunk of states).

    Parameters
    ----------
    ops : Ops
        :data:`MATH`, :data:`NUMPY` or :func:`sympy_ops`.
    k : KernelParameters
        From :func:`kernel_parameters` (or :func:`symbolic_parameters`).
    x, y, phi, dx, dy, dphi, ddx, ddy, ddphi : Value
        Pose ``(x, y, φ)`` of the platform and its first two derivatives
        (m, rad, s): floats, equal-length 1-D arrays, or sympy expressions.
    reactions : bool
        Also compute ``n10, m10, n32, m32``.
    load : (f_x, f_y, m_z) or None
        A time-varying wrench of the environment on the platform (force at
        ``G``, fixed frame, N; moment about ``z0``, N·m), added to ``k``'s
        constant load.

    Returns
    -------
    KernelSolution
        No validation: a singular pose divides by ``sin(φ − π/3) ≈ 0``.  With
        friction, :attr:`KernelSolution.friction` holds its forces; with
        ``μ`` terms (implicit, :func:`solve_mu`) :attr:`KernelSolution.iterations`
        the Newton iterations per sample, ``-1`` where no solution is reached
        continuously from ``μ = 0`` (a self-locking joint), and
        :attr:`KernelSolution.near_lock` whether each sample is near a lock
        (:data:`NEAR_LOCK_MU`).
    """
    geo = kernel_geometry(ops, k, x, y, phi)
    kin = kernel_kinematics(k, geo, dx, dy, dphi, ddx, ddy, ddphi)
    numeric = ops.name in ("math", "numpy")  # sympy: no friction in the generated code
    floor = rate_floor(ops, k, geo, x, y, dx, dy, dphi) if numeric and k.has_friction else None
    f10, f21y, f21z, rest, friction, iterations, near_lock = dynamics(
        ops, k, kin, (ddx, ddy, dphi, ddphi), reactions=reactions, load=load, floor=floor
    )
    v = kin.dlambda10
    p10 = (f10[0] * v[0], f10[1] * v[1], f10[2] * v[2])  # input power f10·λ̇10
    n10, m10, n32, m32 = rest if rest is not None else (None, None, None, None)
    return KernelSolution(
        lambda10=geo.lambda10,
        dlambda10=kin.dlambda10,
        ddlambda10=kin.ddlambda10,
        lambda32=geo.lambda32,
        dlambda32=kin.dlambda32,
        ddlambda32=kin.ddlambda32,
        f10=f10,
        p10=p10,
        f21y=f21y,
        f21z=f21z,
        n10=n10,
        m10=m10,
        n32=n32,
        m32=m32,
        friction=friction,
        iterations=iterations,
        near_lock=near_lock,
    )


def dynamics(
    ops: Ops,
    k: KernelParameters,
    kin: KernelKinematics,
    motion: tuple[Value, Value, Value, Value],
    *,
    reactions: bool = True,
    load: tuple[Value, Value, Value] | None = None,
    floor: Value | None = None,
) -> tuple[
    Legs, Legs, Legs, tuple[Legs, Legs, Legs, Legs] | None, KernelFriction | None, Value, Value
]:
    """The joint forces of a state of known kinematics (what :func:`solve` adds to them).

    ``motion = (ẍ, ÿ, φ̇, φ̈)``: the platform's rates that the wrenches read,
    in the order of :func:`body_wrenches`.  Returns ``(f10, f21y, f21z, (n10, m10, n32, m32) or None, friction,
    iterations, near_lock)``: body wrenches (:func:`body_wrenches`, with the
    load and the explicit friction), virtual work (:func:`joint_forces`) and,
    with ``μ`` terms, the implicit friction by :func:`solve_mu`
    (``iterations`` and ``near_lock`` ``None`` without).  ``floor``
    (:func:`rate_floor`): the joint rates friction reads are those of
    :func:`rest_kinematics` (round-off rates are zero for ``s(v)``).
    """
    dphi = motion[2]
    rates = kin if floor is None else rest_kinematics(kin, floor)
    friction = friction_forces(ops, k, rates, dphi)
    wrenches = body_wrenches(k, kin, *motion, load=load, friction=friction)
    implicit = k.has_mu
    f10, f21y, f21z, rest = joint_forces(k, kin, wrenches, reactions or implicit)
    iterations: Value | None = None
    near_lock: Value | None = None
    if implicit:
        if ops.name not in ("math", "numpy"):
            raise ValueError("the μ terms of friction are implicit: no closed form for sympy")
        assert rest is not None and friction is not None
        friction, iterations, near_lock = solve_mu(
            ops, k, rates, friction, (rest[0], f21y, f21z, rest[2]), dphi
        )
        wrenches = body_wrenches(k, kin, *motion, load=load, friction=friction)
        f10, f21y, f21z, rest = joint_forces(k, kin, wrenches, reactions)
    return f10, f21y, f21z, rest, friction, iterations, near_lock


#: Names of the state symbols of :func:`symbolic_solution`.
STATE_SYMBOLS: tuple[str, ...] = ("x", "y", "phi", "dx", "dy", "dphi", "ddx", "ddy", "ddphi")


def symbolic_solution(
    parameters: KernelParameters | Robot | None = None, reactions: bool = True
) -> tuple[tuple[Any, ...], KernelSolution]:
    """The kernel evaluated on sympy symbols: the same source as the numeric paths.

    Parameters
    ----------
    parameters : KernelParameters, Robot or None
        Numbers of a robot (its constants appear as floats), symbols of your
        own, or ``None`` for :func:`symbolic_parameters`.

    Returns
    -------
    (symbols, KernelSolution)
        The nine state symbols ``x, y, phi, dx, dy, dphi, ddx, ddy, ddphi``
        (real) and the solution as sympy expressions of them.

    Examples
    --------
    >>> import sympy
    >>> state, sol = symbolic_solution(Robot())
    >>> at_rest = dict.fromkeys(state, 0)
    >>> round(float(sol.f10[0].subs(at_rest)), 4)
    31.8589
    """
    import sympy

    if parameters is None:
        parameters = symbolic_parameters()
    elif isinstance(parameters, Robot):
        parameters = kernel_parameters(parameters)
    state = sympy.symbols(STATE_SYMBOLS, real=True)
    return tuple(state), solve(sympy_ops(), parameters, *state, reactions=reactions)
