"""The drift table of docs/forward_and_workspace.md: inverse dynamics → forces → forward dynamics.

For each of the paper's two motions (eq. 4, 3 s), the forces of the inverse
dynamics drive ``prp3.analysis.forward.forward_dynamics`` from the motion's initial
state, open loop; the error is the largest difference of pose and velocity
between the integrated and the planned motion over the 301 output samples,
``max |Δ(x, y, φ, ẋ, ẏ, φ̇)|`` (m, rad, m/s, rad/s mixed, as the table says).

Run from anywhere: ``python docs/examples/drift.py``; it prints the table as
the document has it (``tests/test_docs.py`` compares the two).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

import prp3
from prp3 import (
    PAPER_MOTIONS,
    ActuatorForces,
    compile_robot,
    forward_dynamics,
    law_at,
    sample_actuator_forces,
)

T = np.linspace(0.0, 3.0, 301)


def _planned(name: str, samples: int = 301) -> tuple[prp3.Motion, np.ndarray]:
    motion = prp3.paper_motion(name, samples=samples)
    return motion, prp3.inverse_dynamics(prp3.Robot(), motion)[1].f10


def _exact_forces(name: str) -> Callable[[float], np.ndarray]:
    """``f10(t)`` of the inverse dynamics at any ``t`` (eq. 4 evaluated there)."""
    compiled = compile_robot(prp3.Robot())
    star = PAPER_MOTIONS[name]

    def f10(t: float) -> np.ndarray:
        one = law_at(star, np.array([t]))
        return np.asarray(sample_actuator_forces(compiled, one.pose[0], one.velocity[0],
                                                 one.acceleration[0]))  # fmt: skip

    return f10


def _error(name: str, forces: object, rtol: float, atol: float) -> tuple[float, np.ndarray]:
    plan, _ = _planned(name)
    run = forward_dynamics(prp3.Robot(), forces, T, plan.pose[0], plan.velocity[0],  # type: ignore[arg-type]
                           rtol=rtol, atol=atol)  # fmt: skip
    assert run.status == "completed", run.message
    diff = np.abs(np.concatenate([run.motion.pose - plan.pose,
                                  run.motion.velocity - plan.velocity], axis=1)).max(axis=1)  # fmt: skip
    return float(diff.max()), diff


def _e(value: float) -> str:
    """``2.2e-5``: two digits, the exponent without padding (the document's style)."""
    mantissa, exponent = f"{value:.1e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def main() -> None:
    rows = []
    for label, rtol, atol in (("exact `f10(t)` (inverse dynamics at every `t`)", 1e-10, 1e-12),
                              ("exact `f10(t)`", 1e-10, 1e-14),
                              ("exact `f10(t)`", 1e-12, 1e-14)):  # fmt: skip
        cells = [_e(_error(name, _exact_forces(name), rtol, atol)[0])
                 for name in ("vertical", "rotation")]  # fmt: skip
        tol = f"`{rtol:g}`, `{atol:g}`" + (" (defaults)" if atol == 1e-12 else "")
        rows.append(f"| {label} | {tol} | {cells[0]} | {cells[1]} |")
    for samples, label in ((301, "spline through 301 samples (`results.csv` of `prp3 simulate`)"),
                           (3001, "spline through 3001 samples")):  # fmt: skip
        cells = []
        for name in ("vertical", "rotation"):
            plan, f10 = _planned(name, samples)
            worst, diff = _error(name, ActuatorForces(plan.t, f10), 1e-10, 1e-12)
            cells.append(f"{_e(worst)} at `t = {T[int(np.argmax(diff))]:g} s`")
        rows.append(f"| {label} | defaults | {cells[0]} | {cells[1]} |")
    print("| forces | `rtol`, `atol` | vertical | rotation |")
    print("|---|---|---|---|")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
