"""Figures of walk3d results (rendered off-screen with Matplotlib's Agg canvas)."""

from walk3d.plots.summary import summary_figure, warm_up

__all__ = ["summary_figure", "warm_up"]
