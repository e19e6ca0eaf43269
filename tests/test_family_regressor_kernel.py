"""The family regressor from the one kernel (prp3.family.regressor_kernel; docs/identification.md).

``Y = ∂τ/∂π`` is generated from :func:`prp3.family.sample_mechanics.sample_dynamics` by
forward differentiation of its traced operations.  It is held against three
independent computations:

* the inverse dynamics' fast route (:func:`prp3.family.mechanics.fast_dynamics`, a
  numpy model of its own): ``Y·π + τ_known = τ`` on random robots of the seven
  architectures and random motions;
* the unit-parameter columns the regressor was built from before (one fast-route
  run per unit robot, the ``h`` columns by difference), column by column;
* sympy: the same kernel source on sympy symbols written in ``π`` directly (the
  file's ``m, c, I`` as functions of ``π``), differentiated by sympy — the chain
  rule of the module, and the linearity it rests on, checked at another point.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray

from prp3.apps.family_regressor import (
    FAMILY_PARAMETERS,
    family_known_forces,
    family_random_motion,
    family_regressor,
    family_standard_parameters,
    unit_efforts,
)
from prp3.errors import SingularPoseError, UnreachablePoseError
from prp3.family import Body, FamilyRobot, PlatformBody
from prp3.family.chain import SIGMA
from prp3.family.mechanics import FamilyKinematics, family_kinematics, fast_dynamics
from prp3.family.regressor_kernel import (
    COLUMNS,
    DUAL,
    Dual,
    regressor_batch,
    regressor_function,
)
from prp3.family.sample_mechanics import Design, Inertia, chain_of, sample_dynamics
from prp3.mechanics.ops import MATH, sympy_ops
from prp3.model.motion import Motion
from prp3.model.parameters import Load, Payload
from strategies import FAMILY_ALLOWED, family_designs, family_motions

FloatArray = NDArray[np.float64]


def _relative(a: FloatArray, b: FloatArray) -> float:
    return float(np.abs(a - b).max() / (1.0 + np.abs(b).max()))


# ------------------------------------------------------------------ the old columns, as reference
def _massless(robot: FamilyRobot) -> FamilyRobot:
    return replace(
        robot,
        link1=Body(0.0, (0.0, 0.0), 0.0, name="link1"),
        link2=Body(0.0, (0.0, 0.0), 0.0, name="link2"),
        platform=PlatformBody(0.0, 0.0),
        payload=Payload(),
        load=Load(),
    )


def _fast_tau(kin: FamilyKinematics, robot: FamilyRobot) -> FloatArray:
    return np.asarray(fast_dynamics(replace(kin, robot=robot)).tau).reshape(-1, 3)


def _unit_columns(kin: FamilyKinematics) -> FloatArray:
    """The columns by the fast route on unit robots (the regressor's former construction)."""
    zero = _massless(kin.robot)

    def body(name: str, mass: float, com: tuple[float, float], inertia: float) -> FloatArray:
        if name == "platform":
            unit = (
                replace(zero, platform=PlatformBody(mass, inertia))
                if com == (0.0, 0.0)
                else replace(zero, payload=Payload(mass, com, inertia))
            )
        else:
            unit = replace(zero, **{name: Body(mass, com, inertia, name=name)})
        return _fast_tau(kin, unit)

    columns = []
    for name in FAMILY_PARAMETERS:
        part, kind = name.split("_", 1)
        if kind == "mass":
            columns.append(body(part, 1.0, (0.0, 0.0), 0.0))
        elif kind == "inertia":
            columns.append(body(part, 0.0, (0.0, 0.0), 1.0))
        else:
            com = (1.0, 0.0) if kind == "moment_x" else (0.0, 1.0)
            columns.append(
                body(part, 1.0, com, 0.0)
                - body(part, 1.0, (0.0, 0.0), 0.0)
                - body(part, 0.0, (0.0, 0.0), 1.0)
            )
    return np.stack(columns, axis=-1)


def _kinematics(robot: FamilyRobot, motion: Motion) -> FamilyKinematics:
    try:
        return family_kinematics(robot, motion)
    except (SingularPoseError, UnreachablePoseError):
        assume(False)
        raise


# ------------------------------------------------------------------ against the fast route
@given(data=st.data())
def test_regressor_reproduces_the_fast_route(data: st.DataObject) -> None:
    """``Y·π + τ_known`` is the fast route's ``τ`` to 1e-12 relative, random robots and motions."""
    robot = data.draw(family_designs())
    motion = data.draw(family_motions(robot.home_poses.mean(axis=0)))
    kin = _kinematics(robot, motion)
    tau = _fast_tau(kin, robot)
    Y = family_regressor(robot, motion)
    predicted = Y.tau @ family_standard_parameters(robot) + family_known_forces(robot, motion)
    assert _relative(predicted, tau) < 1e-12


@given(data=st.data())
def test_columns_are_the_unit_robots(data: st.DataObject) -> None:
    """The generated columns equal the unit-parameter columns of the fast route to 1e-12."""
    robot = data.draw(family_designs())
    motion = data.draw(family_motions(robot.home_poses.mean(axis=0)))
    kin = _kinematics(robot, motion)
    old = _unit_columns(kin)
    new = unit_efforts(kin, FAMILY_PARAMETERS)
    for k in range(len(FAMILY_PARAMETERS)):
        assert _relative(new[..., k], old[..., k]) < 1e-12, FAMILY_PARAMETERS[k]


@pytest.mark.parametrize(("arch", "act"), FAMILY_ALLOWED)
def test_every_structure_with_a_load(arch: str, act: int) -> None:
    """Each architecture × actuation: the known part is the fast route's massless robot with the load."""
    robot = replace(
        FamilyRobot.default(arch, act), load=Load((3.0, -2.0), 0.4), gravity=(0.5, -9.81)
    )
    motion = family_random_motion(robot, 9, 3)
    kin = family_kinematics(robot, motion)
    loaded = replace(_massless(robot), load=robot.load)
    known = family_known_forces(robot, motion)
    assert np.abs(known).max() > 0.1
    assert _relative(known, _fast_tau(kin, loaded)) < 1e-12
    assert _relative(unit_efforts(kin, FAMILY_PARAMETERS), _unit_columns(kin)) < 1e-12


def test_one_function_per_structure() -> None:
    """The generated function is built once per architecture × actuated joint."""
    a = regressor_function("RPR", 2)
    assert regressor_function("RPR", 2) is a
    assert regressor_function("RPR", 1) is not a
    assert "def regressor_RPR" in (a.__doc__ or "")


def test_chunks_agree() -> None:
    """Samples beyond one chunk give the same rows as one sample at a time."""
    import prp3.family.regressor_kernel as kernel

    robot = FamilyRobot.default("3-RRR")
    motion = family_random_motion(robot, 7, 5)
    kin = family_kinematics(robot, motion)
    state = np.concatenate([motion.pose, motion.velocity, motion.acceleration], axis=1)
    q = kin.q.reshape(-1, 9)
    whole = regressor_batch(robot, state, q)
    chunk = kernel.CHUNK
    try:
        kernel.CHUNK = 3  # 3 + 3 + 1 samples
        parts = regressor_batch(robot, state, q)
    finally:
        kernel.CHUNK = chunk
    for a, b in zip(whole, parts, strict=True):
        np.testing.assert_array_equal(a, b)


# ------------------------------------------------------------------ against sympy, in π directly
def _sympy_columns(robot: FamilyRobot, kin: FamilyKinematics, sample: int) -> FloatArray:
    """``∂τ/∂π`` of one sample by sympy, the kernel's inputs written as functions of ``π``.

    Per link ``m = m_k``, ``c = h_k/m_k``, ``I = J_k − |h_k|²/m_k``; the platform a
    payload of mass ``s`` with ``c = h3/s`` and the rest of ``m3``, ``J3`` on
    the platform.  The derivatives are taken at a point ``π₀`` other than the
    generated code's unit point (a real robot's π, every mass nonzero).
    """
    import sympy

    ops = sympy_ops()
    symbols = sympy.symbols(" ".join(COLUMNS), real=True)
    p = dict(zip(COLUMNS, symbols, strict=True))
    links = []
    for k in (1, 2):
        m, hx, hy, j = (p[f"link{k}_{n}"] for n in ("mass", "moment_x", "moment_y", "inertia"))
        links.append((m, (hx / m, hy / m), j - (hx * hx + hy * hy) / m))
    s = sympy.Rational(13, 10)
    hx, hy = p["platform_moment_x"], p["platform_moment_y"]
    inertia = Inertia(
        links=tuple(links),
        platform=(p["platform_mass"] - s, p["platform_inertia"] - (hx * hx + hy * hy) / s),
        payload=(s, (hx / s, hy / s), 0),
        load=(0.0, 0.0, 0.0),
        gravity=robot.gravity,
        actuated=robot.actuated - 1,
    )
    design = Design.of(robot)
    q = kin.q.reshape(-1, 9)[sample].tolist()
    legs = []
    for j in range(3):
        _, origins, rotations = chain_of(MATH, design, float(SIGMA[j]), q[3 * j : 3 * j + 3])
        legs.append((origins, rotations))
    x, y, phi = kin.motion.pose[sample]
    state = (x, y, np.cos(phi), np.sin(phi), *kin.motion.velocity[sample],
             *kin.motion.acceleration[sample])  # fmt: skip
    tau = sample_dynamics(ops, robot.types, inertia, design.scale, state, legs)[1:4]
    point = dict(zip(symbols, map(sympy.Float, (0.7, 0.05, -0.02, 0.01, 1.1, -0.03, 0.04, 0.02,
                               2.5, 0.1, 0.05, 0.03)), strict=True))  # fmt: skip
    return np.array([[float(sympy.diff(t, v).xreplace(point)) for v in symbols] for t in tau])


@settings(max_examples=8, deadline=None)
@given(data=st.data())
def test_columns_are_sympy_derivatives(data: st.DataObject) -> None:
    """The generated ``Y`` is sympy's ``∂τ/∂π`` of the kernel written in ``π`` (1e-12)."""
    robot = data.draw(family_designs())
    motion = data.draw(family_motions(robot.home_poses.mean(axis=0), samples=2))
    kin = _kinematics(robot, motion)
    new = unit_efforts(kin, COLUMNS)
    for sample in (1,):
        expected = _sympy_columns(robot, kin, sample)
        assert _relative(new[sample], expected) < 1e-12


# ------------------------------------------------------------------ the dual numbers
@given(
    a=st.floats(0.1, 3.0), b=st.floats(-3.0, 3.0), da=st.floats(-2.0, 2.0),
    db=st.floats(-2.0, 2.0),
)  # fmt: skip
def test_dual_rules(a: float, b: float, da: float, db: float) -> None:
    """Each rule of :class:`Dual` on floats against a central difference of the same formula."""
    x, y = Dual(a, {0: da}), Dual(b, {0: db})

    def f(u: object, v: object, ops: object) -> object:
        return (
            (u * v - v / u + 2.0 - u) / (1.0 + u * u)  # type: ignore[operator]
            + ops.sqrt(u) * ops.cos(v)
            - ops.sin(u * v)
            + ops.tanh(v)
            - 3.0 / u  # type: ignore[attr-defined]
            + (-v) * 0.5
            - (1.0 - v)  # type: ignore[operator]
        )

    out = f(x, y, DUAL)
    assert isinstance(out, Dual)
    e = 1e-6
    slope = (f(a + e * da, b + e * db, MATH) - f(a - e * da, b - e * db, MATH)) / (2 * e)  # type: ignore[operator]
    assert out.value == pytest.approx(f(a, b, MATH), rel=1e-14, abs=1e-14)
    assert out.d.get(0, 0.0) == pytest.approx(slope, rel=1e-6, abs=1e-6)


def test_dual_refuses_a_derivative_through_abs() -> None:
    with pytest.raises(ValueError, match="abs/sign/atan2"):
        DUAL.abs(Dual(1.0, {0: 1.0}))
    assert DUAL.abs(Dual(-2.0)).value == 2.0
