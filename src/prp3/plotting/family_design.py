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

__all__ = ["family_designs_figure"]

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
