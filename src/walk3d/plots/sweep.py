"""The figure of ``walk3d sweep``: stride length, cadence and double support against speed,
predicted and published for adults."""

from __future__ import annotations

from os import PathLike
from pathlib import Path

import numpy as np

from walk3d.plots.canvas import agg_figure, save_png
from walk3d.problem import descriptors

__all__ = ["sweep_figure"]

PUBLISHED = (
    "published: cadence C = √(60 V / (W h)), W = 0.0037 × stature (walk ratio; Murray 1964, "
    "1970; Terrier & Schutz 2003), stride 120 V / C;\ndouble support 0.142 − 0.035 V of the "
    "cycle (stance 64.2 − 3.5 V %, Kirtley, Whittle & Jefferson 1985)"
)


def sweep_figure(rows: list[dict], height: float, path: str | PathLike[str]) -> Path:
    """Three panels over speed from ``sweep.csv``'s rows; ``height`` (m) scales the published
    walk ratio. Converged walking predictions are filled markers, the others open."""
    fig, axes = agg_figure(1, 3, 13.0, 4.2)
    v = np.array([r["speed"] for r in rows], dtype=float)
    good = np.array([bool(r["converged"]) and bool(r["looks_like_walking"]) for r in rows])
    vv = np.linspace(max(0.2, v.min() - 0.1), v.max() + 0.1, 100)
    cadence = descriptors.published_cadence(vv, height)
    panels = [
        ("stride length (m)", [r["stride_length"] for r in rows], 120 * vv / cadence),
        ("cadence (steps/min)", [r["cadence"] for r in rows], cadence),
        ("double support (% of cycle, each)",
         [100 * r["double_support"] / r["period"] for r in rows],
         100 * descriptors.published_ds_fraction(vv)),
    ]  # fmt: skip
    for ax, (label, y, ref) in zip(axes, panels, strict=True):
        y = np.array(y, dtype=float)
        ax.plot(vv, ref, color="0.5", lw=1.5, label="published (adults)")
        ax.plot(v[good], y[good], "o-", color="tab:blue", label="walk3d")
        if (~good).any():
            ax.plot(v[~good], y[~good], "o", mfc="none", color="tab:red",
                    label="not converged or not walking")  # fmt: skip
        ax.set_xlabel("speed (m/s)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle("walk3d sweep: T and Td predicted at each speed", fontsize=11)
    fig.text(0.01, 0.01, PUBLISHED, fontsize=7, va="bottom")
    fig.subplots_adjust(bottom=0.25, wspace=0.3)
    return save_png(fig, path)
