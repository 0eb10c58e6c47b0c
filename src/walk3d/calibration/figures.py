"""Calibration figures in the style of the paper's Figs. 2–3 (Matplotlib, off-screen Agg canvas).

* :func:`transition_figure` (Fig. 3): trailing-foot force and moment in double support, force
  plate (solid) against the transition function (dashed).
* :func:`rollover_figure` (Fig. 2): ankle displacement against foot rotation, measured samples,
  calibrated spline and walk3d's default arc.

Figures are written with :func:`walk3d.plots.canvas.save_png`; no global Matplotlib state is
touched.
"""

from __future__ import annotations

from os import PathLike
from pathlib import Path

import numpy as np

from walk3d.body.rollover import RollOver
from walk3d.calibration.fit import COMPONENTS, TransitionCheck
from walk3d.plots.canvas import agg_figure, save_png

__all__ = ["rollover_figure", "transition_figure"]

_COLORS = ("tab:red", "tab:blue", "tab:green", "tab:purple")


def transition_figure(check: TransitionCheck, path: str | PathLike[str]) -> Path:
    """Fig. 3: trailing-foot wrench in double support, measured vs transition function."""
    fig, axes = agg_figure(2, 3, 12.0, 6.5)
    fig.subplots_adjust(left=0.07, right=0.98, bottom=0.09, top=0.88, hspace=0.4, wspace=0.3)
    units = ("N/kg",) * 3 + ("N m/kg",) * 3
    for k, (ax, comp) in enumerate(zip(axes, COMPONENTS, strict=True)):
        for i, ph in enumerate(check.phases):
            x = 100.0 * ph["t"] / ph["duration"]
            label = f"{ph['side']} trailing" if k == 0 else None
            ax.plot(x, ph["measured"][:, k], color=_COLORS[i % 4], linewidth=1.3, label=label)
            ax.plot(x, ph["model"][:, k], color=_COLORS[i % 4], linestyle="--", linewidth=1.3)
        ax.set_title(f"{comp}  (RMSE {check.rmse[comp]:.3f} {units[k]})", fontsize=9)
        ax.set_xlabel("% of double support (0 = contralateral heel strike)", fontsize=7)
        ax.set_ylabel(units[k], fontsize=7)
        ax.tick_params(labelsize=7)
        ax.grid(True, linewidth=0.3, alpha=0.6)
    axes[0].legend(fontsize=7, title="solid: plate, dashed: model", title_fontsize=7)
    r = check.ratios
    fig.suptitle(
        "Transition function (Eqs. 6-8) vs force plate, right-foot signs; "
        f"μx={r.mu_x:.3f} μz={r.mu_z:.3f} ϖx={r.varpi_x:.3f} ϖy={r.varpi_y:.3f}",
        fontsize=10,
    )
    return save_png(fig, path)


def rollover_figure(
    samples: tuple[np.ndarray, np.ndarray],
    calibrated: RollOver,
    default: RollOver,
    path: str | PathLike[str],
) -> Path:
    """Fig. 2: ankle Δx, y, Δz against the foot rotation (deg)."""
    s, ankle = samples
    fig, axes = agg_figure(1, 3, 12.0, 3.8)
    fig.subplots_adjust(left=0.07, right=0.98, bottom=0.15, top=0.85, wspace=0.3)
    grid = np.linspace(min(calibrated.knots[0], s.min()), max(calibrated.knots[-1], s.max()), 200)
    cal = np.column_stack(calibrated.evaluate(grid)[0])
    dft = np.column_stack(default.evaluate(grid)[0])
    deg = np.degrees(2 * np.arcsin(grid))
    for k, (ax, name) in enumerate(zip(axes, ("Δx ankle (m)", "y ankle (m)", "Δz ankle (m)"),
                                       strict=True)):  # fmt: skip
        ax.plot(np.degrees(2 * np.arcsin(s)), ankle[:, k], "o", markersize=2.5, color="0.5",
                label="measured (walk3d FK of IK)")  # fmt: skip
        ax.plot(deg, cal[:, k], color="tab:red", label="calibrated spline")
        ax.plot(deg, dft[:, k], color="tab:blue", linestyle="--", label="default arc")
        ax.set_xlabel("foot rotation θ from foot flat (deg, toes up +)", fontsize=8)
        ax.set_title(name, fontsize=9)
        ax.tick_params(labelsize=7)
        ax.grid(True, linewidth=0.3, alpha=0.6)
    axes[0].legend(fontsize=7)
    fig.suptitle("Stance-foot roll-over (paper Eq. 1, Fig. 2)", fontsize=10)
    return save_png(fig, path)
