"""The compiled path of docs/family.md §5, generated from the one source on ``Ops``.

:func:`prp3.family.sample_mechanics.path_candidates` (the source the compiled
path's closed forms are traced from) is held candidate by candidate against the
numpy closed forms of :mod:`prp3.family.legs` and the chain's ``μ_leg``
(:mod:`prp3.family.chain`), an independent code; and the compiled engine's
branch choice and refusals against the numpy engine on random robots of all
seven architectures, with poses near the legs' singularities.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from prp3 import Motion
from prp3.errors import Prp3Error
from prp3.family import FamilyRobot
from prp3.family.chain import SIGMA, leg_chain, leg_jacobian, leg_measure, rotate
from prp3.family.legs import LEG_GEOMETRY
from prp3.family.sample_mechanics import Design, path_candidates
from prp3.mechanics.ops import MATH
from strategies import family_designs as designs
from test_family_compiled import close, run, same_error, same_solution

pytest.importorskip("numba")


def wrapped(angle: float) -> float:
    return math.remainder(angle, 2.0 * math.pi)


@given(data=st.data())
def test_path_candidates_are_the_closed_forms_of_legs(data: st.DataObject) -> None:
    """Each candidate's q (R angles mod 2π), μ_leg and transmitted wrench, as the numpy code's."""
    robot = data.draw(designs())
    j = data.draw(st.integers(0, 2))
    home = robot.home_poses[j]
    pose = home + np.array([data.draw(st.floats(-0.05, 0.05)) for _ in range(2)]
                           + [data.draw(st.floats(-0.4, 0.4))])  # fmt: skip
    types, placements, scale = robot.types, robot.leg.placements, robot.leg.scale
    sigma = (math.cos(float(SIGMA[j])), math.sin(float(SIGMA[j])))
    flat = path_candidates(MATH, Design.of(robot), sigma, robot.actuated - 1, pose[0], pose[1],
                           math.cos(pose[2]), math.sin(pose[2]))  # fmt: skip
    local = rotate(-SIGMA[j], pose[None, :2])
    candidates = LEG_GEOMETRY[types](placements).candidates(local, pose[None, 2])
    assert len(flat) == 7 * len(candidates)
    for n, q in enumerate(candidates):
        ours = flat[7 * n : 7 * n + 7]
        if not np.isfinite(q).all():
            assert not all(math.isfinite(v) for v in ours[:4])
            continue
        for k in range(3):
            got = wrapped(ours[k] - q[0, k]) if types[k] == "R" else ours[k] - q[0, k]
            assert abs(got) < 1e-9, (k, ours[k], q[0, k])
        hat = leg_jacobian(types, leg_chain(types, placements, 0.0, q), local, scale)
        assert abs(ours[3] - float(leg_measure(hat)[0])) < 1e-9
        passive = [k for k in range(3) if k != robot.actuated - 1]
        wrench = np.cross(hat[0, :, passive[0]], hat[0, :, passive[1]])
        turned = [*rotate(SIGMA[j], wrench[None, :2])[0], wrench[2]]
        np.testing.assert_allclose(ours[4:], turned, rtol=0, atol=1e-9)


@given(data=st.data())
def test_branch_and_refusals_as_numpy_near_singular_poses(data: st.DataObject) -> None:
    """Poses swept toward and past the legs' singular configurations: the same q or error."""
    robot: FamilyRobot = data.draw(designs())
    centre = robot.home_poses.mean(axis=0)
    n = data.draw(st.integers(1, 5))
    reach = data.draw(st.sampled_from([0.05, 0.2, 0.5]))
    poses = [centre + np.array([data.draw(st.floats(-reach, reach)),
                                data.draw(st.floats(-reach, reach)),
                                data.draw(st.floats(-3 * reach, 3 * reach))])
             for _ in range(n)]  # fmt: skip
    motion = Motion.at_rest(poses, t=np.arange(n, dtype=float))
    compiled = run(robot, motion, engine="numba")
    arrays = run(robot, motion, engine="numpy")
    if isinstance(arrays, Prp3Error):
        assert isinstance(compiled, Prp3Error), f"numpy refused ({arrays}), numba did not"
        same_error(compiled, arrays)
        return
    assert not isinstance(compiled, Prp3Error), compiled
    same_solution(compiled, arrays)
    close(compiled.q, arrays.q, "q")
