"""What the walking animation draws, frame by frame (pure NumPy; no rendering).

:func:`animation_frames` samples a prediction's cycle at a video's frame times over several
cycles (the cycle is periodic: cycle ``c`` is cycle 0 moved forward by ``c`` strides, the
pelvis's displacement over one period), and returns every drawn point in global coordinates
(m; X forward, Y up, Z right): the segments as sticks between landmarks of the body model
(joint centres, head top, hand end; each foot as the ankle and the roll-over sole on which
walk3d's stance foot rolls), and each foot's ground reaction as an arrow from its centre of
pressure, ``grf_scale`` m per body weight, only while the foot is loaded.

Between the prediction's samples, segment centres of mass, centres of pressure and forces are
interpolated linearly and orientations by normalised linear interpolation of the quaternions,
so every segment stays rigid.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from walk3d.constants import G
from walk3d.kinematics import quaternion
from walk3d.results.period import summary_period

if TYPE_CHECKING:
    from walk3d.body.model import BodyModel
    from walk3d.results.prediction import PredictedCycle

__all__ = ["AnimationFrames", "animation_frames", "cycle_period", "segment_landmarks"]

LOADED_FRACTION = 0.01
"""A foot is loaded (its arrow drawn) between two samples whose vertical force exceeds this
share of body weight and whose centre of pressure is defined."""

SOLE_SAMPLES = 33


@dataclass(frozen=True)
class AnimationFrames:
    """The drawn geometry of ``F`` frames (global, m)."""

    time: np.ndarray
    """(F,) s from the first frame."""
    points: np.ndarray
    """(F, P, 3) every landmark of every segment."""
    lines: np.ndarray
    """(L, 2) indices into ``points``: the sticks drawn."""
    line_side: tuple[str, ...]
    """Per stick: ``"r"``, ``"l"`` or ``""`` (pelvis, torso, head)."""
    point_segment: np.ndarray
    """(P,) segment index of each point."""
    foot_points: dict[str, np.ndarray]
    """``"r"``/``"l"``: indices into ``points`` of that foot's landmarks."""
    cop: np.ndarray
    """(F, 2, 3) centre of pressure of the [right, left] foot; NaN where not loaded."""
    grf_tip: np.ndarray
    """(F, 2, 3) tip of the ground-reaction arrow; NaN where not loaded."""
    loaded: np.ndarray
    """(F, 2) bool."""
    pelvis: np.ndarray
    """(F, 3) pelvis origin."""
    stride: np.ndarray
    """(3,) displacement per cycle."""
    period: float
    grf_scale: float
    """m per body weight."""

    @property
    def n_frames(self) -> int:
        return int(self.time.size)


def _sole(body: BodyModel) -> np.ndarray:
    """(K, 3) points of the right foot's roll-over sole in the foot frame: the point touching
    the floor at each foot angle of the roll-over's range (the instantaneous centre of
    rotation, as :func:`walk3d.verify.run.contact_point` at foot flat), from heel to toe, the
    part below the ankle (the arc of the default roll-over reaches past the toe landmark)."""
    knots = body.rollover.knots
    s = np.linspace(knots[0], knots[-1], SOLE_SAMPLES)
    out = []
    for si in s:
        value, d1, _ = body.rollover.evaluate(float(si))
        theta = 2.0 * math.asin(float(si))
        dg = 0.5 * math.cos(theta / 2.0) * float(d1[1])  # dy/dθ
        rel = np.array([-dg, -float(value[1]), 0.0])  # contact - ankle, global, foot turned θ
        c, sn = math.cos(theta), math.sin(theta)
        out.append(np.array([c * rel[0] + sn * rel[1], -sn * rel[0] + c * rel[1], 0.0]))
    sole = np.array(out)
    return sole[sole[:, 1] <= 0.0][::2]


def segment_landmarks(body: BodyModel) -> tuple[list[np.ndarray], list[list[tuple[int, int]]]]:
    """Per segment: its drawn landmarks (K, 3) in the segment frame, and the sticks between
    them as index pairs."""
    joints = {j.name: j for j in body.joints}
    marks: list[np.ndarray] = []
    sticks: list[list[tuple[int, int]]] = []
    sole = _sole(body)
    for i, seg in enumerate(body.segments):
        base, side = (seg.name[:-2], seg.name[-1]) if seg.name[-2:] in ("_r", "_l") else (
            seg.name, "")  # fmt: skip
        origin = np.zeros(3)
        children = [j for j in body.joints if j.parent == i]
        if base == "pelvis":
            pts = [origin, joints["hip_r"].offset, joints["hip_l"].offset, joints["waist"].offset]
            pairs = [(1, 2), (0, 3)]
        elif base == "torso":
            pts = [origin, joints["neck"].offset, joints["shoulder_r"].offset,
                   joints["shoulder_l"].offset]  # fmt: skip
            pairs = [(0, 1), (2, 3)]
        elif base == "foot":
            mirror = np.array([1.0, 1.0, -1.0]) if side == "l" else np.ones(3)
            pts = [origin, *(sole * mirror)]  # the ankle and the sole, heel to toe
            pairs = [(0, 1), (0, len(sole))] + [(1 + k, 2 + k) for k in range(len(sole) - 1)]
        else:  # a stick from the proximal joint to the child joint or the segment's end
            end = children[0].offset if children else np.array([0.0, seg.length, 0.0]) * (
                1.0 if base == "head" else -1.0)  # fmt: skip
            pts, pairs = [origin, end], [(0, 1)]
        marks.append(np.array(pts, dtype=float))
        sticks.append(pairs)
    return marks, sticks


MAX_PERIOD_S = 10.0
"""The longest cycle animated: a longer time axis is not a gait cycle in seconds."""


def _real(value: object) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool) and math.isfinite(
        float(value))  # fmt: skip


def cycle_period(pred: PredictedCycle) -> float:
    """The period the animation plays, s: the span of ``pred.time``, or one sample step more
    when the summary's ``descriptors.period`` says so (:func:`summary_period`). Raises
    ValueError (one line) for another summary period or a span of no gait cycle."""
    span = float(pred.time[-1] - pred.time[0])
    if not (0.0 < span <= MAX_PERIOD_S):
        raise ValueError(f"the cycle's time axis spans {span:.6g} s, not a gait cycle "
                         f"(0-{MAX_PERIOD_S:g} s)")  # fmt: skip
    d = pred.summary.get("descriptors")
    if d is None or (isinstance(d, dict) and "period" not in d):
        return span
    if not isinstance(d, dict):
        raise ValueError("the summary's descriptors is not an object")
    return summary_period(pred.time, d["period"], "descriptors.period")


def _cycle_samples(pred: PredictedCycle) -> tuple[float, np.ndarray, np.ndarray]:
    """The period, the sample times of one closed cycle ``[t0, t0 + T]`` and the indices of
    the samples used (the first one repeated, moved a stride on, if the last is not at T)."""
    t = pred.time - pred.time[0]
    period = cycle_period(pred)
    if period == float(t[-1]):
        return period, t, np.arange(t.size)
    return period, np.append(t, period), np.append(np.arange(t.size), 0)


def _stride(pred: PredictedCycle, period: float, closed: bool) -> np.ndarray:
    if closed:
        return pred.pelvis_position[-1] - pred.pelvis_position[0]
    d = pred.summary.get("descriptors") or {}
    speed = d.get("speed", 0.0) if isinstance(d, dict) else 0.0
    if not _real(speed):
        raise ValueError(f"the summary's descriptors.speed {speed!r:.40} is not a number")
    return np.array([float(speed) * period, 0.0, 0.0])


def animation_frames(
    pred: PredictedCycle,
    body: BodyModel,
    *,
    cycles: int = 2,
    fps: float = 30.0,
    grf_scale: float = 1.0,
) -> AnimationFrames:
    """The geometry of ``round(cycles * T * fps)`` frames at real speed (see the module doc).

    Raises:
        ValueError: ``cycles`` or ``fps`` is not positive, or the prediction's period is not
            its time axis's (:func:`cycle_period`).
    """
    if cycles < 1 or not (math.isfinite(fps) and fps > 0.0):
        raise ValueError(f"cycles must be >= 1 and fps > 0, got {cycles} and {fps}")
    period, t_cycle, idx = _cycle_samples(pred)
    closed = idx[-1] != 0 or idx.size == 1
    stride = _stride(pred, period, closed)
    n_frames = max(1, round(cycles * period * fps))
    time = np.arange(n_frames) / fps
    cycle = np.floor(time / period + 1e-12).astype(int)
    tau = np.clip(time - cycle * period, 0.0, period)
    k = np.clip(np.searchsorted(t_cycle, tau, side="right") - 1, 0, t_cycle.size - 2)
    w = ((tau - t_cycle[k]) / (t_cycle[k + 1] - t_cycle[k]))[:, None]
    a, b = idx[k], idx[k + 1]
    wrap = (b == 0) & (a != 0)  # the appended sample: cycle 0's first, a stride on
    offset = cycle[:, None] * stride[None, :]  # (F, 3)

    def lerp(x: np.ndarray, shift: bool) -> np.ndarray:
        xb = x[b] + (wrap[:, None] * stride).reshape((-1,) + (1,) * (x.ndim - 2) + (3,)) * shift
        out = (1.0 - w.reshape((-1,) + (1,) * (x.ndim - 1))) * x[a]
        out = out + w.reshape((-1,) + (1,) * (x.ndim - 1)) * xb
        if shift:
            out = out + offset.reshape((-1,) + (1,) * (x.ndim - 2) + (3,))
        return out

    com = lerp(pred.segment_com_position, True)  # (F, S, 3)
    qa, qb = pred.segment_orientation[a], pred.segment_orientation[b]
    sign = np.where(np.sum(qa * qb, axis=-1, keepdims=True) < 0.0, -1.0, 1.0)
    q = (1.0 - w[:, :, None]) * qa + w[:, :, None] * sign * qb
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    rot = quaternion.to_matrix(q)  # (F, S, 3, 3)

    marks, sticks = segment_landmarks(body)
    points, lines, sides, owner = [], [], [], []
    feet: dict[str, list[int]] = {"r": [], "l": []}
    start = 0
    for i, (local, pairs) in enumerate(zip(marks, sticks, strict=True)):
        rel = local - np.asarray(body.segments[i].com)
        points.append(com[:, i, None, :] + np.einsum("fij,kj->fki", rot[:, i], rel))
        name = body.segments[i].name
        side = name[-1] if name[-2:] in ("_r", "_l") else ""
        lines += [(start + p, start + r) for p, r in pairs]
        sides += [side] * len(pairs)
        owner += [i] * len(local)
        if name.startswith("foot_"):
            feet[side] += list(range(start, start + len(local)))
        start += len(local)

    weight = float(np.sum(pred.segment_mass)) * G
    force = lerp(pred.grf_force, False)
    cop = lerp(pred.grf_cop, True)
    # loaded where both neighbouring samples are: at a touch-down sample the force is small
    # and its centre of pressure (moment / force) not yet meaningful
    on = np.all(np.isfinite(pred.grf_cop), axis=-1) & (
        pred.grf_force[..., 1] > LOADED_FRACTION * weight
    )
    loaded = on[a] & on[b]
    cop = np.where(loaded[..., None], cop, np.nan)
    tip = cop + force * (grf_scale / weight)
    return AnimationFrames(
        time=time,
        points=np.concatenate(points, axis=1),
        lines=np.array(lines, dtype=int),
        line_side=tuple(sides),
        point_segment=np.array(owner, dtype=int),
        foot_points={s: np.array(v, dtype=int) for s, v in feet.items()},
        cop=cop,
        grf_tip=tip,
        loaded=loaded,
        pelvis=lerp(pred.pelvis_position, True),
        stride=stride,
        period=period,
        grf_scale=grf_scale,
    )
