"""The interface of a leg architecture (prp3.mechanics.architecture): two implementations of one 3-PRP.

The 3-PRP of docs/model.md runs the four stages by the kernel's closed form
(:class:`ClosedForm3PRP`); the same robot in the family's form (docs/family.md,
the 3-PRP conversion: actuated joint 1, the default placements) runs them on
the general leg chain (:class:`LegChain`), which shares no code with the
kernel.  Stage by stage they must agree: the joint values (stage 1), rates
(stage 2), the platform's wrench (stage 3) and the efforts and every joint
force (stage 4).  Each architecture of the family through the interface
equals its Newton–Euler route (the 21×21 balance of docs/family.md §7).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from prp3 import Motion, Robot, inverse_dynamics
from prp3.errors import Prp3Error, SingularPoseError, UnreachablePoseError
from prp3.family import FamilyRobot, family_inverse_dynamics
from prp3.family.architecture import LegChain, architecture_of
from prp3.mechanics.architecture import ClosedForm3PRP, JointSolution, solve_stages
from prp3.model.parameters import Friction, JointFriction, Load, Payload
from test_family_dynamics import ALLOWED, _f, designs, motions


def _pair(draw: st.DrawFn) -> tuple[Robot, FamilyRobot]:
    """One random 3-PRP in both forms (masses, centres of mass, inertias, payload, load, gravity)."""
    piston = (draw(_f(0.1, 3.0)), [draw(_f(-0.1, 0.1)), draw(_f(-0.1, 0.1))], draw(_f(0, 0.01)))
    link = (draw(_f(0.1, 3.0)), [draw(_f(-0.1, 0.1)), draw(_f(-0.1, 0.1))], draw(_f(0, 0.01)))
    platform = (draw(_f(0.1, 5.0)), draw(_f(0.0, 0.1)))
    payload = Payload(draw(_f(0.0, 2.0)), (draw(_f(-0.1, 0.1)), draw(_f(-0.1, 0.1))), 0.01)
    load = Load((draw(_f(-20, 20)), draw(_f(-20, 20))), draw(_f(-2, 2)))
    gravity = [draw(_f(-10, 10)), draw(_f(-10, 10))]
    bodies = {
        "platform": {"mass": platform[0], "inertia": platform[1]},
        "gravity": gravity,
    }
    model = Robot.from_mapping(
        {
            "piston": {"mass": piston[0], "com": piston[1], "inertia": piston[2]},
            "link": {"mass": link[0], "com": link[1], "inertia": link[2]},
            **bodies,
        }
    )
    family = FamilyRobot.from_mapping(
        {
            "architecture": "3-PRP",
            "actuated": 1,
            "link1": {"mass": piston[0], "com": piston[1], "inertia": piston[2]},
            "link2": {"mass": link[0], "com": link[1], "inertia": link[2]},
            "payload": {"mass": payload.mass, "com": list(payload.com), "inertia": payload.inertia},
            "load": {"force": list(load.force), "moment": load.moment},
            **bodies,
        }
    )
    return replace(model, payload=payload, load=load), family


def _close(a: np.ndarray, b: np.ndarray, scale: float, what: str) -> None:
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-10 * scale, err_msg=what)


@settings(max_examples=40)
@given(data=st.data())
def test_the_closed_form_and_the_leg_chain_agree_stage_by_stage(data: st.DataObject) -> None:
    model, family = _pair(data.draw)
    motion = data.draw(motions(np.zeros(3), samples=5))
    closed, chain = ClosedForm3PRP(model), LegChain(family)
    # stage 1 and 2: the joint values, rates and accelerations
    kin_closed = closed.rates(motion, closed.inverse_geometry(motion))
    kin_chain = chain.rates(motion, chain.inverse_geometry(motion))
    wrenches_closed = closed.body_wrenches(motion, kin_closed)
    wrenches_chain = chain.body_wrenches(motion, kin_chain)
    ours = closed.virtual_work(motion, kin_closed, wrenches_closed)
    theirs = chain.virtual_work(motion, kin_chain, wrenches_chain)
    both = solve_stages(closed, motion), solve_stages(chain, motion)
    for name in ("q", "tau", "force", "moment"):  # solve_stages runs the same four stages
        np.testing.assert_array_equal(getattr(both[0], name), getattr(ours, name))
        np.testing.assert_array_equal(getattr(both[1], name), getattr(theirs, name))
    scale = 1.0 + max(float(np.abs(v).max()) for v in (theirs.tau, theirs.force, theirs.moment))
    for name in ("q", "dq", "ddq"):
        _close(getattr(ours, name), getattr(theirs, name), 1.0 + np.abs(theirs.q).max(), name)
    _close(ours.q[..., 0], np.stack(kin_closed.geometry.lambda10, -1), 1.0, "q1 is λ10")
    # stage 3: the wrench the legs give the platform (force at G, moment about G)
    platform = np.stack(
        [wrenches_closed.platform_x, wrenches_closed.platform_y, wrenches_closed.platform_moment],
        -1,
    )
    _close(platform, wrenches_chain[1], scale, "platform wrench")
    # stage 4: the actuator efforts and every joint force
    for name in ("tau", "force", "moment"):
        _close(getattr(ours, name), getattr(theirs, name), scale, name)


@settings(max_examples=20)
@given(data=st.data())
def test_the_closed_form_equals_newton_euler_with_friction_and_a_spring(
    data: st.DataObject,
) -> None:
    # μ terms (implicit: stages 3 and 4 solved together), viscous and Coulomb friction, the spring
    model, _ = _pair(data.draw)
    joint = {
        kind: JointFriction(
            viscous=data.draw(_f(0.0, 2.0)),
            coulomb=data.draw(_f(0.0, 1.0)),
            mu=data.draw(_f(0.0, 0.05)),
            pin_radius=0.01 if kind == "revolute" else 0.0,
            kind=kind,
        )
        for kind in ("actuator", "revolute", "sleeve")
    }
    model = replace(model, friction=Friction(**joint)).with_keys(
        {"spring.actuator.stiffness": data.draw(_f(0.0, 50.0)), "spring.actuator.damping": 0.5}
    )
    motion = data.draw(motions(np.zeros(3), samples=5))
    solution = solve_stages(ClosedForm3PRP(model), motion)
    _, reference = inverse_dynamics(model, motion, "newton-euler")
    scale = 1.0 + float(np.abs(reference.f10).max()) + float(np.abs(reference.n10).max())
    _close(solution.tau, reference.f10, scale, "f10")
    _close(solution.moment[..., 0], reference.m10, scale, "m10")
    _close(
        solution.moment[..., 2] + solution.q[..., 2] * reference.n32, reference.m32, scale, "m32"
    )


@settings(max_examples=len(ALLOWED) * 2)
@given(data=st.data())
def test_every_architecture_through_the_interface_equals_its_newton_euler(
    data: st.DataObject,
) -> None:
    robot = data.draw(designs())
    motion = data.draw(motions(robot.home_poses.mean(axis=0)))
    try:
        reference = family_inverse_dynamics(robot, motion, "newton-euler")
    except (SingularPoseError, UnreachablePoseError):
        assume(False)
        raise
    solution = solve_stages(LegChain(robot), motion)
    assert isinstance(solution, JointSolution)
    scale = 1.0 + float(np.abs(reference.force).max()) + float(np.abs(reference.tau).max())
    for name in ("q", "dq", "ddq"):
        _close(
            getattr(solution, name), getattr(reference, name), 1.0 + np.abs(reference.q).max(), name
        )
    for name in ("tau", "force", "moment"):
        _close(getattr(solution, name), getattr(reference, name), scale, name)


def test_architecture_of_gives_each_robot_its_mechanics() -> None:
    assert isinstance(architecture_of(Robot()), ClosedForm3PRP)
    chain = architecture_of(FamilyRobot.default("3-RPR"))
    assert isinstance(chain, LegChain) and chain.architecture == "3-RPR"
    assert ClosedForm3PRP(Robot()).architecture == "3-PRP"
    for bad in (None, "3-RRR", 1.0):
        with pytest.raises(Prp3Error, match="robot"):
            architecture_of(bad)  # type: ignore[arg-type]
        with pytest.raises(Prp3Error, match="robot"):
            ClosedForm3PRP(bad)  # type: ignore[arg-type]
        with pytest.raises(Prp3Error, match="robot"):
            LegChain(bad)  # type: ignore[arg-type]


def test_refusals_name_the_sample() -> None:
    far = Motion.at_rest([[0.0, 0.0, 0.0], [0.5, 0.0, 0.0]], t=[0.0, 2.5])
    with pytest.raises(UnreachablePoseError) as info:
        solve_stages(LegChain(FamilyRobot.default("3-RRR")), far)
    assert info.value.sample == 1 and info.value.time == 2.5
    singular = Motion.at_rest([[0.0, 0.0, 0.0], [0.0, 0.0, np.pi / 3]], t=[0.0, 1.0])
    with pytest.raises(SingularPoseError) as info:
        solve_stages(ClosedForm3PRP(Robot()), singular)
    assert info.value.sample == 1
    with pytest.raises(Prp3Error, match=r"motion must be a prp3\.Motion"):
        solve_stages(ClosedForm3PRP(Robot()), np.zeros((1, 3)))  # type: ignore[arg-type]
    with pytest.raises(Prp3Error, match="architecture must be a leg architecture"):
        solve_stages(Robot(), far)  # type: ignore[arg-type]


def test_output_rank_follows_the_motion() -> None:
    one = solve_stages(ClosedForm3PRP(Robot()), Motion.at_rest([0.01, 0.02, 0.1]))
    assert one.q.shape == (3, 3) and one.tau.shape == (3,) and one.force.shape == (3, 3, 2)
