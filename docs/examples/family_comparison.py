"""The seven default designs of the family side by side (docs/family_comparison.md quotes it).

Each architecture's default design and actuation (docs/family.md §3) carries
the same payload — 1.5 kg welded to the platform, its centre 2 cm off ``G``
along the platform's ``x`` axis, 2e-3 kg·m² — along the paper's two motions
(eq. 4, 301 samples each), solved by the fast route of the family's inverse
dynamics (``prp3.family.family_inverse_dynamics``).  Printed, as Markdown:

* ``python docs/examples/family_comparison.py``: one row per architecture
  and motion — the peak actuator effort ``max_L |tau_L|`` (N for a driven P
  joint, N·m for a driven R joint) and power ``max_L |p_L|`` (W), the peak
  force ``max_L |(fx_k, fy_k)|`` in each joint ``k`` (N), and the
  singularity margins ``min s·μ_leg`` and ``min s·μ_par`` over the motion
  (docs/family.md §6);
* ``python docs/examples/family_comparison.py --areas``: one row per
  architecture — the reachable and the regular area of the slice ``φ = 0``
  in the window ``|x|, |y| ≤ 0.6 m`` (grid of 121 × 121 points, cells of 1 cm²), and the
  regular areas at ``φ = ±0.3 rad``.

With ``--figures DIR`` it also writes ``DIR/family_comparison.png``
(:func:`prp3.plotting.family_design.comparison_figure`).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from prp3 import (
    ARCHITECTURES,
    FamilyRobot,
    Payload,
    family_inverse_dynamics,
    family_workspace_slice,
    paper_motion,
)

PAYLOAD = Payload(1.5, (0.02, 0.0), 2e-3)
MOTIONS = ("vertical", "rotation")
SAMPLES = 301
WINDOW = np.linspace(-0.6, 0.6, 121)


def robots() -> list[FamilyRobot]:
    """The default designs with the payload."""
    from dataclasses import replace

    return [replace(FamilyRobot.default(a), payload=PAYLOAD) for a in ARCHITECTURES]


def rows() -> list[dict[str, object]]:
    """One dict per architecture and motion: the peaks and the margins."""
    found = []
    for robot in robots():
        home_leg, home_par = robot.home_measures
        for name in MOTIONS:
            solution = family_inverse_dynamics(robot, paper_motion(name, SAMPLES))
            force = np.hypot(solution.force[..., 0], solution.force[..., 1])  # (N, legs, joints)
            kin = solution.kinematics
            found.append(
                {
                    "architecture": robot.architecture,
                    "actuated": robot.actuated,
                    "unit": "N" if robot.types[robot.actuated - 1] == "P" else "N m",
                    "motion": name,
                    "tau": float(np.abs(solution.tau).max()),
                    "power": float(np.abs(solution.power).max()),
                    "force": [float(force[..., k].max()) for k in range(3)],
                    "mu_leg": float((np.sign(home_leg) * kin.mu_leg).min()),
                    "mu_par": float((np.sign(home_par) * kin.mu_par).min()),
                }
            )
    return found


def areas() -> list[dict[str, object]]:
    """One dict per architecture: reachable and regular areas (m²) in the window."""
    found = []
    for robot in robots():
        ws = family_workspace_slice(robot, 0.0, WINDOW, WINDOW)
        turned = [family_workspace_slice(robot, p, WINDOW, WINDOW).regular_area
                  for p in (-0.3, 0.3)]  # fmt: skip
        found.append({"architecture": robot.architecture, "reachable": ws.area,
                      "regular": ws.regular_area, "turned": turned})  # fmt: skip
    return found


def table(found: list[dict[str, object]]) -> str:
    lines = [
        "| architecture | motion | peak effort | peak power (W) | peak F1 (N) | peak F2 (N) "
        "| peak F3 (N) | min μ_leg | min μ_par |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for row in found:
        f1, f2, f3 = row["force"]  # type: ignore[misc]
        lines.append(
            f"| {row['architecture']} ({row['actuated']}) | {row['motion']} "
            f"| {row['tau']:.4g} {row['unit']} | {row['power']:.4g} | {f1:.4g} | {f2:.4g} "
            f"| {f3:.4g} | {row['mu_leg']:.3f} | {row['mu_par']:.3f} |"
        )
    return "\n".join(lines)


def area_table(found: list[dict[str, object]]) -> str:
    lines = [
        "| architecture | reachable at φ = 0 (m²) | regular at φ = 0 (m²) "
        "| regular at φ = −0.3 (m²) | regular at φ = 0.3 (m²) |",
        "|---|---|---|---|---|",
    ]
    for row in found:
        low, high = row["turned"]  # type: ignore[misc]
        lines.append(
            f"| {row['architecture']} | {row['reachable']:.4g} | {row['regular']:.4g} "
            f"| {low:.4g} | {high:.4g} |"
        )
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--areas", action="store_true", help="print the table of areas")
    parser.add_argument("--figures", type=Path, help="write DIR/family_comparison.png")
    args = parser.parse_args()
    if args.areas:
        print(area_table(areas()))
        return
    found = rows()
    print(table(found))
    if args.figures is not None:
        from prp3.plotting import comparison_figure, save_figure

        save_figure(comparison_figure(found, areas()), args.figures / "family_comparison.png")


if __name__ == "__main__":
    main()
