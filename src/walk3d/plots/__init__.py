"""Figures of walk3d results (rendered off-screen with Matplotlib's Agg canvas)."""

from walk3d.plots.animation import animation_frames
from walk3d.plots.summary import summary_figure, summary_plot, warm_up
from walk3d.plots.video import write_animation

__all__ = ["animation_frames", "summary_figure", "summary_plot", "warm_up", "write_animation"]
