"""An off-screen Matplotlib figure (Agg canvas, no global state) and its atomic PNG write."""

from __future__ import annotations

from os import PathLike
from pathlib import Path

import numpy as np

from walk3d.io.atomic import atomic_write

__all__ = ["agg_figure", "save_png"]


def agg_figure(rows: int, cols: int, width: float, height: float, dpi: float = 100.0):
    """A figure of ``rows`` x ``cols`` axes (returned flat) on its own Agg canvas."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=dpi)
    FigureCanvasAgg(fig)
    axes = np.atleast_1d(fig.subplots(rows, cols, squeeze=False)).ravel()
    return fig, axes


def save_png(fig, path: str | PathLike[str]) -> Path:
    """Write ``fig`` as a PNG atomically, creating the folder; returns the path."""
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    return atomic_write(target, lambda handle: fig.savefig(handle, format="png"))
