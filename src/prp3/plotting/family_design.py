"""The figure of a design study across architectures (``prp3 sweep --plots``, family form).

Left: every design that carries the task, its regular area at ``φ = 0``
against its peak joint force, one colour and marker per architecture, the
best design of each architecture ringed.  Right: the peak joint force of the
designs of each architecture (a strip per architecture; the failed designs
counted under it).  matplotlib is imported inside the function (Agg, no pyplot).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["comparison_figure", "family_designs_figure"]

_MARKERS = ("o", "s", "^", "D", "v", "P", "X")


def family_designs_figure(columns: Mapping[str, Any], *, title: str = "") -> Figure:
    """The figure of a family design table (the columns of ``designs.parquet``)."""
    from matplotlib.figure import Figure

    architecture = np.asarray(columns["architecture"]).astype(str)
    status = np.asarray(columns["status"]).astype(str)
    force = np.asarray(columns["peak_joint_force"], dtype=np.float64)
    area = np.asarray(columns["regular_area"], dtype=np.float64)
    names = list(dict.fromkeys(architecture.tolist()))
    labels: list[str] = []
    figure = Figure(figsize=(12.0, 5.2), layout="constrained")
    left, right = figure.subplots(1, 2)
    for k, name in enumerate(names):
        mine = architecture == name
        ok = mine & (status == "ok") & np.isfinite(force)
        colour = f"C{k % 10}"
        marker = _MARKERS[k % len(_MARKERS)]
        left.scatter(area[ok], force[ok], s=16, color=colour, marker=marker, alpha=0.7,
                     label=f"{name} ({int(ok.sum())} of {int(mine.sum())})")  # fmt: skip
        if ok.any():
            best = np.flatnonzero(ok)[np.argmin(force[ok])]
            left.scatter(area[best], force[best], s=140, facecolor="none", edgecolor=colour,
                         linewidth=1.8)  # fmt: skip
            jitter = 0.15 * np.sin(np.arange(int(ok.sum())) * 2.399)
            right.scatter(k + jitter, force[ok], s=12, color=colour, marker=marker, alpha=0.7)
        labels.append(f"{name}\n({int(mine.sum() - ok.sum())} failed)")
    left.set_xlabel("regular area at φ = 0 (m², grid count)")
    left.set_ylabel("peak joint force over the task (N)")
    left.set_title("designs that carry the task; ringed: least peak joint force", fontsize=10)
    left.legend(fontsize=8, title="architecture (ok of designs)", title_fontsize=8)
    left.grid(True, color="0.92")
    right.set_xticks(range(len(names)), labels)
    right.set_xlim(-0.6, len(names) - 0.4)
    right.set_ylabel("peak joint force over the task (N)")
    right.set_title("peak joint force per architecture", fontsize=10)
    right.grid(True, axis="y", color="0.92")
    figure.suptitle(title or "Design study across architectures", fontsize=12)
    return figure


def comparison_figure(
    rows: list[dict[str, Any]], areas: list[dict[str, Any]], *, title: str = ""
) -> Figure:
    """The comparison of designs (``docs/examples/family_comparison.py``): four panels.

    Peak joint force per joint (largest over the motions), peak actuator power
    per motion, singularity margins (smallest over the motions), and the
    regular and reachable areas at ``φ = 0``.

    Parameters
    ----------
    rows : list of dict
        One per architecture and motion: ``architecture``, ``motion``,
        ``power``, ``force`` (3 joints), ``mu_leg``, ``mu_par``.
    areas : list of dict
        One per architecture: ``architecture``, ``reachable``, ``regular``.
    """
    from matplotlib.figure import Figure

    names = list(dict.fromkeys(str(r["architecture"]) for r in rows))
    motions = list(dict.fromkeys(str(r["motion"]) for r in rows))
    x = np.arange(len(names))

    def of(name: str, key: str) -> list[Any]:
        return [r[key] for r in rows if r["architecture"] == name]

    figure = Figure(figsize=(13.0, 8.4), layout="constrained")
    axes = figure.subplots(2, 2)
    ax = axes[0, 0]
    for k in range(3):
        peaks = [max(f[k] for f in of(n, "force")) for n in names]
        ax.bar(x + (k - 1) * 0.27, peaks, 0.27, label=f"joint {k + 1}", color=f"C{k}")
    ax.set_ylabel("peak |F| over both motions (N)")
    ax.set_title("peak force in each joint (largest of the legs)", fontsize=10)
    ax.legend(fontsize=8)
    ax = axes[0, 1]
    for m, motion in enumerate(motions):
        peaks = [next(r["power"] for r in rows if r["architecture"] == n and r["motion"] == motion)
                 for n in names]  # fmt: skip
        ax.bar(x + (m - 0.5) * 0.4, peaks, 0.4, label=f"{motion} motion", color=f"C{m + 3}")
    ax.set_ylabel("peak |p| (W)")
    ax.set_title("peak actuator power (largest of the legs)", fontsize=10)
    ax.legend(fontsize=8)
    ax = axes[1, 0]
    legs = [min(of(n, "mu_leg")) for n in names]
    parallel = [min(of(n, "mu_par")) for n in names]
    ax.bar(x - 0.2, legs, 0.4, label="min s·μ_leg", color="C5")
    ax.bar(x + 0.2, parallel, 0.4, label="min s·μ_par", color="C6")
    ax.set_ylim(0.0, 1.05)
    ax.set_ylabel("smallest margin over both motions")
    ax.set_title("singularity margins (docs/family.md §6; 0 is singular)", fontsize=10)
    ax.legend(fontsize=8, loc="lower right")
    ax = axes[1, 1]
    by_name = {str(a["architecture"]): a for a in areas}
    ax.bar(x, [by_name[n]["reachable"] for n in names], 0.6, facecolor="none",
           edgecolor="0.3", label="reachable")  # fmt: skip
    ax.bar(x, [by_name[n]["regular"] for n in names], 0.6, color="C9", label="regular")
    ax.set_ylabel("area at φ = 0 in the window |x|, |y| ≤ 0.6 m (m²)")
    ax.set_title(
        "workspace at φ = 0 (no joint limits: with a P joint a leg may reach\nthe whole window)",
        fontsize=10,
    )
    ax.legend(fontsize=8)
    for ax in axes.flat:
        ax.set_xticks(x, names)
        ax.grid(True, axis="y", color="0.92")
    figure.suptitle(
        title or "The seven default designs carrying a 1.5 kg payload along the paper's motions",
        fontsize=12,
    )
    return figure
