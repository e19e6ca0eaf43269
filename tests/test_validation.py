"""One validation layer: every public function refuses the same bad values the same way.

A parametrised test over every public function that takes arrays × every
kind of bad value (booleans, text, ``None``, an integer beyond float64, a
masked array, a wrong shape, NaN, infinity): each is refused with a
:class:`~prp3.errors.Prp3Error` whose message names the argument and says the
same thing everywhere (it comes from :mod:`prp3.validation`).  Before this
layer ``forward_geometry``, ``fast.paper_forces``, ``fast.sample_forces``,
``reachable`` and ``jacobian_condition`` accepted booleans or text that
``inverse_geometry`` refused.

The Jacobian condition number near the singularity is checked against
50-digit singular values (mpmath), independent of prp3's closed form.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import prp3
from prp3 import Motion, Robot
from prp3.engines.compiled_robot import compile_robot
from prp3.errors import Prp3Error
from prp3.pose_validation import check_poses
from prp3.validation import check_real

ROBOT = Robot()
COMPILED = compile_robot(ROBOT)
ZERO = np.zeros(3)
SMALL = np.array([0.01, -0.02, 0.1])
FORCES = prp3.ActuatorForces(t=[0.0, 1.0], f10=np.zeros((2, 3)))


def _bad(kind: str, good: np.ndarray) -> Any:
    """``good`` spoilt in the way ``kind`` says."""
    if kind == "booleans":
        return good.astype(bool)
    if kind == "text":
        return good.astype(str)
    if kind == "None":
        return None
    if kind == "huge integer":
        values: Any = good.astype(int).tolist()
        if good.ndim == 1:
            values[-1] = 10**400
        else:
            values[-1][-1] = 10**400
        return values
    if kind == "masked array":
        return np.ma.masked_array(good, mask=np.ones(good.shape, dtype=bool))
    if kind == "wrong shape":
        return good[..., :2]
    spoilt = good.astype(float).copy()
    spoilt.reshape(-1)[-1] = {"nan": math.nan, "infinity": math.inf}[kind]
    return spoilt


#: What every refusal of each kind says.
FRAGMENTS = {
    "booleans": "must be an array of real numbers, got booleans",
    "text": "must be an array of real numbers, got text",
    "None": "must be an array of real numbers, got None",
    "huge integer": "must be an array of real numbers, got an integer too large for float64",
    "masked array": "is a masked array: not accepted",
    "wrong shape": "must have shape",
    "nan": "is not finite (nan)",
    "infinity": "is not finite (inf)",
}

#: name -> (argument name, good value, call with the value)
CALLS: dict[str, tuple[str, np.ndarray, Callable[[Any], object]]] = {
    "inverse_geometry": ("pose", SMALL, lambda v: prp3.inverse_geometry(ROBOT, v)),
    "forward_geometry": ("lambda10", ZERO, lambda v: prp3.forward_geometry(ROBOT, v)),
    "forward_velocity(pose)": ("pose", SMALL, lambda v: prp3.forward_velocity(ROBOT, v, ZERO)),
    "forward_velocity(rates)": (
        "dlambda10",
        ZERO,
        lambda v: prp3.forward_velocity(ROBOT, SMALL, v),
    ),
    "forward_acceleration": (
        "ddlambda10",
        ZERO,
        lambda v: prp3.forward_acceleration(ROBOT, SMALL, ZERO, v),
    ),
    "forward_kinematics": (
        "lambda10",
        ZERO,
        lambda v: prp3.forward_kinematics(ROBOT, 0.0, v, ZERO, ZERO),
    ),
    "platform_dynamics": ("velocity", ZERO, lambda v: prp3.platform_dynamics(ROBOT, SMALL, v)),
    "forward_dynamics": (
        "initial_velocity",
        ZERO,
        lambda v: prp3.forward_dynamics(ROBOT, FORCES, [0.0, 1.0], SMALL, v),
    ),
    "ActuatorForces": (
        "f10",
        np.zeros((2, 3)),
        lambda v: prp3.ActuatorForces(t=[0.0, 1.0], f10=v),
    ),
    "Motion": (
        "velocity",
        ZERO,
        lambda v: Motion(t=0.0, pose=SMALL, velocity=v, acceleration=ZERO),
    ),
    "Motion.at_rest": ("pose", SMALL, lambda v: Motion.at_rest(v)),
    "law_motion": ("amplitude", SMALL, lambda v: prp3.law_motion(v)),
    "paper_forces": ("pose", SMALL, lambda v: prp3.paper_forces(ROBOT, v, ZERO, ZERO)),
    "paper_forces(acceleration)": (
        "acceleration",
        ZERO,
        lambda v: prp3.paper_forces(COMPILED, SMALL, ZERO, v),
    ),
    "sample_forces": ("pose", SMALL, lambda v: prp3.sample_forces(COMPILED, v, ZERO, ZERO)),
    "sample_forces(velocity)": (
        "velocity",
        ZERO,
        lambda v: prp3.sample_forces(COMPILED, SMALL, v, ZERO),
    ),
    "reachable": ("pose", SMALL, lambda v: prp3.reachable(ROBOT, v)),
    "jacobian_condition": ("pose", SMALL, lambda v: prp3.jacobian_condition(ROBOT, v)),
    "platform_vertices": ("pose", SMALL, lambda v: prp3.platform_vertices(ROBOT, v)),
}


@pytest.mark.parametrize("kind", list(FRAGMENTS))
@pytest.mark.parametrize("name", list(CALLS))
def test_every_public_function_refuses_every_bad_value_alike(name: str, kind: str) -> None:
    argument, good, call = CALLS[name]
    call(good)  # the good value is accepted
    with pytest.raises(Prp3Error) as info:
        call(_bad(kind, good))
    message = str(info.value)
    assert FRAGMENTS[kind] in message, message
    assert argument in message, message
    assert "\n" not in message


@pytest.mark.parametrize(
    "call",
    [
        lambda: prp3.inverse_geometry(None, ZERO),
        lambda: prp3.forward_geometry("robot", ZERO),
        lambda: prp3.reachable(None, ZERO),
        lambda: prp3.jacobian_condition(None, ZERO),
        lambda: prp3.workspace_slice(None, 0.1, [0.0, 1.0], [0.0, 1.0]),
        lambda: prp3.orientation_range(None),
        lambda: prp3.platform_vertices(None, ZERO),
        lambda: prp3.forward_dynamics(None, FORCES, [0.0, 1.0], SMALL, ZERO),
    ],
)
def test_a_missing_robot_is_refused_alike(call: Callable[[], object]) -> None:
    with pytest.raises(prp3.ParameterError, match=r"robot must be a prp3\.Robot, got None|'robot'"):
        call()


@pytest.mark.parametrize("value", [True, "0.1", None, 10**400, math.nan])
def test_scalar_arguments_are_refused_alike(value: object) -> None:
    for call in (
        lambda: prp3.workspace_slice(ROBOT, value, [0.0, 1.0], [0.0, 1.0]),  # type: ignore[arg-type]
        lambda: prp3.law_motion(SMALL, 5, value),  # type: ignore[arg-type]
        lambda: prp3.forward_dynamics(ROBOT, FORCES, [0.0, 1.0], SMALL, ZERO, rtol=value),  # type: ignore[arg-type]
    ):
        with pytest.raises(Prp3Error, match=r"must be a (finite )?number|too large for float64"):
            call()


def test_errors_carry_their_location_as_fields() -> None:
    poses = np.zeros((4, 3))
    poses[2] = [0.01, 0.02, math.pi / 3]
    with pytest.raises(prp3.SingularPoseError) as info:
        check_poses(poses)
    error = info.value
    assert (error.subject, error.sample, error.pose) == ("pose", 2, (0.01, 0.02, math.pi / 3))
    moved = error.located(file="traj.csv", line=7, time=0.5, subject=None)
    assert str(moved).startswith("traj.csv:7: sample 2, t = 0.5 s: singular pose (x=0.01")
    assert (moved.file, moved.line, moved.sample) == ("traj.csv", 7, 2)
    assert str(error).startswith("pose: sample 2: singular pose")  # the original is unchanged
    with pytest.raises(prp3.TrajectoryError) as bad:
        check_real("t", np.ma.masked_array([1.0]))
    assert bad.value.args == (str(bad.value),)


# ------------------------------------------------ Jacobian conditioning near singularity
def _kappa_mp(robot: Robot, pose: tuple[float, float, float]) -> float:
    """κ of ``J·diag(1, 1, 1/l0)`` from 50-digit arithmetic: λ10 of the closure (eq. 10) by
    Cramer's rule, J by mpmath's differentiation, κ by its singular values."""
    mpmath = pytest.importorskip("mpmath")
    mp = mpmath.mp
    mp.dps = 50
    l0 = mp.mpf(robot.l0)
    s3 = mp.sqrt(3)
    alpha = [mp.pi / 3, mp.pi, -mp.pi / 3]
    base = [(0, -l0), (s3 / 2 * l0, l0 / 2), (-s3 / 2 * l0, l0 / 2)]
    c = (l0 / 2 / s3, l0 / 2)

    def lam(i: int, x: Any, y: Any, phi: Any) -> Any:
        e = (mp.cos(alpha[i]), mp.sin(alpha[i]))
        theta = alpha[i] + phi
        d = (mp.cos(theta - mp.pi / 3), mp.sin(theta - mp.pi / 3))
        rc = (
            mp.cos(theta) * c[0] - mp.sin(theta) * c[1],
            mp.sin(theta) * c[0] + mp.cos(theta) * c[1],
        )
        r = (x - base[i][0] - rc[0], y - base[i][1] - rc[1])
        return (r[0] * d[1] - r[1] * d[0]) / (e[0] * d[1] - e[1] * d[0]) - l0 / s3

    q = [mp.mpf(v) for v in pose]
    rows = []
    for i in range(3):
        row = []
        for k in range(3):

            def f(t: Any, k: int = k, i: int = i) -> Any:
                args = list(q)
                args[k] = t
                return lam(i, *args)

            row.append(mp.diff(f, q[k]) / (l0 if k == 2 else 1))
        rows.append(row)
    sigma = mpmath.svd_r(mpmath.matrix(rows), compute_uv=False)
    values = sorted(float(sigma[k]) for k in range(3))
    return values[-1] / values[0]


@pytest.mark.parametrize("offset", [1.5e-4, -1.5e-4, 3e-4, -1e-3])
@pytest.mark.parametrize("singular", [math.pi / 3, -2 * math.pi / 3])
@pytest.mark.parametrize("xy", [(0.0, 0.0), (0.02, -0.03)])
def test_jacobian_condition_is_accurate_next_to_the_singularity(
    offset: float, singular: float, xy: tuple[float, float]
) -> None:
    # was: a closed form with a cancelling μ− = (a·b − |v|²)/μ+: 28 % wrong, inf or nan here
    pose = (xy[0], xy[1], singular + offset)
    kappa = float(prp3.jacobian_condition(ROBOT, pose))
    reference = _kappa_mp(ROBOT, pose)
    assert math.isfinite(kappa)
    assert abs(kappa - reference) <= 1e-8 * reference, (kappa, reference)


def test_jacobian_condition_is_still_sqrt6_at_the_centre() -> None:
    assert abs(float(prp3.jacobian_condition(ROBOT, ZERO)) - math.sqrt(6.0)) < 1e-14
    assert abs(_kappa_mp(ROBOT, (0.0, 0.0, 0.0)) - math.sqrt(6.0)) < 1e-12


# ------------------------------------------------- one sample: the fast pass and the exact checks
_EDGES = (
    0.0, -0.0, 1e-300, 0.01, -0.3, 1.5, 1e308, -1e308, math.nan, math.inf, -math.inf,
    30.0, -30.0, math.nextafter(30.0, 31.0), 100.0, -100.0, math.nextafter(100.0, 101.0),
    math.pi / 3.0, -2.0 * math.pi / 3.0, math.pi / 3.0 - 1.5e-4, math.pi / 3.0 - 2e-4,
    math.pi / 3.0 + 1e-4, -2.0 * math.pi / 3.0 + 2e-4, -2.0 * math.pi / 3.0 - 9e-5,
    4.0 * math.pi / 3.0 + 1e-4, 99.0,
)  # fmt: skip


def _numbers() -> Any:
    from hypothesis import strategies as st

    edge = st.sampled_from(_EDGES)
    real = st.one_of(edge, st.floats(-200.0, 200.0), st.floats(allow_nan=True))
    return st.one_of(
        real,
        real.map(np.float64),
        st.floats(-200.0, 200.0, width=32).map(np.float32),
        st.integers(-200, 200),
        st.sampled_from([10**400, True, False, np.int64(3), np.bool_(True), "1.0", None, 1j]),
    )


def _three() -> Any:
    from hypothesis import strategies as st

    exact = st.lists(_numbers(), min_size=3, max_size=3)
    values = st.one_of(exact, exact, st.lists(_numbers(), min_size=2, max_size=4))

    def container(items: list[Any], kind: str) -> Any:
        if kind == "tuple":
            return tuple(items)
        if kind == "list":
            return items
        try:
            return np.array(items, dtype=np.float64 if kind == "float64" else None)
        except (TypeError, ValueError, OverflowError):
            return tuple(items)

    kinds = st.sampled_from(["tuple", "list", "float64", "array"])
    return st.builds(container, values, kinds)


def _outcome(call: Callable[[], object]) -> tuple[Any, ...]:
    try:
        result = call()
    except Prp3Error as error:
        return ("refused", type(error), str(error))
    assert isinstance(result, tuple) and all(type(value) is float for value in result)
    return ("accepted", tuple(map(repr, result)))


def test_one_sample_is_accepted_and_refused_as_the_exact_checks_do() -> None:
    # the fast pass of check_state_sample accepts only what the exact checks accept,
    # returns the same floats, and leaves every refusal to them (the same message)
    from hypothesis import given, settings
    from hypothesis import strategies as st

    from prp3.pose_validation import check_state_sample, exact_state

    @settings(max_examples=200)
    @given(_three(), _three(), _three(), st.sampled_from([None, ROBOT]))
    def agree(pose: Any, velocity: Any, acceleration: Any, robot: Robot | None) -> None:
        fast = _outcome(lambda: check_state_sample(pose, velocity, acceleration, robot))
        exact = _outcome(lambda: exact_state(pose, velocity, acceleration, robot))
        assert fast == exact

    agree()


def test_one_sample_load_is_accepted_and_refused_as_check_load_does() -> None:
    # the load's fast pass of the single-sample entries accepts only what check_load
    # accepts, returns the same floats, and leaves every refusal to it (the same message)
    from hypothesis import given, settings

    from prp3.engines.entries import check_load
    from prp3.engines.sample_entries import check_load_sample

    def exact(load: Any) -> tuple[float, ...]:
        return tuple(check_load(load, (3,)).tolist())

    @settings(max_examples=300)
    @given(_three())
    def agree(load: Any) -> None:
        assert _outcome(lambda: check_load_sample(load)) == _outcome(lambda: exact(load))

    agree()
