"""The table of tracking errors of docs/control.md: plants × controllers, prp3 plant.

The paper's motion (eq. 4, 3 s) at 1 kHz with the default gains (KP = 400
1/s², KD = 40 1/s); the controller's model is always the paper's robot; the
plant, whose actuators have the stroke ``[-0.1, 0.1] m`` (twice what the
motions need), is

* ``exact model``: the paper's robot;
* ``20 % mass error``: every mass and inertia of the plant 20 % above the
  model's (m1, m2, m3, I2, I3 × 1.2);
* ``0.5 kg unknown payload``: a payload of 0.5 kg with ``I_zz = 1e-3 kg·m²``
  fixed at ``G``, unknown to the model: the plant's platform is ``m3 + 0.5 kg``
  and ``I3 + 1e-3 kg·m²`` (exactly a ``[payload]`` at ``com = [0, 0]``).

Each cell is the largest ``|x_ref − x|, |y_ref − y|`` (m) and ``|φ_ref − φ|``
(rad) over the run; a run that stops early says when.  Prints a Markdown table.

By default only the prp3 plant runs (about 20 s: what ``tests/test_docs.py``
compares with docs/control.md); ``--plants prp3,mujoco`` adds the MuJoCo plant's
column (about 2 minutes; ``python benchmarks/control_table.py`` runs that).
The two plants agree to about 1e-9 along these loops (``tests/test_control.py``
holds them to 1e-8), so the columns are the same to the digits printed.

``--open-loop`` prints instead why feedback is needed (a few seconds): the
growth rate of the robot held at rest by constant forces
(``prp3.analysis.equations_of_motion.open_loop_growth_rate``) at the central pose and at the poses
of the paper's two motions (every 0.1 s), and how far the exact forces of the
rotation motion, applied open loop (feed-forward, 1 kHz hold, no stroke), take
the platform off its path.

Run from anywhere: ``python docs/examples/control_table.py [--motion vertical]``.
"""

from __future__ import annotations

import argparse

import numpy as np

import prp3
from prp3 import (
    PAPER_DURATION,
    PAPER_MOTIONS,
    Limits,
    LinkParameters,
    PistonParameters,
    PlatformParameters,
    Robot,
    Tracking,
    control_times,
    law_at,
    open_loop_growth_rate,
    track,
)

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
CONTROLLERS = {"pd": "PD", "feedforward": "feedforward", "computed-torque": "computed torque"}
#: How a cell says why a run stopped early.
_STOPS = {"stroke": "leaves the stroke", "singular": "reaches the singularity",
          "failed": "fails"}  # fmt: skip


def _e(value: float) -> str:
    """Two significant digits: ``0.019`` above 0.01, ``1.3e-06`` below."""
    return f"{value:.2g}" if value >= 0.01 else f"{value:.1e}"


def _cell(run: Tracking) -> str:
    position = max(float(run.max_error[0]), float(run.max_error[1]))
    text = f"{_e(position)} m, {_e(float(run.max_error[2]))} rad"
    if run.status != "completed":
        text += f" ({_STOPS[run.status]} at {float(run.t[-1]):.2f} s)"
    return text


def open_loop() -> None:
    """Why open loop fails: the growth rate, and the feed-forward run without a stroke."""
    central = open_loop_growth_rate(PAPER, [0.0, 0.0, 0.0])
    rates = [
        open_loop_growth_rate(PAPER, pose)
        for name in PAPER_MOTIONS
        for pose in prp3.paper_motion(name, samples=31).pose
    ]
    print(f"growth rate held at rest: {central:.1f} 1/s at the central pose, "
          f"{min(rates):.1f} to {max(rates):.1f} 1/s at the poses of the paper's motions")  # fmt: skip
    reference = law_at(PAPER_MOTIONS["rotation"], control_times(0.0, PAPER_DURATION, 1000.0))
    run = track(PAPER, reference, controller="feedforward", plant="prp3")
    print("feed-forward, exact forces, 1 kHz hold, rotation motion, no stroke:")
    for until in (0.5, 1.0, 1.5):
        phi = float(np.abs(run.error[run.t <= until + 1e-9, 2]).max())
        print(f"  max |phi_ref - phi| up to {until:g} s: {_e(phi)} rad")
    print(f"  stops at {float(run.t[-1]):.3f} s: {run.status}")


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--motion", choices=tuple(PAPER_MOTIONS), default="rotation")
    parser.add_argument("--plants", default="prp3", help="prp3, mujoco or prp3,mujoco")
    parser.add_argument("--open-loop", action="store_true", help="why feedback is needed")
    args = parser.parse_args()
    if args.open_loop:
        open_loop()
        return
    engines = args.plants.split(",")
    if not set(engines) <= {"prp3", "mujoco"}:
        parser.error(f"--plants {args.plants!r}: give prp3, mujoco or prp3,mujoco")
    reference = law_at(PAPER_MOTIONS[args.motion], control_times(0.0, PAPER_DURATION, 1000.0))
    print("| plant | controller | " + " | ".join(f"{e} plant" for e in engines) + " |")
    print("|---|---|" + "---|" * len(engines))
    for name, plant in PLANTS.items():
        for controller, label in CONTROLLERS.items():
            cells = []
            for engine in engines:
                run = track(plant, reference, controller=controller, plant=engine, model=PAPER)  # type: ignore[arg-type]
                cell = _cell(run)
                cells.append(
                    f"**{cell}**"
                    if name == "exact model" and controller == "computed-torque"
                    else cell
                )
            print(f"| {name} | {label} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
