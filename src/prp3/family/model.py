"""The family robot: an immutable, validated model of a planar 3-leg robot (docs/family.md §3, §9).

A :class:`FamilyRobot` is one of the seven architectures (``3-PRP``, ``3-RPR``,
``3-RRR``, ``3-PRR``, ``3-PPR``, ``3-RPP``, ``3-RRP``), its actuated joint, leg
A's chain (:class:`LegDesign`: three joint placements, the attachment, the home
joint values, the scale ``ℓ`` of the measures) and the inertial parameters of
link 1, link 2 and the platform, with the payload, load and gravity of the
3-PRP model.  :meth:`FamilyRobot.default` gives the default design of each
architecture; ``ROBOT.toml`` files in *family form* are read by
:meth:`FamilyRobot.from_toml` (:func:`robot_file_form` tells the forms apart).

>>> robot = FamilyRobot.default("3-RRR")
>>> robot.types, robot.actuated, robot.leg.joint2
('RRR', 1, (0.2, 0.0, 1.5707963267948966))
>>> FamilyRobot.from_mapping({"architecture": "3-PPR", "actuated": 3})
Traceback (most recent call last):
...
prp3.errors.ParameterError: robot: actuated = 3 of the 3-PPR leaves two passive P joints: every leg would transmit a pure couple (refused)
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from prp3.errors import ParameterError
from prp3.family.chain import (
    SIGMA,
    SINGULAR,
    leg_chain,
    leg_jacobian,
    leg_measure,
    parallel_measure,
    transmitted_wrench,
    wrap,
)
from prp3.model.parameters import (
    Load,
    Payload,
    body_scale_checks,
    check_pair,
    check_parts,
    gravity_scale_check,
    load_scale_check,
    refuse_overflow,
)
from prp3.model.robot import Robot
from prp3.model.robot_toml import (
    parse_located,
    payload_load_toml,
    read_toml,
    toml_float,
    toml_line,
    toml_list,
    toml_table,
)
from prp3.validation import check_choice, check_file_path, check_integer, check_scalar

__all__ = [
    "ARCHITECTURES",
    "Body",
    "FamilyRobot",
    "LegDesign",
    "PlatformBody",
    "family_template",
    "read_robot_file",
    "robot_file_form",
]

FloatArray = NDArray[np.float64]
Triple = tuple[float, float, float]

#: The seven architectures of docs/family.md, in its order.
ARCHITECTURES: tuple[str, ...] = ("3-PRP", "3-RPR", "3-RRR", "3-PRR", "3-PPR", "3-RPP", "3-RRP")

_S2 = math.sqrt(2.0)
_S3 = math.sqrt(3.0)
_PI = math.pi

#: docs/family.md §3: actuated joint, joint1, joint2, joint3, attachment, home of leg A.
_DESIGNS: dict[str, tuple[int, Triple, Triple, Triple, Triple, Triple]] = {
    "3-PRP": (1, (_S3 / 20, -0.15, _PI / 3), (0.0, 0.0, -_PI / 3), (0.0, 0.0, 0.0),
              (-_S3 / 20, 0.15, 0.0), (0.0, 0.0, 0.0)),
    "3-RPR": (2, (0.0, -0.3, _PI / 4), (0.0, 0.0, 0.0), (0.0, 0.0, -_PI / 4),
              (-0.2, 0.1, 0.0), (0.0, 0.2 * _S2, 0.0)),
    "3-RRR": (1, (0.0, -0.3, 0.0), (0.2, 0.0, _PI / 2), (0.2, 0.0, -_PI / 2),
              (-0.2, 0.1, 0.0), (0.0, 0.0, 0.0)),
    "3-PRR": (1, (0.2, -0.3, _PI / 2), (0.0, 0.0, 0.0), (0.2, 0.0, -_PI / 2),
              (-0.2, 0.1, 0.0), (0.0, 0.0, 0.0)),
    "3-PPR": (1, (0.0, -0.3, 0.0), (0.0, 0.0, _PI / 2), (0.0, 0.0, -_PI / 2),
              (-0.1, 0.2, 0.0), (0.1, 0.1, 0.0)),
    "3-RPP": (2, (0.0, -0.3, 3 * _PI / 4), (0.0, 0.0, 0.0), (0.0, 0.0, -_PI / 2),
              (0.15 * _S2, -0.05 * _S2, -_PI / 4), (0.0, 0.2 * _S2, 0.0)),
    "3-RRP": (1, (0.0, -0.3, _PI / 4), (0.2 * _S2, 0.0, -_PI / 4), (0.0, 0.0, 0.0),
              (-0.2, 0.1, 0.0), (0.0, 0.0, 0.0)),
}  # fmt: skip

#: docs/family.md §3: link 1 (com, inertia) and link 2 (com, inertia); masses 1.0 and 0.75 kg.
_INERTIA: dict[str, tuple[tuple[float, float], float, tuple[float, float], float]] = {
    "3-PRP": ((0.0, 0.0), 0.0, (0.0, 0.0), 6.25e-4),
    "3-RPR": ((0.1, 0.0), 3e-3, (-0.1, 0.0), 2e-3),
    "3-RRR": ((0.1, 0.0), 3e-3, (0.1, 0.0), 2.5e-3),
    "3-PRR": ((0.0, 0.0), 0.0, (0.1, 0.0), 2.5e-3),
    "3-PPR": ((0.0, 0.0), 0.0, (-0.1, 0.0), 0.0),
    "3-RPP": ((0.1, 0.0), 3e-3, (0.0, 0.0), 6.25e-4),
    "3-RRP": ((0.1 * _S2, 0.0), 6.5e-3, (0.0, 0.0), 6.25e-4),
}

#: Keys of model form (docs/model.md) that family form refuses (docs/family.md §1).
MODEL_ONLY_KEYS: tuple[str, ...] = ("l0", "piston", "link", "friction")

#: Top-level keys of a family-form file.
FAMILY_KEYS: tuple[str, ...] = (
    "architecture", "actuated", "gravity", "leg", "link1", "link2", "platform", "payload", "load",
)  # fmt: skip

#: The keys whose presence makes a file family form (besides a non-3-PRP ``architecture``).
FAMILY_MARKERS: tuple[str, ...] = ("actuated", "leg", "link1", "link2")


def _triple(where: str, value: Any) -> Triple:
    if not isinstance(value, list | tuple | np.ndarray) or len(value) != 3:
        raise ParameterError(
            f"{where} must be three numbers [a, b, gamma], got {value!r}"[:200],
            subject="robot",
            key=where,
        )
    a, b, c = (check_scalar(f"{where}[{i}]", value[i], subject="robot") for i in range(3))
    return (a, b, c)


def _non_negative(where: str, value: Any, unit: str) -> float:
    return check_scalar(where, value, subject="robot", non_negative=True, unit=unit)


@dataclass(frozen=True)
class LegDesign:
    """Leg A's chain (docs/family.md §2): placements ``[a, b, γ]`` (m, m, rad), home, scale.

    Attributes
    ----------
    joint1, joint2, joint3 : tuple of 3 floats
        Placement of the joint-k frame in the preceding frame.
    attachment : tuple of 3 floats
        Placement of the attachment frame ``E`` in ``F_3``.
    home : tuple of 3 floats
        ``q1, q2, q3`` of the home configuration (m for P, rad for R).
    scale : float
        ``ℓ`` of the singularity measures (m), > 0.
    """

    joint1: Triple
    joint2: Triple
    joint3: Triple
    attachment: Triple
    home: Triple
    scale: float = 0.3

    def __post_init__(self) -> None:
        for name in ("joint1", "joint2", "joint3", "attachment", "home"):
            object.__setattr__(self, name, _triple(f"leg.{name}", getattr(self, name)))
        object.__setattr__(
            self,
            "scale",
            check_scalar("leg.scale", self.scale, subject="robot", positive=True, unit="m"),
        )

    @property
    def placements(self) -> FloatArray:
        """``joint1, joint2, joint3, attachment`` as rows, shape ``(4, 3)``."""
        return np.array([self.joint1, self.joint2, self.joint3, self.attachment])


@dataclass(frozen=True)
class Body:
    """A link of each leg: mass (kg, >= 0), ``com`` in the body's frame (m), ``I_zz`` (kg·m²)."""

    mass: float
    com: tuple[float, float]
    inertia: float
    name: str = field(default="link", compare=False, repr=False)

    def __post_init__(self) -> None:
        n = self.name
        object.__setattr__(self, "mass", _non_negative(f"{n}.mass", self.mass, "kg"))
        object.__setattr__(self, "com", check_pair(f"{n}.com", self.com))
        object.__setattr__(self, "inertia", _non_negative(f"{n}.inertia", self.inertia, "kg·m²"))


@dataclass(frozen=True)
class PlatformBody:
    """The platform: mass (kg) and ``I_zz`` about its mass centre ``G`` (kg·m²), both >= 0."""

    mass: float = 3.0
    inertia: float = 0.0675

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", _non_negative("platform.mass", self.mass, "kg"))
        object.__setattr__(
            self, "inertia", _non_negative("platform.inertia", self.inertia, "kg·m²")
        )


@dataclass(frozen=True)
class FamilyRobot:
    """A planar 3-leg parallel robot of docs/family.md (immutable, validated).

    Construction refuses an actuation that leaves two passive P joints and a
    home configuration with a singularity measure below ``1e-4`` in magnitude.

    Attributes
    ----------
    architecture : str
        One of :data:`ARCHITECTURES`.
    actuated : int
        The driven joint of every leg, 1, 2 or 3.
    leg : LegDesign
    link1, link2 : Body
        The bodies between joints 1–2 (frame ``F_1``) and 2–3 (frame ``F_2``).
    platform : PlatformBody
    payload : prp3.model.parameters.Payload
    load : prp3.model.parameters.Load
    gravity : tuple of float
        ``(g_x, g_y)`` (m/s²).

    Examples
    --------
    >>> robot = FamilyRobot.default("3-RPR")
    >>> [round(v, 3) for v in robot.home_measures[0]], round(robot.home_measures[1], 3)
    ([-0.943, -0.943, -0.943], 1.0)
    """

    architecture: str
    actuated: int
    leg: LegDesign
    link1: Body
    link2: Body
    platform: PlatformBody = field(default_factory=PlatformBody)
    payload: Payload = field(default_factory=Payload)
    load: Load = field(default_factory=Load)
    gravity: tuple[float, float] = (0.0, -9.81)

    def __post_init__(self) -> None:
        check_choice("architecture", self.architecture, ARCHITECTURES)
        check_integer("actuated", self.actuated, 1, 3, subject="robot")
        check_parts(
            self,
            (
                ("leg", LegDesign),
                ("link1", Body),
                ("link2", Body),
                ("platform", PlatformBody),
                ("payload", Payload),
                ("load", Load),
            ),
        )
        object.__setattr__(self, "gravity", check_pair("gravity", self.gravity))
        passive = [self.types[k] for k in range(3) if k != self.actuated - 1]
        if passive == ["P", "P"]:
            raise ParameterError(
                f"actuated = {self.actuated} of the {self.architecture} leaves two passive P "
                "joints: every leg would transmit a pure couple (refused)",
                subject="robot",
                key="actuated",
            )
        self._check_home()
        self._check_scale()

    # ---------------------------------------------------------------- derived
    @property
    def types(self) -> str:
        """The joint types of a leg, base to platform (``"RRR"`` ...)."""
        return self.architecture[2:]

    @cached_property
    def home_poses(self) -> FloatArray:
        """Each leg's home pose ``(x, y, φ)`` at ``q = home`` (docs/family.md §5), shape ``(3, 3)``."""
        frames = leg_chain(self.types, self.leg.placements, SIGMA, np.tile(self.leg.home, (3, 1)))
        poses = np.concatenate(
            [frames.end_origin, wrap(frames.end_angle - SIGMA)[:, None]], axis=-1
        )
        poses.flags.writeable = False
        return poses

    @cached_property
    def home_measures(self) -> tuple[list[float], float]:
        """``μ_leg`` of legs A, B, C and ``μ_par`` in the home configuration (docs/family.md §6)."""
        frames = leg_chain(self.types, self.leg.placements, SIGMA, np.tile(self.leg.home, (3, 1)))
        hat = leg_jacobian(self.types, frames, frames.end_origin, self.leg.scale)
        mu_leg = leg_measure(hat)
        mu_par = parallel_measure(transmitted_wrench(hat, self.actuated))
        return [float(v) for v in mu_leg], float(mu_par)

    def _check_home(self) -> None:
        with np.errstate(all="ignore"):
            mu_leg, mu_par = self.home_measures
            frames = leg_chain(
                self.types, self.leg.placements, SIGMA, np.tile(self.leg.home, (3, 1))
            )
            scaled = leg_jacobian(self.types, frames, frames.end_origin, self.leg.scale)
            wrench = transmitted_wrench(scaled, self.actuated)
        if not (
            np.isfinite(scaled).all() and np.isfinite(wrench).all() and np.isfinite(mu_leg).all()
        ):
            raise ParameterError(
                f"leg.scale = {self.leg.scale!r} m with the placements and home of [leg] makes the "
                "singularity measures overflow float64 (lengths out of range)",
                subject="robot",
                key="leg.scale",
            )
        for leg, value in zip("ABC", mu_leg, strict=True):
            if not abs(value) >= SINGULAR:
                raise ParameterError(
                    f"the home configuration q = {list(self.leg.home)} is singular: "
                    f"mu_leg of leg {leg} = {value:.3g} (|mu| < {SINGULAR:g}, docs/family.md §6)",
                    subject="robot",
                    key="leg.home",
                )
        if not abs(mu_par) >= SINGULAR:
            raise ParameterError(
                f"the home configuration q = {list(self.leg.home)} with actuated = "
                f"{self.actuated} is a parallel singularity: mu_par = {mu_par:.3g} "
                f"(|mu| < {SINGULAR:g})",
                subject="robot",
                key="actuated",
            )

    def _check_scale(self) -> None:
        """Refuse bodies, a payload or a load whose effects overflow float64 (``mass = 1e308``).

        The checks of the 3-PRP (:func:`prp3.model.parameters.body_scale_checks`) with the
        leg's reach ``Σ|(a_k, b_k)| + Σ|q_k(home)|`` (m) in place of ``l0``: each body's weight,
        its inertia and the moment of its weight about a leg's base (the links three times:
        one per leg), their totals, and the load's wrench.
        """
        g = max(abs(self.gravity[0]), abs(self.gravity[1]), 1.0)
        with np.errstate(over="ignore"):
            reach = float(
                np.hypot(self.leg.placements[:, 0], self.leg.placements[:, 1]).sum()
                + np.abs(np.array(self.leg.home)).sum()
            )
        checks = [
            gravity_scale_check(self.gravity, reach),
            *body_scale_checks("link1", *self._body(self.link1), reach, g, count=3),
            *body_scale_checks("link2", *self._body(self.link2), reach, g, count=3),
            *body_scale_checks(
                "platform", self.platform.mass, (0.0, 0.0), self.platform.inertia, reach, g
            ),
            *body_scale_checks(
                "payload", self.payload.mass, self.payload.com, self.payload.inertia, reach, g
            ),
            load_scale_check(self.load, reach),
        ]
        refuse_overflow(
            checks, f"(reach of a leg {reach:.6g} m, gravity = {list(self.gravity)!r} m/s²)"
        )

    @staticmethod
    def _body(body: Body) -> tuple[float, tuple[float, float], float]:
        return body.mass, body.com, body.inertia

    # ---------------------------------------------------------------- builders
    @classmethod
    def default(cls, architecture: str = "3-RRR", actuated: int | None = None) -> FamilyRobot:
        """The default design of ``architecture`` (docs/family.md §3), optionally another actuation.

        >>> FamilyRobot.default("3-PRP").leg.attachment[1]
        0.15
        """
        check_choice("architecture", architecture, ARCHITECTURES)
        act, j1, j2, j3, att, home = _DESIGNS[architecture]
        com1, i1, com2, i2 = _INERTIA[architecture]
        return cls(
            architecture=architecture,
            actuated=act if actuated is None else actuated,
            leg=LegDesign(joint1=j1, joint2=j2, joint3=j3, attachment=att, home=home),
            link1=Body(1.0, com1, i1, name="link1"),
            link2=Body(0.75, com2, i2, name="link2"),
        )

    @classmethod
    def from_mapping(cls, data: Mapping[str, Any]) -> FamilyRobot:
        """A robot from a family-form ``ROBOT.toml`` mapping (docs/family.md §9).

        Missing keys take the architecture's defaults; the keys of the 3-PRP file of docs/model.md only
        and unknown keys are refused naming the key.

        >>> FamilyRobot.from_mapping({"architecture": "3-RRR", "l0": 0.3})
        Traceback (most recent call last):
        ...
        prp3.errors.ParameterError: robot: key 'l0' belongs to model form (the 3-PRP file of docs/model.md); a family-form robot file (architecture, actuated, [leg], [link1], [link2]) does not accept it
        """
        top = toml_table("", data, FAMILY_KEYS, _model_only)
        architecture = top.get("architecture", "3-PRP")
        if not isinstance(architecture, str) or architecture not in ARCHITECTURES:
            raise ParameterError(
                f"architecture must be one of {', '.join(ARCHITECTURES)}, got {architecture!r}"[
                    :200
                ],
                subject="robot",
                key="architecture",
            )
        base = cls.default(architecture)
        leg = replace(base.leg, **toml_table("leg", top.get("leg", {}), _LEG_KEYS))
        bodies = {}
        for name in ("link1", "link2"):
            given = toml_table(name, top.get(name, {}), ("mass", "com", "inertia"))
            bodies[name] = replace(getattr(base, name), **given)
        platform = PlatformBody(
            **toml_table("platform", top.get("platform", {}), ("mass", "inertia"))
        )
        payload = toml_table("payload", top.get("payload", {}), ("mass", "com", "inertia"))
        if "com" in payload:
            payload["com"] = check_pair("payload.com", payload["com"])
        load = toml_table("load", top.get("load", {}), ("force", "moment"))
        if "force" in load:
            load["force"] = check_pair("load.force", load["force"])
        return cls(
            architecture=architecture,
            actuated=top.get("actuated", base.actuated),
            leg=leg,
            link1=bodies["link1"],
            link2=bodies["link2"],
            platform=platform,
            payload=Payload(**payload),
            load=Load(**load),
            gravity=check_pair("gravity", top["gravity"]) if "gravity" in top else base.gravity,
        )

    @classmethod
    def from_toml(cls, path: str | Path) -> FamilyRobot:
        """Read a family-form ``ROBOT.toml`` (errors name the file and the key)."""
        path = Path(path)
        return parse_located(path, cls.from_mapping, read_toml(path, "robot"))

    def to_toml(self) -> str:
        """The robot as family-form ``ROBOT.toml`` text (round-trips through :meth:`from_mapping`).

        >>> import tomllib
        >>> robot = FamilyRobot.default("3-RPP")
        >>> FamilyRobot.from_mapping(tomllib.loads(robot.to_toml())) == robot
        True
        """
        return family_template(self, comments=False)


_LEG_KEYS: tuple[str, ...] = ("joint1", "joint2", "joint3", "attachment", "home", "scale")


def _model_only(key: str, dotted: str) -> None:
    """Refuse a key of model form (the 3-PRP file) at the top of a family-form file."""
    if key in MODEL_ONLY_KEYS:
        shown = f"[{key}]" if key != "l0" else "'l0'"
        raise ParameterError(
            f"key {shown} belongs to model form (the 3-PRP file of docs/model.md); a family-form robot file (architecture, "
            "actuated, [leg], [link1], [link2]) does not accept it",
            subject="robot",
            key=dotted,
        )


def robot_file_form(data: Mapping[str, Any]) -> Literal["model", "family"]:
    """Which form a ``ROBOT.toml`` mapping is in (docs/family.md §1).

    >>> robot_file_form({"l0": 0.3}), robot_file_form({"architecture": "3-RRR"})
    ('model', 'family')
    >>> robot_file_form({"architecture": "3-PRP"}), robot_file_form({"actuated": 1})
    ('model', 'family')
    """
    if "architecture" in data and data["architecture"] != "3-PRP":
        return "family"
    if any(key in data for key in FAMILY_MARKERS):
        return "family"
    return "model"


def read_robot_file(path: str | Path) -> Robot | FamilyRobot:
    """Read ``ROBOT.toml`` in either form: a :class:`prp3.Robot` or a :class:`FamilyRobot`.

    A model-form file (docs/model.md) is read exactly as :meth:`prp3.Robot.from_toml` reads
    it (``architecture = "3-PRP"`` is then dropped); a family-form file by
    :meth:`FamilyRobot.from_toml`.
    """
    path = check_file_path("path", path)
    data = read_toml(path, "robot")
    if robot_file_form(data) == "family":
        return parse_located(path, FamilyRobot.from_mapping, data)
    model_form = {k: v for k, v in data.items() if k != "architecture"}
    return parse_located(path, Robot.from_mapping, model_form)


_ARCH_NOTE = {
    "3-PRP": "the robot of docs/model.md at l0 = 0.3 m: guide, sleeve pivot, platform slide",
    "3-RPR": "base pivot, telescopic leg (q2 = its length), platform pivot",
    "3-RRR": "base pivot, elbow, platform pivot; link 1 along x0, link 2 along y0 at home",
    "3-PRR": "vertical base guide, link 2 from the slider pivot to the platform pivot",
    "3-PPR": "horizontal guide, vertical slide on it, platform pivot",
    "3-RPP": "pivot, guide at 135 deg, cross-slide at 45 deg; the platform slides on it",
    "3-RRP": "pivot, link 1 to the elbow; link 2 a sleeve along the platform edge",
}


def family_template(robot: FamilyRobot | str | None = None, *, comments: bool = True) -> str:
    """A family-form ``ROBOT.toml`` text of ``robot`` (an architecture name: its defaults).

    With ``comments=True`` every key carries its meaning and unit; this is
    what ``prp3 robot --template --architecture NAME`` prints.

    >>> import tomllib
    >>> text = family_template("3-RRR")
    >>> FamilyRobot.from_mapping(tomllib.loads(text)) == FamilyRobot.default("3-RRR")
    True
    """
    if robot is None or isinstance(robot, str):
        robot = FamilyRobot.default("3-RRR" if robot is None else robot)
    if not isinstance(robot, FamilyRobot):
        raise ParameterError(f"robot must be a FamilyRobot, got {robot!r}"[:200], key="robot")

    def line(key: str, value: str, comment: str) -> str:
        return toml_line(key, value, comment, comments)

    values = toml_list

    leg = robot.leg
    units = ["m" if kind == "P" else "rad" for kind in robot.types]
    out: list[str] = []
    if comments:
        out += [
            f"# prp3 robot parameters, family form: a {robot.architecture} "
            f"({_ARCH_NOTE[robot.architecture]}).",
            "# SI units, angles in rad. Every key is optional; omitted keys take the defaults",
            "# of the architecture shown here (docs/family.md states the model).",
        ]
    out += [
        line("architecture", f'"{robot.architecture}"', " | ".join(ARCHITECTURES)),
        line("actuated", str(robot.actuated), "1, 2 or 3: the driven joint of every leg"),
        line("gravity", values(robot.gravity), "m/s^2, gravity in the fixed frame (y0 up)"),
        "",
        "[leg]" + ("  # leg A's chain, base to platform; legs B, C turned by 120, 240 deg"
                   if comments else ""),
        line("joint1", values(leg.joint1), f"[a, b, gamma] of joint 1 ({robot.types[0]}) in the "
             "start frame (m, m, rad)"),
        line("joint2", values(leg.joint2), f"joint 2 ({robot.types[1]}) in F_1"),
        line("joint3", values(leg.joint3), f"joint 3 ({robot.types[2]}) in F_2"),
        line("attachment", values(leg.attachment), "the platform frame (G, phi) in F_3"),
        line("home", values(leg.home), f"q1, q2, q3 at home ({', '.join(units)})"),
        line("scale", toml_float(leg.scale), "m, length of the singularity measures"),
    ]  # fmt: skip
    for name, where in (("link1", "joints 1 and 2, frame F_1"), ("link2", "joints 2 and 3, F_2")):
        body: Body = getattr(robot, name)
        out += [
            "",
            f"[{name}]" + (f"  # body between {where}" if comments else ""),
            line("mass", toml_float(body.mass), "kg"),
            line("com", values(body.com), "m, mass centre in the body's frame"),
            line("inertia", toml_float(body.inertia), "kg m^2, I_zz about its mass centre"),
        ]
    out += [
        "",
        "[platform]" + ("  # its mass centre is G by definition" if comments else ""),
        line("mass", toml_float(robot.platform.mass), "kg"),
        line("inertia", toml_float(robot.platform.inertia), "kg m^2, I_zz about G"),
    ]
    out += payload_load_toml(robot.payload, robot.load, comments)
    return "\n".join(out) + "\n"
