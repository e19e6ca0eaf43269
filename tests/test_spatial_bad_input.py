"""Bad input, round four, for the spatial robots (issue 33).

Absurd efforts in the spatial forward dynamics are refused up front from the equations
of motion (docs/spatial.md §18); hostile values on the spatial commands end in one line on
stderr, exit 2, and leave the output folder as it was.
"""

from __future__ import annotations

import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from clitools import cli, listing, one_line
from prp3.errors import ParameterError
from prp3.spatial.forward import MAX_ACCELERATION, hold_efforts, spatial_forward_dynamics
from prp3.spatial.model import delta, hexapod, three_rps

ROBOTS = {"6-UPS": hexapod, "3-RPS": three_rps, "3-RUU": delta}


def _robot_file(folder: Path, architecture: str) -> Path:
    path = folder / f"{architecture}.toml"
    path.write_text(f'architecture = "{architecture}"\n', encoding="utf-8")
    return path


def _efforts_csv(path: Path, rows: list[list[float]], legs: int) -> Path:
    head = ",".join(["t"] + [f"tau_{i + 1}" for i in range(legs)])
    body = [",".join(repr(float(v)) for v in row) for row in rows]
    path.write_text("\n".join([head, *body]) + "\n", encoding="utf-8")
    return path


@pytest.mark.parametrize("architecture", sorted(ROBOTS))
@pytest.mark.parametrize("push", [1e6, 1e20, 1e308, -1e308])
def test_absurd_efforts_are_refused_before_the_integration(architecture, push):
    robot = ROBOTS[architecture]()
    began = time.monotonic()
    with pytest.raises(ParameterError, match="beyond the bound") as refused:
        spatial_forward_dynamics(robot, hold_efforts(robot) + push, duration=0.1, samples=3)
    assert time.monotonic() - began < 30.0
    assert "the effort of leg 1 is" in str(refused.value)
    assert refused.value.key == "efforts"


def test_the_bound_is_the_acceleration_of_the_equations_of_motion():
    """Efforts just below and above the bound (from ``a_f = A⁻¹(τ − h)`` by an independent
    finite difference of the inverse dynamics: the efforts are affine in ``a_f``)."""
    robot = hexapod()
    hold = hold_efforts(robot)
    # a uniform push of s N on every leg lifts the platform: the vertical acceleration is
    # s·6·(dτ/da_z)⁻¹-ish; measure it from a small push's integration instead of the code
    small = spatial_forward_dynamics(robot, hold + 1.0, duration=1e-4, samples=2)
    rate = float(np.abs(np.concatenate([small.motion.alpha[0], small.motion.acceleration[0]])).max())
    below = 0.5 * MAX_ACCELERATION / rate
    spatial_forward_dynamics(robot, hold + below, duration=1e-6, samples=2)  # accepted
    with pytest.raises(ParameterError, match="beyond the bound"):
        spatial_forward_dynamics(robot, hold + 2.0 * MAX_ACCELERATION / rate, duration=1e-6)


@pytest.mark.parametrize("push", [1e6, 1e20, 1e308])
def test_prp3_forward_refuses_absurd_efforts_naming_the_file(capsys, tmp_path, push):
    robot_file = _robot_file(tmp_path, "3-RUU")
    hold = hold_efforts(delta())
    table = _efforts_csv(tmp_path / "push.csv", [[0.0, *(hold + push)], [0.1, *(hold + push)]], 3)
    out = tmp_path / "out"
    began = time.monotonic()
    status, _, err = cli(capsys, "forward", "--robot", robot_file, "--efforts", table,
                         "--output", out)  # fmt: skip
    assert time.monotonic() - began < 60.0
    assert status == 2
    line = one_line(err)
    assert "push.csv" in line and "beyond the bound" in line and repr(float(hold[0] + push)) in line
    assert not out.exists()


def test_a_callable_turning_absurd_stops_naming_the_time():
    robot = three_rps()
    hold = hold_efforts(robot)

    def efforts(t: float) -> np.ndarray:
        return hold + (1e300 if t > 1e-3 else 0.0)

    began = time.monotonic()
    with pytest.raises(Exception, match=r"at t = .* s, not below") as refused:
        spatial_forward_dynamics(robot, efforts, duration=0.01, samples=3)
    assert time.monotonic() - began < 60.0
    assert type(refused.value).__module__ == "prp3.errors"
