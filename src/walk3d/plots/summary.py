"""One-page summary figure of a prediction: joint angles and ground reactions over the cycle.

The figure is drawn on a :class:`matplotlib.figure.Figure` with an Agg canvas, so no global
Matplotlib backend is selected or changed and no display is needed.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from walk3d.constants import G
from walk3d.io.atomic import atomic_write
from walk3d.results.angles import pelvis_angles

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from walk3d.results.prediction import PredictedCycle

__all__ = ["summary_figure", "summary_plot", "warm_up"]

_RIGHT = {"color": "tab:red", "label": "right"}
_LEFT = {"color": "tab:blue", "label": "left"}

# (panel title, DoF name without the side suffix) of the bilateral angle panels
_BILATERAL = (
    ("Hip flexion", "hip_flexion"),
    ("Hip adduction", "hip_adduction"),
    ("Hip rotation", "hip_rotation"),
    ("Knee flexion", "knee_flexion"),
    ("Ankle dorsiflexion", "ankle_dorsiflexion"),
    ("Subtalar inversion", "subtalar_inversion"),
    ("Shoulder flexion", "arm_flex"),
    ("Elbow flexion", "elbow_flex"),
)
_GRF = (("Vertical GRF", 1), ("Fore-aft GRF (+forward)", 0), ("Lateral GRF (+right)", 2))


def _percent_cycle(time: np.ndarray) -> np.ndarray:
    span = float(time[-1] - time[0]) if time.size > 1 else 0.0
    if span <= 0.0:
        return np.zeros_like(time)
    return 100.0 * (time - time[0]) / span


def _number(value: Any) -> float | None:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.number)):
        return None
    return float(value)


def _criterion(objective: Mapping[str, Any], key: str) -> float | None:
    entry = objective.get(key)
    if isinstance(entry, Mapping):
        return _number(entry.get("total"))
    return _number(entry)


def _title(summary: Mapping[str, Any]) -> str:
    converged = summary.get("converged")
    if converged is True:
        head = "walk3d prediction: converged"
    elif converged is False:
        head = "walk3d prediction: NOT CONVERGED"
    else:
        head = "walk3d prediction: convergence unknown"
    status = summary.get("status")
    if isinstance(status, str) and status:
        head += f" ({status})"
    parts = []
    objective = summary.get("objective")
    if isinstance(objective, Mapping):
        for key in ("C_tor", "C_en"):
            value = _criterion(objective, key)
            if value is not None:
                parts.append(f"{key} = {value:.4g}")
    for key, label, fmt in (
        ("max_constraint_violation", "max violation", ".2e"),
        ("stride_length_m", "stride", ".3f"),
        ("iterations", "iterations", "d"),
        ("wall_time_s", "time", ".1f"),
    ):
        value = _number(summary.get(key))
        if value is None or not math.isfinite(value):
            continue
        text = format(int(value), fmt) if fmt == "d" else format(value, fmt)
        unit = {"stride_length_m": " m", "wall_time_s": " s"}.get(key, "")
        parts.append(f"{label} {text}{unit}")
    return head if not parts else head + "\n" + ",  ".join(parts)


def _bilateral(ax: Axes, pred: PredictedCycle, x: np.ndarray, title: str, base: str) -> None:
    for side, style in (("r", _RIGHT), ("l", _LEFT)):
        name = f"{base}_{side}"
        if name in pred.dof_names:
            ax.plot(x, np.degrees(pred.dof(name)), **style)
    ax.set_title(title, fontsize=9, y=1.0)
    ax.set_ylabel("deg", fontsize=8)


def _trunk(ax: Axes, pred: PredictedCycle, x: np.ndarray) -> None:
    pelvis = np.degrees(pelvis_angles(pred.segment_orientation[:, 0, :]))
    colors = ("tab:green", "tab:purple", "tab:orange")
    for k, label in enumerate(("tilt", "list", "rotation")):
        ax.plot(x, pelvis[:, k], color=colors[k], label=f"pelvis {label}")
    for name, color in zip(
        ("lumbar_extension", "lumbar_bending", "lumbar_rotation"), colors, strict=True
    ):
        if name in pred.dof_names:
            ax.plot(x, np.degrees(pred.dof(name)), color=color, linestyle="--", label=name)
    ax.set_title("Pelvis (global) and lumbar", fontsize=9, y=1.0)
    ax.set_ylabel("deg", fontsize=8)
    ax.legend(fontsize=6, ncol=2, loc="best")


def _grf(ax: Axes, pred: PredictedCycle, x: np.ndarray, title: str, axis: int) -> None:
    mass = pred.body_mass
    scale = 1.0 / mass if mass > 0 else 1.0
    for k, style in enumerate((_RIGHT, _LEFT)):
        ax.plot(x, pred.grf_force[:, k, axis] * scale, **style)
    ax.set_title(title, fontsize=9, y=1.0)
    ax.set_ylabel("N/kg" if mass > 0 else "N", fontsize=8)
    if axis == 1 and mass > 0:
        ax.axhline(G, color="0.6", linewidth=0.8, linestyle=":")


def _draw(pred: PredictedCycle, figsize: Sequence[float], dpi: float):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=tuple(figsize), dpi=dpi)
    FigureCanvasAgg(fig)
    # fixed margins: a layout engine would double the rendering time
    fig.subplots_adjust(left=0.07, right=0.98, bottom=0.05, top=0.9, hspace=0.4, wspace=0.3)
    axes = fig.subplots(4, 3, sharex=True).ravel()
    x = _percent_cycle(pred.time)
    for ax, (title, base) in zip(axes[:8], _BILATERAL, strict=True):
        _bilateral(ax, pred, x, title, base)
    _trunk(axes[8], pred, x)
    for ax, (title, axis) in zip(axes[9:], _GRF, strict=True):
        _grf(ax, pred, x, title, axis)
    for ax in axes:
        ax.tick_params(labelsize=7)
        ax.grid(True, linewidth=0.3, alpha=0.6)
        ax.set_xlim(0.0, 100.0)
    for ax in axes[9:]:
        ax.set_xlabel("% gait cycle", fontsize=8)
    axes[0].legend(fontsize=7, loc="best")
    fig.suptitle(_title(pred.summary), fontsize=10)
    return fig


def warm_up() -> None:
    """Import Matplotlib and render a small figure with text, so that its fonts and caches are
    loaded. About 0.6 s; :func:`walk3d.pipeline.predict` runs it in a thread while IPOPT
    iterates (CasADi releases the GIL), which takes it off the end-to-end time."""
    import io

    fig = _draw_blank()
    fig.savefig(io.BytesIO(), format="png")


def _draw_blank():
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(1.0, 1.0), dpi=20)
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    ax.plot([0.0, 1.0], [0.0, 1.0])
    ax.set_title("walk3d", fontsize=9)
    ax.legend(["line"], fontsize=7)
    return fig


def summary_plot(
    pred: PredictedCycle, *, figsize: Sequence[float] = (11.0, 11.0), dpi: float = 100.0
) -> Figure:
    """The figure :func:`summary_figure` saves, as a Matplotlib Figure (not attached to pyplot,
    so nothing is shown unless asked)."""
    return _draw(pred, figsize, dpi)


def summary_figure(
    pred: PredictedCycle,
    path: str | PathLike[str],
    *,
    figsize: Sequence[float] = (11.0, 11.0),
    dpi: float = 100.0,
) -> Path:
    """Save a PNG summary of ``pred``: joint angles (deg) and ground reactions (N/kg).

    Angle panels show right (red) and left (blue) hip flexion, adduction and rotation, knee flexion,
    ankle dorsiflexion, subtalar inversion, shoulder flexion and elbow flexion, plus the pelvis's
    global tilt/list/rotation with the lumbar angles; the ground reaction panels show vertical,
    fore-aft (+x) and lateral (+z, to the right) force over body mass. The x axis is the percent
    of ``pred.time``'s span. The title says converged / NOT CONVERGED and lists the criteria
    (``summary["objective"]["C_tor"]["total"]``, ``C_en``) and other summary values when present.

    The PNG is rendered into a temporary file in the destination folder (created if needed) and
    moved over ``path`` with :func:`os.replace`.

    Returns:
        The path written.
    """
    return save_png(_draw(pred, figsize, dpi), path)


def save_png(fig: Figure, path: str | PathLike[str]) -> Path:
    """Write ``fig`` as a PNG atomically (the folder created if needed); returns the path."""
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    return atomic_write(target, lambda handle: fig.savefig(handle, format="png"))
