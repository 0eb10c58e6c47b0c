"""The figure of ``walk3d compare``: two predictions over the gait cycle, both sides (A solid,
B dashed; right red, left blue): sagittal and frontal leg angles, their joint moments per body
mass, and the ground reactions."""

from __future__ import annotations

from os import PathLike
from pathlib import Path

import numpy as np

from walk3d.plots.canvas import agg_figure, save_png
from walk3d.results.compare import dof_moments
from walk3d.results.prediction import PredictedCycle

__all__ = ["compare_figure"]

_DOFS = ("hip_flexion", "hip_adduction", "knee_flexion", "ankle_dorsiflexion")
_SIDES = (("r", "tab:red"), ("l", "tab:blue"))
_RUNS = (("-", "A"), ("--", "B"))


def compare_figure(a: PredictedCycle, b: PredictedCycle, path: str | PathLike[str],
                   labels: tuple[str, str] = ("A", "B")) -> Path:  # fmt: skip
    """Write the comparison figure (PNG) of ``a`` and ``b`` to ``path``."""
    fig, axes = agg_figure(3, 4, 14.0, 9.0)
    fig.subplots_adjust(left=0.06, right=0.98, bottom=0.07, top=0.9, hspace=0.45, wspace=0.3)
    x = np.linspace(0.0, 100.0, a.time.size)
    for pred, (style, _) in zip((a, b), _RUNS, strict=True):
        m = dof_moments(pred) / pred.body_mass
        names = list(pred.dof_names)
        for k, dof in enumerate(_DOFS):
            for side, color in _SIDES:
                i = names.index(f"{dof}_{side}")
                axes[k].plot(x, np.degrees(pred.joint_angle[:, i]), style, color=color)
                axes[4 + k].plot(x, m[:, i], style, color=color)
        for k, dof in enumerate(("subtalar_inversion", "arm_flex")):
            for side, color in _SIDES:
                i = names.index(f"{dof}_{side}")
                axes[8 + k].plot(x, np.degrees(pred.joint_angle[:, i]), style, color=color)
        for k, axis in enumerate((1, 0)):
            for f, (_, color) in enumerate(_SIDES):
                axes[10 + k].plot(x, pred.grf_force[:, f, axis] / pred.body_mass, style,
                                  color=color)  # fmt: skip
    titles = [f"{d} (deg)" for d in _DOFS] + [f"{d} moment (N m/kg)" for d in _DOFS]
    titles += ["subtalar_inversion (deg)", "arm_flex (deg)", "vertical GRF (N/kg)",
               "fore-aft GRF (N/kg)"]  # fmt: skip
    for ax, title in zip(axes, titles, strict=True):
        ax.set_title(title, fontsize=9)
        ax.tick_params(labelsize=7)
        ax.grid(True, linewidth=0.3, alpha=0.6)
        ax.set_xlim(0.0, 100.0)
    for ax in axes[8:]:
        ax.set_xlabel("% gait cycle", fontsize=8)
    handles = [axes[0].lines[0], axes[0].lines[1], axes[0].lines[2]]
    axes[0].legend(handles, [f"{labels[0]} right", f"{labels[0]} left",
                             f"{labels[1]} right"], fontsize=7)  # fmt: skip
    fig.suptitle(f"{labels[0]} (solid) against {labels[1]} (dashed)", fontsize=11)
    return save_png(fig, path)
