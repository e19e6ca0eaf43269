"""The compiled family engine (``prp3.family.compiled``, numba) against the family route.

Compared with ``family_inverse_dynamics`` (the numpy route, another
formulation: angles, ``atan2``, batched inverses) to 1e-12 relative to the
sample's largest output: ``tau``, every joint wrench, ``μ_leg`` and ``μ_par``, on
one design of each kind of closure (two R joints, RPR's quadratic in a slide,
one R joint with two slides, RRP's sleeve) with a payload and a load, along the
paper's motions, and on hypothesis-random designs; and the refusals name the
same sample as the family route.  Each robot is compiled once (a few seconds),
so the designs are few.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from prp3.errors import SingularPoseError, TrajectoryError, UnreachablePoseError
from prp3.family import FamilyRobot, family_inverse_dynamics
from prp3.family.compiled import compiled_inverse_dynamics
from prp3.model import Load, Payload
from prp3.motion import Motion, paper_motion

pytest.importorskip("numba")

DESIGNS = [("3-RRR", 1), ("3-RPR", 2), ("3-PRP", 1), ("3-RRP", 3)]


def loaded(arch: str, act: int) -> FamilyRobot:
    return replace(
        FamilyRobot.default(arch, act),
        payload=Payload(0.5, (0.02, -0.01), 1e-3),
        load=Load((3.0, -2.0), 0.4),
    )


def compare(robot: FamilyRobot, motion: Motion) -> float:
    got = compiled_inverse_dynamics(robot, motion)
    want = family_inverse_dynamics(robot, motion)
    n = motion.samples
    a = np.concatenate(
        [got.tau.reshape(n, -1), got.force.reshape(n, -1), got.moment.reshape(n, -1)], axis=1
    )
    b = np.concatenate(
        [want.tau.reshape(n, -1), want.force.reshape(n, -1), want.moment.reshape(n, -1)], axis=1
    )
    scale = np.maximum(np.abs(b).max(axis=1, keepdims=True), 1e-9)
    kin = want.kinematics
    assert np.abs(got.mu_leg - kin.mu_leg).max() < 1e-12
    assert np.abs(got.mu_par - kin.mu_par).max() < 1e-12
    return float((np.abs(a - b) / scale).max())


@pytest.mark.parametrize(("arch", "act"), DESIGNS)
def test_paper_motions_match_the_family_route(arch: str, act: int) -> None:
    robot = loaded(arch, act)
    for name in ("vertical", "rotation"):
        assert compare(robot, paper_motion(name, 101)) <= 1e-12, name


def _f(low: float, high: float) -> st.SearchStrategy[float]:
    return st.floats(low, high, allow_nan=False, allow_infinity=False)


@settings(max_examples=2, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    design=st.sampled_from(DESIGNS),
    masses=st.lists(_f(0.0, 3.0), min_size=3, max_size=3),
    coms=st.lists(_f(-0.2, 0.2), min_size=4, max_size=4),
    amp=st.lists(_f(0.0, 0.02), min_size=3, max_size=3),
    w=st.lists(_f(0.5, 4.0), min_size=3, max_size=3),
)
def test_random_designs_match_the_family_route(
    design: tuple[str, int],
    masses: list[float],
    coms: list[float],
    amp: list[float],
    w: list[float],
) -> None:
    base = FamilyRobot.default(*design)
    robot = replace(
        base,
        link1=replace(base.link1, mass=masses[0], com=(coms[0], coms[1])),
        link2=replace(base.link2, mass=masses[1], com=(coms[2], coms[3])),
        platform=replace(base.platform, mass=masses[2]),
        payload=Payload(0.3, (0.01, 0.02), 1e-3),
    )
    t = np.linspace(0.0, 1.0, 9)[:, None]
    a, f = np.array(amp) * [1.0, 1.0, 5.0], np.array(w)
    motion = Motion(
        t=t[:, 0],
        pose=a * np.sin(f * t + 0.3),
        velocity=a * f * np.cos(f * t + 0.3),
        acceleration=-a * f * f * np.sin(f * t + 0.3),
    )
    try:
        family_inverse_dynamics(robot, motion)
    except (SingularPoseError, UnreachablePoseError):
        assume(False)
    assert compare(robot, motion) <= 1e-12


def test_one_sample_has_the_rank_of_the_motion() -> None:
    robot = loaded("3-RRR", 1)
    solution = compiled_inverse_dynamics(robot, Motion.at_rest([0.01, 0.0, 0.05]))
    assert solution.tau.shape == (3,) and solution.force.shape == (3, 3, 2)
    assert solution.moment.shape == (3, 3) and solution.mu_par.shape == ()


def _motion(poses: list[list[float]]) -> Motion:
    pose = np.array(poses)
    zero = np.zeros_like(pose)
    return Motion(t=np.arange(len(poses), dtype=float), pose=pose, velocity=zero, acceleration=zero)


def test_refusals_name_the_sample() -> None:
    rrr = loaded("3-RRR", 1)
    motion = _motion([[0.0, 0.0, 0.0], [0.05, 0.0, 0.0], [0.5, 0.0, 0.0]])
    with pytest.raises(UnreachablePoseError) as info:
        compiled_inverse_dynamics(rrr, motion)
    assert info.value.sample == 2 and info.value.leg == "A"  # type: ignore[attr-defined]
    prp = loaded("3-PRP", 1)
    motion = _motion([[0.0, 0.0, 0.0], [0.0, 0.0, math.pi / 3.0 - 5e-5]])
    for route in (compiled_inverse_dynamics, family_inverse_dynamics):
        with pytest.raises(SingularPoseError) as caught:
            route(prp, motion)
        assert caught.value.sample == 1  # type: ignore[attr-defined]
    with pytest.raises(TrajectoryError, match="robot lengths"):
        compiled_inverse_dynamics(rrr, _motion([[0.0, 0.0, 0.0], [1e3, 0.0, 0.0]]))
