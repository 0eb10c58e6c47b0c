"""``animation.mp4``: the predicted walk in 3D with a side and a front view, rendered frame by
frame on an off-screen Matplotlib figure (Agg canvas) and encoded as H.264 by the ffmpeg that
imageio-ffmpeg ships.

The drawn geometry comes from :func:`walk3d.plots.animation.animation_frames`. The views follow
the pelvis by drawing X relative to it, so the axes, labels and ground are drawn once and
cached; each frame restores them and draws only the moving artists (the sticks, the arrows,
the walkway marks every 0.25 m and the clock). The video goes to a temporary file
next to the destination and is moved over it with :func:`os.replace` when complete.
"""

from __future__ import annotations

import errno
import math
import numbers
import os
import re
from collections.abc import Callable, Iterable, Iterator
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from walk3d.io.atomic import atomic_path
from walk3d.plots.animation import AnimationFrames, animation_frames
from walk3d.results.labels import did_not_converge, invalid_reason

if TYPE_CHECKING:
    from walk3d.body.model import BodyModel
    from walk3d.results.prediction import PredictedCycle

__all__ = ["FRAME_SIZE", "VIDEO_MARKER", "encode_mp4", "is_walk3d_video", "write_animation"]

VIDEO_MARKER = "walk3d animation"
"""The comment in every video's metadata (its ``moov`` box), by which walk3d knows a video it
wrote from a user's file (:func:`is_walk3d_video`)."""
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


def _moving(artist):
    """Mark ``artist`` as drawn per frame over the cached background."""
    artist.set_animated(True)
    return artist


def _collections(ax3, side, front, frames: AnimationFrames):
    from matplotlib.collections import LineCollection
    from mpl_toolkits.mplot3d.art3d import Line3DCollection

    sides = np.array(frames.line_side)
    out = []
    for key in ("l", "", "r"):  # the right side drawn last: nearest in the side view
        mask = sides == key
        kw = {"colors": _COLORS[key], "linewidths": 2.2, "capstyle": "round"}
        c3 = _moving(Line3DCollection([np.zeros((2, 3))], **kw))
        ax3.add_collection3d(c3, autolim=False)
        cs, cf = _moving(LineCollection([], **kw)), _moving(LineCollection([], **kw))
        side.add_collection(cs, autolim=False)
        front.add_collection(cf, autolim=False)
        out.append((mask, c3, cs, cf))
    arrows = []
    for k in range(2):
        kw = {"color": _COLORS["rl"[k]], "lw": 1.5, "alpha": 0.8}
        arrows.append((_moving(ax3.plot([], [], [], **kw)[0]),
                       _moving(side.plot([], [], **kw)[0]),
                       _moving(front.plot([], [], **kw)[0])))  # fmt: skip
    return out, arrows


def _ground(ax3, side, front, frames: AnimationFrames, height: float):
    """The static ground and axes (the views follow the pelvis: X is drawn relative to it)
    and the moving marks every 0.25 m of walkway; returns the marks' (3D, side) collections
    and their absolute X."""
    from matplotlib.collections import LineCollection
    from mpl_toolkits.mplot3d.art3d import Line3DCollection

    x0 = float(np.nanmin(frames.points[..., 0])) - _HALF_WINDOW
    x1 = float(np.nanmax(frames.points[..., 0])) + _HALF_WINDOW
    ticks = np.arange(math.floor(x0 / 0.25) * 0.25, x1 + 0.25, 0.25)
    marks3 = _moving(Line3DCollection([np.zeros((2, 3))], colors="0.8", linewidths=0.6))
    ax3.add_collection3d(marks3, autolim=False)
    marks_side = _moving(LineCollection([], colors="0.6", linewidths=0.6))
    side.add_collection(marks_side, autolim=False)
    for z in (-0.6, 0.0, 0.6):
        ax3.plot([-_HALF_WINDOW, _HALF_WINDOW], [z, z], [0.0, 0.0], color="0.8", lw=0.6)
    for ax in (side, front):
        ax.axhline(0.0, color="0.4", lw=1.0)
        ax.set_ylim(-0.05, 1.15 * height)
        ax.set_aspect("equal", adjustable="box")
        ax.tick_params(labelsize=7)
        ax.grid(True, linewidth=0.3, alpha=0.5)
    side.set_xlim(-_HALF_WINDOW, _HALF_WINDOW)
    side.set_xlabel("X forward, from the pelvis (m)", fontsize=8)
    side.set_ylabel("Y up (m)", fontsize=8)
    side.set_title("side view (from the right), following the pelvis", fontsize=9)
    front.set_xlim(0.7, -0.7)  # seen from in front: the walker's right (+Z) on the left
    front.set_xlabel("Z right (m)", fontsize=8)
    front.set_title("front view", fontsize=9)
    ax3.set_xlim(-_HALF_WINDOW, _HALF_WINDOW)
    ax3.set_zlim(0.0, 1.15 * height)
    ax3.set_ylim(-_HALF_WINDOW, _HALF_WINDOW)
    ax3.set_box_aspect((2.2, 2.2, 1.15 * height))
    ax3.view_init(elev=12.0, azim=-60.0)
    ax3.set_axis_off()  # the ground grid (0.25 m along X) stands for the axes
    ax3.text2D(0.5, 0.02, "3D view (ground lines every 0.25 m)", transform=ax3.transAxes,
               ha="center", fontsize=9)  # fmt: skip
    return marks3, marks_side, ticks


def _update(frames: AnimationFrames, i: int, cols, arrows, ground) -> None:
    x = float(frames.pelvis[i, 0])
    shift = np.array([x, 0.0, 0.0])
    p = frames.points[i] - shift
    seg = p[frames.lines]  # (L, 2, 3)
    for mask, c3, cs, cf in cols:
        s = seg[mask]
        c3.set_segments(np.stack([s[..., 0], -s[..., 2], s[..., 1]], axis=-1))
        cs.set_segments(s[..., [0, 1]])
        cf.set_segments(s[..., [2, 1]])
    for k, (a3, a_side, a_front) in enumerate(arrows):
        if frames.loaded[i, k]:
            ab = np.stack([frames.cop[i, k], frames.grf_tip[i, k]]) - shift
        else:
            ab = np.full((2, 3), np.nan)
        a3.set_data_3d(ab[:, 0], -ab[:, 2], ab[:, 1])
        a_side.set_data(ab[:, 0], ab[:, 1])
        a_front.set_data(ab[:, 2], ab[:, 1])
    marks3, marks_side, ticks = ground
    rel = ticks[np.abs(ticks - x) <= _HALF_WINDOW] - x
    marks3.set_segments([[(u, -0.6, 0.0), (u, 0.6, 0.0)] for u in rel])
    marks_side.set_segments([[(u, 0.0), (u, -0.03)] for u in rel])


class _Scene:
    """The figure of one animation: :meth:`frame` draws frame ``i`` over the cached background
    (``full=True``: a whole redraw, the reference the cached drawing must equal)."""

    def __init__(self, pred: PredictedCycle, body: BodyModel, cycles: int, fps: float) -> None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        self.frames = frames = animation_frames(pred, body, cycles=cycles, fps=fps)
        self.cycles = cycles
        width, height = FRAME_SIZE
        fig = Figure(figsize=(width / _DPI, height / _DPI), dpi=_DPI)
        self.canvas = FigureCanvasAgg(fig)
        ax3, side, front = _views(fig)
        self.ground = _ground(ax3, side, front, frames, body.height)
        self.cols, self.arrows = _collections(ax3, side, front, frames)
        d = pred.summary.get("descriptors") or {}
        speed = d.get("speed") if isinstance(d, dict) else None
        head = "walk3d prediction"
        if isinstance(speed, numbers.Real) and not isinstance(speed, bool) and math.isfinite(
                speed):  # fmt: skip
            head += f": V = {float(speed):.2f} m/s, T = {frames.period:.3f} s"
        fig.suptitle(f"{head}; arrows: ground reaction, 1 m = body weight", fontsize=10,
                     x=0.02, ha="left")  # fmt: skip
        if invalid_reason(pred.summary) is not None:  # in every frame, as report.html's banner
            label = ("NOT CONVERGED: not a valid prediction" if did_not_converge(pred.summary)
                     else "DOES NOT LOOK LIKE WALKING (gait checks)")  # fmt: skip
            fig.text(0.02, 0.9, label, fontsize=10, color="#d33a2c", fontweight="bold")
        self.clock = _moving(fig.text(0.98, 0.98, "", fontsize=10, ha="right", va="top"))
        self.moving = [*self.ground[:2], *(a for c in self.cols for a in c[1:]),
                       *(a for arrow in self.arrows for a in arrow), self.clock]  # fmt: skip
        self.canvas.draw()  # everything but the moving artists, once
        self.background = self.canvas.copy_from_bbox(fig.bbox)

    def frame(self, i: int, full: bool = False) -> np.ndarray:
        """Frame ``i``, RGB (height, width, 3) uint8."""
        f = self.frames
        _update(f, i, self.cols, self.arrows, self.ground)
        cycle = int(f.time[i] // f.period) + 1
        self.clock.set_text(f"t = {f.time[i]:5.2f} s (cycle {cycle} of {self.cycles})")
        if full:
            for artist in self.moving:
                artist.set_animated(False)
            try:
                self.canvas.draw()
            finally:
                for artist in self.moving:
                    artist.set_animated(True)
        else:
            self.canvas.restore_region(self.background)
            for artist in self.moving:
                if hasattr(artist, "do_3d_projection"):
                    artist.do_3d_projection()
                (artist.axes or artist.figure).draw_artist(artist)
        return np.ascontiguousarray(np.asarray(self.canvas.buffer_rgba())[..., :3])


def write_animation(
    pred: PredictedCycle,
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
    from walk3d.results.osim_model import prediction_body

    scene = _Scene(pred, body or prediction_body(pred), cycles, fps)

    def frames() -> Iterator[bytes]:
        n = scene.frames.n_frames
        for i in range(n):
            yield scene.frame(i).tobytes()
            if on_frame is not None:
                on_frame(i + 1, n)

    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(target) as tmp:
        encode_mp4(tmp, frames(), fps)
    return target


def encode_mp4(path: Path, frames: Iterable[bytes], fps: float) -> None:
    """Encode RGB frames of :data:`FRAME_SIZE` as an H.264 MP4 at ``path`` with the ffmpeg of
    imageio-ffmpeg, its messages kept from the terminal. Raises :class:`OSError` with one line
    (ffmpeg's reason) when ffmpeg fails, e.g. on a full disk; ffmpeg is stopped on any error."""
    import subprocess
    import threading

    import imageio_ffmpeg

    width, height = FRAME_SIZE
    cmd = [imageio_ffmpeg.get_ffmpeg_exe(), "-y", "-v", "error", "-f", "rawvideo",
           "-pix_fmt", "rgb24", "-s", f"{width}x{height}", "-r", f"{fps:g}", "-i", "-", "-an",
           "-vcodec", "libx264", "-pix_fmt", "yuv420p", "-crf", "20",
           "-metadata", f"comment={VIDEO_MARKER}", "-f", "mp4", str(path)]  # fmt: skip
    proc = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, start_new_session=True)  # fmt: skip
    said: list[bytes] = []
    reader = threading.Thread(target=lambda: said.extend(proc.stderr), daemon=True)
    reader.start()
    done = False
    try:
        try:
            for frame in frames:
                proc.stdin.write(frame)
        except BrokenPipeError:
            pass  # ffmpeg stopped early: its exit code says why
        try:
            proc.stdin.close()
        except BrokenPipeError:
            pass
        code = proc.wait()
        done = True
    finally:
        if not done:
            proc.kill()
            proc.wait()
        reader.join(timeout=10)
    if code != 0:
        raise _ffmpeg_error(code, said)


def is_walk3d_video(path: str | PathLike[str]) -> bool:
    """Whether the file ``path`` is an MP4 walk3d wrote: :data:`VIDEO_MARKER` in its ``moov``
    box (the top-level boxes are walked, the frames' ``mdat`` skipped)."""
    try:
        with open(path, "rb") as f:
            size = os.fstat(f.fileno()).st_size
            at = 0
            while at + 8 <= size:
                f.seek(at)
                head = f.read(16)
                n, kind = int.from_bytes(head[:4], "big"), head[4:8]
                if n == 1 and len(head) == 16:  # a 64-bit size follows
                    n = int.from_bytes(head[8:16], "big")
                elif n == 0:  # to the end of the file
                    n = size - at
                if n < 8:
                    return False
                if kind == b"moov":
                    f.seek(at)
                    return VIDEO_MARKER.encode() in f.read(min(n, 1 << 26))
                at += n
    except OSError:
        return False
    return False


def _ffmpeg_error(code: int, said: list[bytes]) -> OSError:
    """ffmpeg's failure as one OSError: its exit code is the negated errno (mod 256) when the
    system refused, else its last message line is the reason."""
    number = 256 - code if 128 < code < 256 else 0
    if 0 < number < 134:
        return OSError(number, os.strerror(number))
    lines = [b.decode("utf-8", "replace").strip() for b in said if b.strip()]
    last = re.sub(r"^\[[^\]]*\]\s*", "", lines[-1]) if lines else f"exit code {code}"
    return OSError(errno.EIO, f"ffmpeg: {last}")
