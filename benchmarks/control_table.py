#!/usr/bin/env python
"""The table of tracking errors of ``docs/control.md``: models × controllers × plants.

Run from the repository root (MuJoCo optional: its columns are skipped without it)::

    python benchmarks/control_table.py            # the paper's rotation motion, ~2 minutes
    python benchmarks/control_table.py --motion vertical

For the paper's motion at 1 kHz, default gains (KP = 400 1/s², KD = 40 1/s),
the controller's model is always the paper's robot; the plant, whose
actuators have the stroke ``[-0.1, 0.1] m`` (twice what the motions need), is

* ``exact``: the paper's robot;
* ``20 % mass error``: every mass and inertia of the plant 20 % above the
  model's (m1, m2, m3, I2, I3 × 1.2);
* ``0.5 kg payload``: a payload of 0.5 kg with ``I_zz = 1e-3 kg·m²`` fixed at
  ``G``, unknown to the model: the plant's platform is ``m3 + 0.5 kg`` and
  ``I3 + 1e-3 kg·m²`` (exactly a ``[payload]`` at ``com = [0, 0]``);

and each cell is the largest ``|x_ref − x|, |y_ref − y|`` (m) and
``|φ_ref − φ|`` (rad) over the run; a run that stops early (open loop reaching
the singularity) says when.  Prints a Markdown table.
"""

from __future__ import annotations

import argparse
import sys

import prp3
from prp3 import Limits, LinkParameters, PistonParameters, PlatformParameters, Robot
from prp3.control import Tracking, control_times, law_at, track
from prp3.motion import PAPER_DURATION, PAPER_MOTIONS

PAPER = Robot()
#: Actuator strokes of every plant (m): twice what the motions need; a run that
#: leaves them stops (open loop would otherwise report errors of metres).
STROKE = Limits(stroke=(-0.1, 0.1))
#: The plants of the table; the controller's model is always the paper's robot.
PLANTS: dict[str, Robot] = {
    "exact model": Robot(limits=STROKE),
    "20 % mass error": Robot(
        limits=STROKE,
        piston=PistonParameters(mass=1.2 * PAPER.piston.mass),
        link=LinkParameters(mass=1.2 * PAPER.link.mass, inertia=1.2 * PAPER.link.inertia),
        platform=PlatformParameters(
            mass=1.2 * PAPER.platform.mass, inertia=1.2 * PAPER.platform_inertia
        ),
    ),
    "0.5 kg unknown payload": Robot(
        limits=STROKE,
        platform=PlatformParameters(
            mass=PAPER.platform.mass + 0.5, inertia=PAPER.platform_inertia + 1e-3
        ),
    ),
}
CONTROLLERS = ("pd", "feedforward", "computed-torque")


def _cell(run: Tracking) -> str:
    position = max(float(run.max_error[0]), float(run.max_error[1]))
    text = f"{position:.2g} m, {float(run.max_error[2]):.2g} rad"
    if run.status != "completed":
        text += f" (stops at {float(run.t[-1]):.2f} s: {run.status})"
    return text


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--motion", choices=tuple(PAPER_MOTIONS), default="rotation")
    parser.add_argument("--rate", type=float, default=1000.0)
    args = parser.parse_args()
    reference = law_at(PAPER_MOTIONS[args.motion], control_times(0.0, PAPER_DURATION, args.rate))
    engines = ["prp3"]
    try:
        import mujoco  # noqa: F401

        engines.append("mujoco")
    except ImportError:
        print("MuJoCo not installed: its column is skipped", file=sys.stderr)
    print(
        f"{args.motion} motion, {args.rate:g} Hz, KP = 400 1/s², KD = 40 1/s, prp3 {prp3.__version__}"
    )
    print()
    print("| plant | controller | " + " | ".join(f"{e} plant" for e in engines) + " |")
    print("|---|---|" + "---|" * len(engines))
    for name, plant in PLANTS.items():
        for controller in CONTROLLERS:
            cells = [
                _cell(track(plant, reference, controller=controller, plant=engine, model=PAPER))  # type: ignore[arg-type]
                for engine in engines
            ]
            print(f"| {name} | {controller} | " + " | ".join(cells) + " |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
