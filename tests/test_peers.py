"""The benchmark's peer engines (``benchmarks/peers.py``) against prp3.

Each peer (MuJoCo, Pinocchio) solves the closed-chain inverse dynamics of its
own tree model; its actuator forces must equal prp3's ``f10`` (verified
elsewhere against an independent Newton–Euler solution) to 1e-8 of the largest
``|f10|`` of the motion, on the paper's motions, with default parameters, with
centre-of-mass offsets and another gravity, and on random robots and motions.
Each engine's tests are skipped when it is not installed.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings

from prp3 import LinkParameters, Motion, PistonParameters, PlatformParameters, Robot
from prp3.analysis.inverse_dynamics import inverse_dynamics
from prp3.model.motion import PAPER_MOTIONS, paper_motion
from strategies import AnalyticMotion, scenarios

PEERS_PATH = Path(__file__).resolve().parents[1] / "benchmarks" / "peers.py"


def _load_peers() -> ModuleType:
    name = "prp3_benchmark_peers"
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, PEERS_PATH)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # dataclasses look their module up while being built
    spec.loader.exec_module(module)
    return module


peers = _load_peers()

ROBOTS = {
    "default": Robot(),
    "offset": Robot(
        gravity=(3.0, -7.0),
        piston=PistonParameters(mass=1.2, inertia=0.4, com=(0.05, -0.02)),
        link=LinkParameters(mass=0.6, inertia=1e-3, com=(0.03, 0.04)),
        platform=PlatformParameters(mass=2.5, inertia=0.05),
    ),
    "zero-inertia": Robot(
        link=LinkParameters(inertia=0.0, com=(0.02, -0.01)),
        platform=PlatformParameters(inertia=0.0),
    ),
}
ENGINES = {"mujoco": "MujocoPeer", "pinocchio": "PinocchioPeer"}


def _peer(engine: str, robot: Robot) -> Any:
    pytest.importorskip(engine)
    return getattr(peers, ENGINES[engine])(robot)


def _relative_error(actual: np.ndarray, expected: np.ndarray, robot: Robot) -> float:
    """Largest error over the largest ``|f10|`` (at least 1e-6 N per kg of robot)."""
    mass = 3 * robot.piston.mass + 3 * robot.link.mass + robot.platform.mass
    scale = max(float(np.abs(expected).max()), 1e-6 * mass)
    return float(np.abs(actual - expected).max() / scale)


@pytest.mark.parametrize("motion_name", sorted(PAPER_MOTIONS))
@pytest.mark.parametrize("robot_name", sorted(ROBOTS))
@pytest.mark.parametrize("engine", sorted(ENGINES))
def test_peer_matches_prp3(engine: str, robot_name: str, motion_name: str) -> None:
    robot = ROBOTS[robot_name]
    peer = _peer(engine, robot)
    motion = paper_motion(motion_name, samples=61)
    forces = peer.forces(peer.prepare(motion))
    _, dyn = inverse_dynamics(robot, motion)
    assert forces.shape == (61, 3)
    # measured ≲ 1e-15; MuJoCo with zero inertias written as its floor ≲ 1e-12
    assert _relative_error(forces, dyn.f10, robot) < 1e-8


def test_pinocchio_is_exact_with_zero_inertias() -> None:
    # Pinocchio takes zero inertias as they are: round-off agreement, not just 1e-8
    robot = ROBOTS["zero-inertia"]
    peer = _peer("pinocchio", robot)
    motion = paper_motion("rotation", samples=31)
    _, dyn = inverse_dynamics(robot, motion)
    assert _relative_error(peer.forces(peer.prepare(motion)), dyn.f10, robot) < 1e-13


@pytest.mark.parametrize("engine", sorted(ENGINES))
def test_single_sample_matches_the_loop(engine: str) -> None:
    robot = ROBOTS["offset"]
    peer = _peer(engine, robot)
    prepared = peer.prepare(paper_motion("vertical", samples=21))
    forces = peer.forces(prepared)
    for i in (0, 7, 20):
        q, qd, qdd = peer.single_state(prepared, i)
        assert q.shape == qd.shape == qdd.shape == (9,)
        single = peer.single(q, qd, qdd)
        assert single.shape == (3,)
        np.testing.assert_array_equal(single, forces[i])


@pytest.mark.parametrize("engine", sorted(ENGINES))
def test_single_sample_motion(engine: str) -> None:
    # a one-sample motion (rank 0 time) gives one row of forces (3,)
    robot = Robot()
    peer = _peer(engine, robot)
    motion = Motion.at_rest([0.01, -0.02, 0.1])
    prepared = peer.prepare(motion)
    forces = peer.forces(prepared)
    _, dyn = inverse_dynamics(robot, motion)
    assert forces.shape == (3,)
    np.testing.assert_array_equal(peer.single(*peer.single_state(prepared, 0)), forces)
    assert _relative_error(forces, dyn.f10, robot) < 1e-8


@settings(max_examples=10)
@given(scenario=scenarios())
def test_peers_on_random_robots_and_motions(scenario: tuple[Robot, AnalyticMotion]) -> None:
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 5))
    _, dyn = inverse_dynamics(robot, motion)
    compared = 0
    for peer in peers.available_peers(robot):
        assert _relative_error(peer.forces(peer.prepare(motion)), dyn.f10, robot) < 1e-8
        compared += 1
    if compared == 0:
        pytest.skip("neither mujoco nor pinocchio is installed")


def _imports(name: str) -> bool:
    try:
        importlib.import_module(name)
    except ImportError:
        return False
    return True


def test_available_peers_skips_missing_engines(monkeypatch: pytest.MonkeyPatch) -> None:
    installed = [name for name in sorted(ENGINES) if _imports(name)]
    assert [p.name for p in peers.available_peers(Robot())] == installed
    # an engine that does not import is left out without an error
    monkeypatch.setitem(sys.modules, "pinocchio", None)  # makes `import pinocchio` fail
    monkeypatch.setitem(sys.modules, "mujoco", None)
    assert peers.available_peers(Robot()) == []
