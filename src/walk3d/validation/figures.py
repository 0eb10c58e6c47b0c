"""Validation figures in the style of the paper's Figs. 2–7 (Matplotlib, off-screen Agg canvas).

* :func:`comparison_figures`: one PNG per group (ground reactions, joint moments, joint
  angles): the measured mean ± SD as a grey band (mean dashed), each prediction as a line
  (first solid, then dash-dot, dotted...), 0–100 % from right heel strike. A quantity the
  reference lacks is drawn without a band and labelled "no measurement".

Figures are written with :func:`walk3d.plots.canvas.save_png`; no global Matplotlib state is
touched.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from os import PathLike
from pathlib import Path

import numpy as np

from walk3d.plots.canvas import agg_figure, save_png
from walk3d.validation.compare import Comparison
from walk3d.validation.quantities import GROUP_TITLES, GROUPS, QUANTITIES

__all__ = ["comparison_figures"]

_STYLES = ("-", "-.", ":", "--")
_COLORS = ("tab:red", "tab:blue", "tab:green", "tab:purple")


def comparison_figures(
    comparisons: Sequence[Comparison], out_dir: str | PathLike[str], prefix: str = ""
) -> dict[str, Path]:
    """Write ``<prefix>grf.png``, ``<prefix>moments.png``, ``<prefix>angles.png``.

    All comparisons must share one reference (the band); each adds a prediction line labelled
    with its name and RMSE.
    """
    if not comparisons:
        raise ValueError("no comparison to draw")
    ref = comparisons[0].reference
    names = {"grf": "grf", "moment": "moments", "angle": "angles"}
    out = {}
    for group in GROUPS:
        qs = [q for q in QUANTITIES if q.group == group]
        cols = 3 if len(qs) <= 9 else 4
        rows = math.ceil(len(qs) / cols)
        height = 2.7 * rows + 1.2
        fig, axes = agg_figure(rows, cols, 4.0 * cols, height, dpi=75.0)
        fig.subplots_adjust(left=0.06, right=0.98, bottom=0.5 / height, top=1 - 0.7 / height,
                            hspace=0.55, wspace=0.28)  # fmt: skip
        for ax, q in zip(axes, qs, strict=False):
            x = comparisons[0].percent
            if ref.has(q.key):
                m, s = ref.mean[q.key], ref.sd[q.key]
                if np.isfinite(s).any():
                    ax.fill_between(
                        x, m - s, m + s, color="0.82", linewidth=0, label="measured ± SD"
                    )
                ax.plot(x, m, color="0.25", linestyle="--", linewidth=1.0, label="measured mean")
            else:
                ax.text(0.5, 0.9, "no measurement", transform=ax.transAxes, ha="center",
                        fontsize=7, color="0.4")  # fmt: skip
            parts = []
            for k, comp in enumerate(comparisons):
                row = comp.row(q.key)
                ax.plot(x, comp.predicted[q.key], color=_COLORS[k % 4], linewidth=1.3,
                        linestyle=_STYLES[k % 4], label=comp.prediction_name)  # fmt: skip
                if row.status == "ok":
                    parts.append(f"{row.rmse:.2f}")
            title = q.label + (f"  (RMSE {', '.join(parts)} {q.unit})" if parts else "")
            ax.set_title(title, fontsize=8)
            ax.set_xlim(0, 100)
            ax.tick_params(labelsize=7)
            ax.grid(True, linewidth=0.3, alpha=0.6)
            ax.set_ylabel(q.unit, fontsize=7)
        for ax in axes[len(qs) :]:
            ax.set_visible(False)
        for ax in axes[max(0, len(qs) - cols) : len(qs)]:
            ax.set_xlabel("% gait cycle (0 = right heel strike)", fontsize=7)
        axes[0].legend(fontsize=6, loc="best")
        fig.suptitle(f"{GROUP_TITLES[group]} ({q.unit}): prediction vs {ref.name}", fontsize=10)
        out[group] = save_png(fig, Path(out_dir) / f"{prefix}{names[group]}.png")
    return out
