"""The mechanics of one sample of a family robot on scalars, for the generated C (docs/family_export.md).

Written once, in the vector form of the chain (each frame's rotation as
``(cos, sin)``, so no angle is ever needed), on the operations ``ops`` of
:class:`prp3.mechanics.ops.Ops`: run on the tracer of :mod:`prp3.engines.trace` it becomes
the C of :mod:`prp3.family.codegen`, on Python floats it is
:func:`prp3.family.codegen.python_sample`.  Two stages:

* :func:`leg_candidates`: per leg, in the leg's frame, the closed-form closure
  solutions of :mod:`prp3.family.legs` (one for PRP, PPR, RPP; two for RRR,
  RPR, PRR, RRP), each as its frame rotations ``R_{F_k}`` and P values, the
  joint origins by the chain of docs/family.md §2, and ``μ_leg``;
* :func:`sample_dynamics`: the dynamics of :mod:`prp3.family.mechanics` on the
  chosen configurations: ``q̇ = J⁻¹·t``, ``q̈ = J⁻¹·(ṫ − J̇·q̇)``, the body
  wrenches, virtual work for ``tau``, every joint wrench, and ``μ_par``.

>>> from prp3.mechanics.ops import MATH
>>> from prp3.family.model import FamilyRobot
>>> design = Design.of(FamilyRobot.default("3-RRR"))
>>> len(list(leg_candidates(MATH, design, (0.0, 0.0), (1.0, 0.0))))
2
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from prp3.family.model import FamilyRobot
from prp3.mechanics.ops import Ops

__all__ = ["leg_candidates", "sample_dynamics"]

Pair = tuple[Any, Any]


# ------------------------------------------------------------------ planar helpers
def _add(a: Pair, b: Pair) -> Pair:
    return (a[0] + b[0], a[1] + b[1])


def _sub(a: Pair, b: Pair) -> Pair:
    return (a[0] - b[0], a[1] - b[1])


def _scale(k: Any, a: Pair) -> Pair:
    return (k * a[0], k * a[1])


def _dot(a: Pair, b: Pair) -> Any:
    return a[0] * b[0] + a[1] * b[1]


def _cross(a: Pair, b: Pair) -> Any:
    return a[0] * b[1] - a[1] * b[0]


def _perp(a: Pair) -> Pair:
    return (-a[1], a[0])


def turn(r: Pair, v: Pair) -> Pair:
    """``Rot·v`` for a rotation given as ``(cos, sin)`` (a complex product)."""
    return (r[0] * v[0] - r[1] * v[1], r[1] * v[0] + r[0] * v[1])


def _unit(ops: Ops, angle: Any) -> Pair:
    """``(cos, sin)`` of a design angle (traced when the design is: one kernel for every robot)."""
    return (ops.cos(angle), ops.sin(angle))


def _over(v: Pair, c: tuple[float, float]) -> Pair:
    """The rotation taking the constant ``c`` to ``v`` (``|v| = |c|``): ``v·conj(c)/|c|²``."""
    n = c[0] * c[0] + c[1] * c[1]
    return ((v[0] * c[0] + v[1] * c[1]) / n, (v[1] * c[0] - v[0] * c[1]) / n)


# ------------------------------------------------------------------ stage 1: geometry
#: The numbers of a traced design (:meth:`Design.values`).
DESIGN_VALUES = 13


@dataclass(frozen=True)
class Design:
    """Leg A's constants as plain floats."""

    types: str
    c: tuple[tuple[float, float], ...]  # c_1, c_2, c_3, c_P
    gamma: tuple[float, ...]  # γ_1, γ_2, γ_3, γ_P
    scale: float

    @classmethod
    def of(cls, robot: FamilyRobot) -> Design:
        p = robot.leg.placements
        return cls(
            types=robot.types,
            c=tuple((float(p[k, 0]), float(p[k, 1])) for k in range(4)),
            gamma=tuple(float(p[k, 2]) for k in range(4)),
            scale=robot.leg.scale,
        )

    def values(self) -> tuple[float, ...]:
        """The 13 numbers ``c_1 … c_P`` (8), ``γ_1 … γ_P`` (4), ``scale``: the inputs of a traced design."""
        return (*(v for pair in self.c for v in pair), *self.gamma, self.scale)

    @classmethod
    def from_values(cls, types: str, values: Sequence[Any]) -> Design:
        """The design of :meth:`values` (floats or traced values) for the joints ``types``."""
        c = tuple((values[2 * k], values[2 * k + 1]) for k in range(4))
        return cls(types=types, c=c, gamma=tuple(values[8:12]), scale=values[12])


def _chain(
    ops: Ops, design: Design, rotations: Sequence[Pair], slides: dict[int, Any]
) -> list[Pair]:
    """Joint origins ``O_k`` from the frame rotations ``R_{F_k}`` and the P values (§2)."""
    prev_r: Pair = (1.0, 0.0)
    prev_o: Pair = (0.0, 0.0)
    origins = []
    for k in range(3):
        origin = _add(prev_o, turn(prev_r, design.c[k]))
        if design.types[k] == "P":
            origin = _add(origin, _scale(slides[k], turn(prev_r, _unit(ops, design.gamma[k]))))
        origins.append(origin)
        prev_r, prev_o = rotations[k], origin
    return origins


def _measure(design: Design, g: Pair, origins: Sequence[Pair], rotations: Sequence[Pair]) -> Any:
    """``μ_leg = det Ĵ``: columns ``(perp(G − O_k)/ℓ, 1)`` (R), ``(u_k, 0)`` (P)."""
    cols = _scaled_columns(design, g, origins, rotations)
    return _det(cols)


def _scaled_columns(
    design: Design, g: Pair, origins: Sequence[Pair], rotations: Sequence[Pair]
) -> list[tuple[Any, Any, Any]]:
    cols = []
    for k in range(3):
        if design.types[k] == "R":
            v = _perp(_sub(g, origins[k]))
            cols.append((v[0] / design.scale, v[1] / design.scale, 1.0))
        else:
            u = rotations[k]  # a P joint's frame keeps the joint frame's angle: u_k
            cols.append((u[0], u[1], 0.0))
    return cols


def _det(cols: Sequence[tuple[Any, Any, Any]]) -> Any:
    """Determinant of the matrix with columns ``cols``."""
    (a, d, g), (b, e, h), (c, f, i) = cols
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)


def _roots(ops: Ops, b: Any, c: Any) -> tuple[Any, Any]:
    """``−b ± √(b² − c)`` (the order of :mod:`prp3.family.legs`)."""
    root = ops.sqrt(b * b - c)
    return (-b + root, -b - root)


def leg_candidates(
    ops: Ops, design: Design, g: Pair, rphi: Pair
) -> list[tuple[list[Pair], list[Pair], Any]]:
    """The closure solutions of a leg in its own frame: ``(origins, rotations, μ_leg)`` each.

    ``g`` is ``G`` in the leg frame, ``rphi = (cos φ, sin φ)``; the closed forms
    are those of :mod:`prp3.family.legs`, each frame's rotation obtained from
    the vector it turns (``R_{F_1} = (O_2 − O_1)·conj(c_2)/|c_2|²`` for an R-R
    pair, ...) instead of from angles.  :func:`leg_solutions` with the slides.
    """
    return [(o, r, mu) for o, r, _, mu in leg_solutions(ops, design, g, rphi)]


def leg_solutions(
    ops: Ops, design: Design, g: Pair, rphi: Pair
) -> list[tuple[list[Pair], list[Pair], dict[int, Any], Any]]:
    """:func:`leg_candidates` with each solution's P values: ``(origins, rotations, slides, μ_leg)``.

    ``slides`` maps each P joint (0-based) to its value (m).
    """
    types, c, gamma = design.types, design.c, design.gamma
    r3 = turn(rphi, _unit(ops, -gamma[3]))  # R_{F_3}: the attachment frame's angle is φ
    wrist = _sub(g, turn(r3, c[3]))  # O_3 = origin of F_3
    solutions: list[tuple[list[Pair], dict[int, Any]]] = []
    if types.count("R") == 1:
        r = types.index("R")
        rotations: list[Pair] = []
        for k in range(3):
            if k < r:
                rotations.append(_unit(ops, sum(gamma[: k + 1])))
            else:
                rotations.append(turn(r3, _unit(ops, -sum(gamma[k + 1 : 3]))))
        a, b = (k for k in range(3) if types[k] == "P")
        zero = _chain(ops, design, rotations, {a: 0.0, b: 0.0})
        rhs = _sub(g, _add(zero[2], turn(r3, c[3])))
        ua, ub = rotations[a], rotations[b]
        det = _cross(ua, ub)
        solutions.append((rotations, {a: _cross(rhs, ub) / det, b: _cross(ua, rhs) / det}))
    elif types == "RRR":
        o1 = c[0]
        d = _sub(wrist, o1)
        dd = _dot(d, d)
        r2s, r3s = _dot(c[1], c[1]), _dot(c[2], c[2])
        along = (dd + (r2s - r3s)) / (2.0 * dd)
        height = ops.sqrt(r2s / dd - along * along)
        for sign in (1.0, -1.0):
            o2 = _add(_add(o1, _scale(along, d)), _scale(sign * height, _perp(d)))
            solutions.append(([_over(_sub(o2, o1), c[1]), _over(_sub(wrist, o2), c[2]), r3], {}))
    elif types == "RPR":
        d = _sub(wrist, c[0])
        v = _unit(ops, gamma[1])
        w0 = _add(c[1], turn(v, c[2]))
        b = _dot(w0, v)
        for q2 in _roots(ops, b, _dot(w0, w0) - _dot(d, d)):
            w = _add(w0, _scale(q2, v))
            n = _dot(w, w)
            r1 = ((d[0] * w[0] + d[1] * w[1]) / n, (d[1] * w[0] - d[0] * w[1]) / n)
            solutions.append(([r1, turn(r1, v), r3], {1: q2}))
    elif types == "PRR":
        u1 = _unit(ops, gamma[0])
        d = _sub(_sub(wrist, c[0]), turn(u1, c[1]))
        b = -_dot(d, u1)
        for q1 in _roots(ops, b, _dot(d, d) - _dot(c[2], c[2])):
            solutions.append(([u1, _over(_sub(d, _scale(q1, u1)), c[2]), r3], {0: q1}))
    elif types == "RRP":
        r2 = turn(r3, _unit(ops, -gamma[2]))
        reach = _sub(_sub(_sub(g, c[0]), turn(r2, c[2])), turn(r3, c[3]))
        b = -_dot(reach, r3)
        for q3 in _roots(ops, b, _dot(reach, reach) - _dot(c[1], c[1])):
            solutions.append(([_over(_sub(reach, _scale(q3, r3)), c[1]), r2, r3], {2: q3}))
    else:  # pragma: no cover - the model admits the seven architectures only
        raise AssertionError(types)
    out = []
    for rotations, slides in solutions:
        origins = _chain(ops, design, rotations, slides)
        out.append((origins, list(rotations), slides, _measure(design, g, origins, rotations)))
    return out


# ------------------------------------------------------------------ stage 3: dynamics
@dataclass(frozen=True)
class Inertia:
    """The robot's inertial constants as plain floats."""

    links: tuple[tuple[float, tuple[float, float], float], ...]  # (mass, com, I) of link 1, 2
    platform: tuple[float, float]
    payload: tuple[float, tuple[float, float], float]
    load: tuple[float, float, float]
    gravity: tuple[float, float]
    actuated: int

    @classmethod
    def of(cls, robot: FamilyRobot) -> Inertia:
        return cls(
            links=tuple((b.mass, b.com, b.inertia) for b in (robot.link1, robot.link2)),
            platform=(robot.platform.mass, robot.platform.inertia),
            payload=(robot.payload.mass, robot.payload.com, robot.payload.inertia),
            load=(*robot.load.force, robot.load.moment),
            gravity=robot.gravity,
            actuated=robot.actuated - 1,
        )

    def values(self) -> tuple[float, ...]:
        """The 19 numbers: links (mass, com, I) ×2 (8), platform (2), payload (4), load (3), gravity (2)."""
        links = [v for mass, com, izz in self.links for v in (mass, *com, izz)]
        mass, com, izz = self.payload
        return (*links, *self.platform, mass, *com, izz, *self.load, *self.gravity)

    @classmethod
    def from_values(cls, values: Sequence[Any], actuated: int) -> Inertia:
        """The inertia of :meth:`values` (floats or traced values); ``actuated`` 0-based."""
        v = values
        return cls(
            links=((v[0], (v[1], v[2]), v[3]), (v[4], (v[5], v[6]), v[7])),
            platform=(v[8], v[9]),
            payload=(v[10], (v[11], v[12]), v[13]),
            load=(v[14], v[15], v[16]),
            gravity=(v[17], v[18]),
            actuated=actuated,
        )


def _inverse(cols: Sequence[tuple[Any, Any, Any]]) -> list[list[Any]]:
    """Rows of the inverse of the matrix with columns ``cols`` (adjugate over determinant)."""
    (a, d, g), (b, e, h), (c, f, i) = cols
    co = (e * i - f * h, f * g - d * i, d * h - e * g)
    inv = 1.0 / (a * co[0] + b * co[1] + c * co[2])
    return [
        [co[0] * inv, (c * h - b * i) * inv, (b * f - c * e) * inv],
        [co[1] * inv, (a * i - c * g) * inv, (c * d - a * f) * inv],
        [co[2] * inv, (b * g - a * h) * inv, (a * e - b * d) * inv],
    ]


def _apply(k: Sequence[Sequence[Any]], v: Sequence[Any]) -> list[Any]:
    return [k[i][0] * v[0] + k[i][1] * v[1] + k[i][2] * v[2] for i in range(3)]


def _apply_transposed(k: Sequence[Sequence[Any]], v: Sequence[Any]) -> list[Any]:
    return [k[0][i] * v[0] + k[1][i] * v[1] + k[2][i] * v[2] for i in range(3)]


@dataclass(frozen=True)
class _Moving:
    """A leg's chain at one instant: joint origins, frame rotations, joint rates."""

    types: str
    origins: Sequence[Pair]
    rotations: Sequence[Pair]
    dq: Sequence[Any]

    def velocity(self, p: Pair, body: int) -> Pair:
        """Velocity of the point ``p`` fixed in the distal body of joint ``body − 1``."""
        out: Pair = (0.0, 0.0)
        for i in range(body):
            if self.types[i] == "R":
                out = _add(out, _scale(self.dq[i], _perp(_sub(p, self.origins[i]))))
            else:
                out = _add(out, _scale(self.dq[i], self.rotations[i]))
        return out

    def acceleration(
        self,
        p: Pair,
        body: int,
        ddq: Sequence[Any],
        o_dot: Sequence[Pair],
        omega_before: Sequence[Any],
    ) -> Pair:
        """``Σ_i q̈_i·s_i + q̇_i·ṡ_i`` of the point ``p`` (the twists' rates as in mechanics)."""
        v = self.velocity(p, body)
        out: Pair = (0.0, 0.0)
        for i in range(body):
            if self.types[i] == "R":
                out = _add(out, _scale(ddq[i], _perp(_sub(p, self.origins[i]))))
                out = _add(out, _scale(self.dq[i], _perp(_sub(v, o_dot[i]))))
            else:
                u = self.rotations[i]
                out = _add(out, _scale(ddq[i], u))
                out = _add(out, _scale(self.dq[i] * omega_before[i], _perp(u)))
        return out


def _sums_before(types: str, rates: Sequence[Any]) -> list[Any]:
    """``[Σ_{i<k, R} rates_i for k = 0..3]``: the rotation rate of each joint's frame."""
    total: Any = 0.0
    sums = [0.0 * rates[0]] * 4
    for k in range(3):
        sums[k] = total
        if types[k] == "R":
            total = total + rates[k]
    sums[3] = total
    return sums


def sample_dynamics(
    ops: Ops,
    types: str,
    inertia: Inertia,
    scale: float,
    state: Sequence[Any],
    legs: Sequence[tuple[Sequence[Pair], Sequence[Pair]]],
    extended: bool = False,
) -> list[Any]:
    """``[μ_par, tau_A, tau_B, tau_C, joint (27)]`` of one sample (docs/family.md §6, §7).

    ``state`` is ``x, y, cos φ, sin φ, ẋ, ẏ, φ̇, ẍ, ÿ, φ̈``; ``legs`` the
    fixed-frame joint origins and frame rotations of each leg.  The steps of
    :mod:`prp3.family.mechanics`: ``q̇ = K·t`` and ``q̈ = K·(ṫ − J̇·q̇)`` with
    ``K = J⁻¹``; the bodies' wrenches about ``G``; virtual work
    ``Σ_L τ_L·K_L[a, :] = w_platform + Σ_L K_Lᵀ·B_L``; ``w_L = K_Lᵀ·(τ_L·e_a − B_L)``,
    ``W_3 = w_L``, ``W_2 = N_2 + W_3``, ``W_1 = N_1 + W_2``.

    ``extended``: after those, per leg ``q̇`` (9), ``q̈`` (9), the power
    ``τ_L·q̇_a`` (3), ``J`` (27, row-major per leg) and ``K = J⁻¹`` (27).
    """
    x, y, cphi, sphi, dx, dy, dphi, ddx, ddy, ddphi = state
    g: Pair = (x, y)
    grav = inertia.gravity
    twist = (dx, dy, dphi)
    a_idx = inertia.actuated
    per_leg = []
    wrench_rows = []
    rates: list[tuple[list[Any], list[Any], list[tuple[Any, Any, Any]]]] = []
    for origins, rotations in legs:
        cols = []
        for k in range(3):
            if types[k] == "R":
                v = _perp(_sub(g, origins[k]))
                cols.append((v[0], v[1], 1.0))
            else:
                cols.append((rotations[k][0], rotations[k][1], 0.0))
        kinv = _inverse(cols)
        dq = _apply(kinv, twist)
        omega_before = _sums_before(types, dq)  # Σ_{i<k, R} q̇_i

        chain = _Moving(types, origins, rotations, dq)
        o_dot = [chain.velocity(origins[k], k) if types[k] == "R" else (0.0, 0.0) for k in range(3)]
        bias = [
            _perp(_sub((dx, dy), o_dot[k]))
            if types[k] == "R"
            else _scale(omega_before[k], _perp(rotations[k]))
            for k in range(3)
        ]
        rhs = (
            ddx - (bias[0][0] * dq[0] + bias[1][0] * dq[1] + bias[2][0] * dq[2]),
            ddy - (bias[0][1] * dq[0] + bias[1][1] * dq[1] + bias[2][1] * dq[2]),
            ddphi,
        )
        ddq = _apply(kinv, rhs)
        alpha_before = _sums_before(types, ddq)  # Σ_{i<k, R} q̈_i

        links = []
        for body in (1, 2):
            mass, com, izz = inertia.links[body - 1]
            centre = _add(origins[body - 1], turn(rotations[body - 1], com))
            acc = chain.acceleration(centre, body, ddq, o_dot, omega_before)
            force = _scale(mass, _sub(acc, grav))
            moment = izz * alpha_before[body] + _cross(_sub(centre, g), force)
            links.append((force[0], force[1], moment))
        distal = [
            tuple(links[0][i] + links[1][i] for i in range(3)),
            links[1],
            (0.0, 0.0, 0.0),
        ]
        powers = [_dot(cols[k][:2], distal[k][:2]) + cols[k][2] * distal[k][2] for k in range(3)]
        per_leg.append((origins, kinv, links, powers))
        rates.append((dq, ddq, cols))
        wrench_rows.append(_apply_transposed(kinv, powers))
    # the platform's need (with the payload) minus the load, docs/family.md §4
    mp, ip = inertia.platform
    mpl, compl, ipl = inertia.payload
    r = turn((cphi, sphi), compl)
    a_pl = _sub(_add((ddx, ddy), _scale(ddphi, _perp(r))), _scale(dphi * dphi, r))
    f_pl = _scale(mpl, _sub(a_pl, grav))
    platform = [
        mp * (ddx - grav[0]) + f_pl[0] - inertia.load[0],
        mp * (ddy - grav[1]) + f_pl[1] - inertia.load[1],
        ip * ddphi + ipl * ddphi + _cross(r, f_pl) - inertia.load[2],
    ]
    need = [platform[i] + sum(row[i] for row in wrench_rows) for i in range(3)]
    matrix_cols = [(kinv[a_idx][0], kinv[a_idx][1], kinv[a_idx][2]) for _, kinv, _, _ in per_leg]
    tau = _apply(_inverse(matrix_cols), need)  # columns K_L[a, :]
    joints: list[Any] = []
    for (origins, kinv, links, powers), t in zip(per_leg, tau, strict=True):
        effort = [t - powers[k] if k == a_idx else -powers[k] for k in range(3)]
        w3 = _apply_transposed(kinv, effort)
        w2 = [links[1][i] + w3[i] for i in range(3)]
        w1 = [links[0][i] + w2[i] for i in range(3)]
        for k, wk in enumerate((w1, w2, w3)):
            joints += [wk[0], wk[1], wk[2] + _cross(_sub(g, origins[k]), (wk[0], wk[1]))]
    # μ_par: the passive columns' cross products, normalised (docs/family.md §6)
    rows = []
    for origins, rotations in legs:
        cols_hat = _scaled_columns(Design(types, (), (), scale), g, origins, rotations)
        p, q = (cols_hat[k] for k in range(3) if k != a_idx)
        rows.append(
            (p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0])
        )
    norms = [_dot(row[:2], row[:2]) + row[2] * row[2] for row in rows]
    mu_par = _det(rows) / ops.sqrt(norms[0] * norms[1] * norms[2])
    if not extended:
        return [mu_par, *tau, *joints]
    extra = [v for dq, _, _ in rates for v in dq] + [v for _, ddq, _ in rates for v in ddq]
    extra += [t * dq[a_idx] for t, (dq, _, _) in zip(tau, rates, strict=True)]
    extra += [cols[c][i] for _, _, cols in rates for i in range(3) for c in range(3)]
    extra += [v for _, kinv, _, _ in per_leg for row in kinv for v in row]
    return [mu_par, *tau, *joints, *extra]


# ------------------------------------------------------------------ the stages as traced
def fixed_candidates(
    ops: Ops, design: Design, sigma: Pair, x: Any, y: Any, c: Any, s: Any
) -> list[Any]:
    """:func:`leg_candidates` of the leg turned by ``sigma = (cos σ_j, sin σ_j)``, flat, in the fixed frame.

    13 numbers per candidate: the origins ``O_1 … O_3`` (6), the rotations of
    ``F_1 … F_3`` (6), ``μ_leg``; ``(x, y)`` is ``G`` and ``(c, s) = (cos φ, sin φ)``.
    """
    cs, ss = sigma
    local = (cs * x + ss * y, cs * y - ss * x)
    out: list[Any] = []
    for origins, rotations, mu in leg_candidates(ops, design, local, (c, s)):
        for o in origins:  # back to the fixed frame: Rot(σ_j)
            out += turn((cs, ss), o)
        for r in rotations:
            out += turn((cs, ss), r)
        out.append(mu)
    return out


def path_candidates(
    ops: Ops, design: Design, sigma: Pair, actuated: int, x: Any, y: Any, c: Any, s: Any
) -> list[Any]:
    """What the path of docs/family.md §5 needs of each candidate of :func:`leg_solutions`, flat.

    7 numbers per candidate of the leg turned by ``sigma = (cos σ_j, sin σ_j)``
    at ``G = (x, y)``, ``(c, s) = (cos φ, sin φ)`` (fixed frame): the joint
    values ``q_1 … q_3`` — an R angle as ``atan2`` of its relative rotation
    ``R_{F_k}·conj(R_{F_{k−1}}·Rot(γ_k))`` (rad, in ``[−π, π]``, to be unwrapped
    along the path), a P value as solved (m) —, ``μ_leg`` and the wrench the
    leg transmits, ``Ĵ[:, p] × Ĵ[:, r]`` of its passive joints (``actuated``
    0-based) turned into the fixed frame (:func:`prp3.family.chain.transmitted_wrench`).
    """
    cs, ss = sigma
    local = (cs * x + ss * y, cs * y - ss * x)
    out: list[Any] = []
    for origins, rotations, slides, mu in leg_solutions(ops, design, local, (c, s)):
        before: Pair = (1.0, 0.0)
        for k in range(3):
            if design.types[k] == "R":
                joint, r = turn(before, _unit(ops, design.gamma[k])), rotations[k]
                out.append(ops.atan2(_cross(joint, r), _dot(joint, r)))
            else:
                out.append(slides[k])
            before = rotations[k]
        cols = _scaled_columns(design, local, origins, rotations)
        p, r3 = (cols[k] for k in range(3) if k != actuated)
        w = (p[1] * r3[2] - p[2] * r3[1], p[2] * r3[0] - p[0] * r3[2], p[0] * r3[1] - p[1] * r3[0])
        out += [mu, cs * w[0] - ss * w[1], ss * w[0] + cs * w[1], w[2]]
    return out


def legs_of(values: Sequence[Any]) -> list[tuple[list[Pair], list[Pair]]]:
    """The ``legs`` argument of :func:`sample_dynamics` from 12 numbers per leg (origins, rotations)."""
    legs = []
    for j in range(3):
        v = values[12 * j : 12 * j + 12]
        legs.append(
            ([(v[2 * k], v[2 * k + 1]) for k in range(3)],
             [(v[6 + 2 * k], v[7 + 2 * k]) for k in range(3)])
        )  # fmt: skip
    return legs


def chain_of(
    ops: Ops, design: Design, sigma: float, q: Sequence[Any]
) -> tuple[list[Any], list[Pair], list[Pair]]:
    """The chain of docs/family.md §2 at joint values ``q``, as :func:`prp3.family.chain.leg_chain`.

    Returns ``(frames, origins, rotations)``: ``frames`` the 27 numbers
    ``J_k`` origins (6), angles (3), ``F_k`` origins (6), angles (3), the axes
    ``u_k`` (6), ``E``'s origin (2) and angle (1); ``origins`` the ``O_k`` and
    ``rotations`` the ``(cos, sin)`` of the ``F_k`` (the ``legs`` of
    :func:`sample_dynamics`).  ``σ`` is the leg's start angle.
    """
    theta: Any = sigma
    p: Pair = (0.0, 0.0)
    joint_o: list[Any] = []
    axes: list[Any] = []
    joint_a: list[Any] = []
    frame_a: list[Any] = []
    frame_o: list[Pair] = []
    rotations: list[Pair] = []
    for k in range(3):
        pj = _add(p, turn(_unit(ops, theta), design.c[k]))
        tj = theta + design.gamma[k]
        u = _unit(ops, tj)
        if design.types[k] == "R":
            p, theta = pj, tj + q[k]
        else:
            p, theta = _add(pj, _scale(q[k], u)), tj
        joint_o += pj
        joint_a.append(tj)
        frame_o.append(p)
        frame_a.append(theta)
        axes += u
        rotations.append(_unit(ops, theta))
    end = _add(p, turn(_unit(ops, theta), design.c[3]))
    end_angle = theta + design.gamma[3]
    frames = [*joint_o, *joint_a, *(v for o in frame_o for v in o), *frame_a, *axes, *end,
              end_angle]  # fmt: skip
    return frames, frame_o, rotations
