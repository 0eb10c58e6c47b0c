"""Validation figures in the style of the paper's Figs. 2–7 (Matplotlib, off-screen Agg canvas).

* :func:`comparison_figures`: one PNG per group (ground reactions, joint moments, joint
  angles): the measured mean ± SD as a grey band (mean dashed), each prediction as a line
  (first solid, then dash-dot, dotted...), 0–100 % from right heel strike. A quantity the
  reference lacks is drawn without a band and labelled "no measurement".
* :func:`transition_figure` (Fig. 3): trailing-foot force and moment in double support, force
  plate (solid) against the transition function (dashed).
* :func:`rollover_figure` (Fig. 2): ankle displacement against foot rotation, measured samples,
  calibrated spline and walk3d's default arc.

Figures are written with :func:`walk3d.io._atomic.atomic_write`; no global Matplotlib state is
touched.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from os import PathLike
from pathlib import Path

import numpy as np

from walk3d.io._atomic import atomic_write
from walk3d.kinematics.rollover import RollOver
from walk3d.validation.calibration import COMPONENTS, TransitionCheck
from walk3d.validation.compare import Comparison
from walk3d.validation.quantities import GROUP_TITLES, GROUPS, QUANTITIES

__all__ = ["comparison_figures", "rollover_figure", "transition_figure"]

_STYLES = ("-", "-.", ":", "--")
_COLORS = ("tab:red", "tab:blue", "tab:green", "tab:purple")


def _figure(rows: int, cols: int, width: float, height: float, dpi: float = 100.0):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=dpi)
    FigureCanvasAgg(fig)
    axes = np.atleast_1d(fig.subplots(rows, cols, squeeze=False)).ravel()
    return fig, axes


def _save(fig, path: str | PathLike[str]) -> Path:
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    return atomic_write(target, lambda handle: fig.savefig(handle, format="png"))


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
        fig, axes = _figure(rows, cols, 4.0 * cols, height, dpi=75.0)
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
        out[group] = _save(fig, Path(out_dir) / f"{prefix}{names[group]}.png")
    return out


def transition_figure(check: TransitionCheck, path: str | PathLike[str]) -> Path:
    """Fig. 3: trailing-foot wrench in double support, measured vs transition function."""
    fig, axes = _figure(2, 3, 12.0, 6.5)
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
    return _save(fig, path)


def rollover_figure(
    samples: tuple[np.ndarray, np.ndarray],
    calibrated: RollOver,
    default: RollOver,
    path: str | PathLike[str],
) -> Path:
    """Fig. 2: ankle Δx, y, Δz against the foot rotation (deg)."""
    s, ankle = samples
    fig, axes = _figure(1, 3, 12.0, 3.8)
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
    return _save(fig, path)
