"""``animation.mp4``: the predicted walk in 3D with a side and a front view, rendered frame by
frame on an off-screen Matplotlib figure (Agg canvas) and encoded as H.264 by the ffmpeg that
imageio-ffmpeg ships.

The drawn geometry comes from :func:`walk3d.plots.animation.animation_frames`. The artists are
made once and only their data change from frame to frame. The video goes to a temporary file
next to the destination and is moved over it with :func:`os.replace` when complete.
"""

from __future__ import annotations

import math
import os
import secrets
from collections.abc import Callable
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from walk3d.plots.animation import AnimationFrames, animation_frames

if TYPE_CHECKING:
    from walk3d.body.model import BodyModel
    from walk3d.results.prediction import Prediction

__all__ = ["FRAME_SIZE", "write_animation"]

FRAME_SIZE = (1280, 480)
"""Width and height of the video's frames, pixels (multiples of 16, as H.264 prefers)."""

_DPI = 100.0
_COLORS = {"r": "tab:red", "l": "tab:blue", "": "0.15"}
_HALF_WINDOW = 1.1  # m of walkway shown either side of the pelvis


def _views(fig):
    """The 3D view (matplotlib's z is walk3d's Y: plot x, y, z = X, -Z, Y), the side view
    (X-Y, seen from the walker's right) and the front view (Z-Y, seen from in front)."""
    ax3 = fig.add_axes((0.0, 0.02, 0.42, 0.9), projection="3d")
    side = fig.add_axes((0.45, 0.1, 0.33, 0.78))
    front = fig.add_axes((0.82, 0.1, 0.16, 0.78))
    return ax3, side, front


def _collections(fig, ax3, side, front, frames: AnimationFrames):
    from matplotlib.collections import LineCollection
    from mpl_toolkits.mplot3d.art3d import Line3DCollection

    sides = np.array(frames.line_side)
    out = []
    for key in ("l", "", "r"):  # the right side drawn last: nearest in the side view
        mask = sides == key
        kw = {"colors": _COLORS[key], "linewidths": 2.2, "capstyle": "round"}
        c3 = Line3DCollection([np.zeros((2, 3))], **kw)
        ax3.add_collection3d(c3, autolim=False)
        cs, cf = LineCollection([], **kw), LineCollection([], **kw)
        side.add_collection(cs)
        front.add_collection(cf)
        out.append((mask, c3, cs, cf))
    arrows = []
    for k in range(2):
        color = _COLORS["rl"[k]]
        arrows.append((ax3.plot([], [], [], color=color, lw=1.5, alpha=0.8)[0],
                       side.plot([], [], color=color, lw=1.5, alpha=0.8)[0],
                       front.plot([], [], color=color, lw=1.5, alpha=0.8)[0]))  # fmt: skip
    return out, arrows


def _ground(ax3, side, front, frames: AnimationFrames, height: float) -> None:
    x0 = float(np.nanmin(frames.points[..., 0])) - _HALF_WINDOW
    x1 = float(np.nanmax(frames.points[..., 0])) + _HALF_WINDOW
    ticks = np.arange(math.floor(x0 / 0.25) * 0.25, x1 + 0.25, 0.25)
    for x in ticks:  # across the walkway: how far the walker has come
        ax3.plot([x, x], [-0.6, 0.6], [0.0, 0.0], color="0.8", lw=0.6)
        side.plot([x, x], [0.0, -0.03], color="0.6", lw=0.6)
    for z in (-0.6, 0.0, 0.6):
        ax3.plot([x0, x1], [z, z], [0.0, 0.0], color="0.8", lw=0.6)
    for ax in (side, front):
        ax.axhline(0.0, color="0.4", lw=1.0)
        ax.set_ylim(-0.05, 1.15 * height)
        ax.set_aspect("equal", adjustable="box")
        ax.tick_params(labelsize=7)
        ax.grid(True, linewidth=0.3, alpha=0.5)
    side.set_xlabel("X forward (m)", fontsize=8)
    side.set_ylabel("Y up (m)", fontsize=8)
    side.set_title("side view (from the right)", fontsize=9)
    front.set_xlim(0.7, -0.7)  # seen from in front: the walker's right (+Z) on the left
    front.set_xlabel("Z right (m)", fontsize=8)
    front.set_title("front view", fontsize=9)
    ax3.set_zlim(0.0, 1.15 * height)
    ax3.set_ylim(-_HALF_WINDOW, _HALF_WINDOW)
    ax3.set_box_aspect((2.2, 2.2, 1.15 * height))
    ax3.view_init(elev=12.0, azim=-60.0)
    ax3.set_axis_off()  # the ground grid (0.25 m along X) stands for the axes: faster
    ax3.text2D(
        0.5,
        0.02,
        "3D view (ground lines every 0.25 m)",
        transform=ax3.transAxes,
        ha="center",
        fontsize=9,
    )


def _update(frames: AnimationFrames, i: int, cols, arrows, ax3, side) -> None:
    p = frames.points[i]
    seg = p[frames.lines]  # (L, 2, 3)
    for mask, c3, cs, cf in cols:
        s = seg[mask]
        c3.set_segments(np.stack([s[..., 0], -s[..., 2], s[..., 1]], axis=-1))
        cs.set_segments(s[..., [0, 1]])
        cf.set_segments(s[..., [2, 1]])
    for k, (a3, a_side, a_front) in enumerate(arrows):
        if frames.loaded[i, k]:
            ab = np.stack([frames.cop[i, k], frames.grf_tip[i, k]])
        else:
            ab = np.full((2, 3), np.nan)
        a3.set_data_3d(ab[:, 0], -ab[:, 2], ab[:, 1])
        a_side.set_data(ab[:, 0], ab[:, 1])
        a_front.set_data(ab[:, 2], ab[:, 1])
    x = float(frames.pelvis[i, 0])
    ax3.set_xlim(x - _HALF_WINDOW, x + _HALF_WINDOW)
    side.set_xlim(x - _HALF_WINDOW, x + _HALF_WINDOW)


def write_animation(
    pred: Prediction,
    path: str | PathLike[str],
    *,
    cycles: int = 2,
    fps: float = 30.0,
    body: BodyModel | None = None,
    on_frame: Callable[[int, int], None] | None = None,
) -> Path:
    """Write an H.264 MP4 of ``cycles`` gait cycles of ``pred`` at real speed, ``fps`` frames
    per second (:data:`FRAME_SIZE` pixels): the 3D view, the side view and the front view, the
    right side red and the left blue, the ground reactions as arrows from the centres of
    pressure (1 m per body weight). ``body``: the body model ``pred`` was evaluated with
    (default: rebuilt from its settings). ``on_frame(done, total)`` is called after each frame.

    Raises:
        ValueError: bad ``cycles`` or ``fps``, or a prediction that does not fit its body model.
        OSError: the video could not be written (nothing is left behind).
    """
    import imageio_ffmpeg
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from walk3d.results.osim_model import prediction_body

    body = body or prediction_body(pred)
    frames = animation_frames(pred, body, cycles=cycles, fps=fps)
    width, height = FRAME_SIZE
    fig = Figure(figsize=(width / _DPI, height / _DPI), dpi=_DPI)
    canvas = FigureCanvasAgg(fig)
    ax3, side, front = _views(fig)
    _ground(ax3, side, front, frames, body.height)
    cols, arrows = _collections(fig, ax3, side, front, frames)
    d = pred.summary.get("descriptors") or {}
    head = "walk3d prediction"
    if isinstance(d, dict) and "speed" in d:
        head += f": V = {float(d['speed']):.2f} m/s, T = {frames.period:.3f} s"
    title = fig.suptitle("", fontsize=10, x=0.02, ha="left")

    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = target.with_name(f".{target.name}.{secrets.token_hex(6)}.tmp")
    writer = imageio_ffmpeg.write_frames(
        str(tmp), (width, height), fps=fps, codec="libx264", pix_fmt_in="rgb24",
        macro_block_size=16, quality=6, output_params=["-f", "mp4"], ffmpeg_log_level="error",
    )  # fmt: skip
    try:
        writer.send(None)
        n = frames.n_frames
        for i in range(n):
            _update(frames, i, cols, arrows, ax3, side)
            cycle = int(frames.time[i] // frames.period) + 1
            title.set_text(f"{head}   t = {frames.time[i]:5.2f} s (cycle {cycle} of {cycles}); "
                           "arrows: ground reaction, 1 m = body weight")  # fmt: skip
            canvas.draw()
            rgb = np.asarray(canvas.buffer_rgba())[..., :3]
            writer.send(np.ascontiguousarray(rgb).tobytes())
            if on_frame is not None:
                on_frame(i + 1, n)
        writer.close()
        with open(tmp, "rb") as handle:
            os.fsync(handle.fileno())
        os.replace(tmp, target)
    except BaseException:
        writer.close()
        tmp.unlink(missing_ok=True)
        raise
    return target
