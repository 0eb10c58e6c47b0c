"""A prediction as a motion-capture lab trial: ``markers.c3d``.

:func:`write_markers_c3d` writes the virtual Plug-in Gait markers (:mod:`walk3d.results.markers`)
and each foot's ground reaction on a force platform, so that clinical gait software reads a
prediction like a walk over two plates.

* **Frames.** The prediction's own samples (a closed cycle: the last sample repeats the first
  one period later, a stride on), at ``(N - 1) / T`` Hz, repeated periodically and moved a
  stride forward per period. The trial starts at the right heel strike and lasts one period
  plus the double support that completes the left stance begun in it, plus one sample, so that
  each foot has one complete stance (:func:`lab_trial`).
* **Plates.** Plate 1 lies under the right foot's complete stance, plate 2 under the left's,
  fixed on the floor: the rectangle, along the walking direction, around the centre of
  pressure and the foot's heel, toe and metatarsal heads at every sample of that stance where
  the foot carries at least :data:`LOADED_SHARE` of body weight, widened by
  :data:`PLATE_MARGIN`. A plate carries only its foot's load and only during that stance; the
  foot's partial contacts at the trial's two ends (in double support) fall beside the plates,
  as in a lab. Between samples, force and moment about the plate centre are interpolated
  linearly to :data:`ANALOG_RATIO` analog samples per frame, from the foot strike (no ramp
  before it) to the first unloaded sample. The plates record the load of
  the foot **on** the plate (the negative of walk3d's ground reaction), as a real plate does.
* **Lab frame.** Z up, as in most labs: lab ``(X, Y, Z)`` = walk3d ``(X, -Z, Y)``, i.e. X
  forward, Y to the walker's left (:data:`LAB_FROM_WALK3D`); millimetres in the file.
* **Events.** ``Foot Strike`` at a foot's first loaded sample, ``Foot Off`` at its first
  unloaded one, ``Right``/``Left`` context, for every one inside the trial.

``pred`` is a :class:`walk3d.results.prediction.PredictedCycle` (not imported: that module writes
this file).
"""

from __future__ import annotations

from dataclasses import dataclass
from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np

from walk3d.body.model import BodyModel
from walk3d.constants import G
from walk3d.io.c3d_write import C3dEvent, PlateLoads, file_rate, write_c3d
from walk3d.results.markers import Marker, marker_positions, marker_set

__all__ = [
    "ANALOG_RATIO",
    "LAB_FROM_WALK3D",
    "LOADED_SHARE",
    "PLATE_MARGIN",
    "LabTrial",
    "lab_trial",
    "plate_loads",
    "write_markers_c3d",
]

LAB_FROM_WALK3D = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
"""``v_lab = LAB_FROM_WALK3D @ v``: X forward, Y left, Z up."""
ANALOG_RATIO = 10
"""Analog samples per frame: about 1 kHz at walk3d's ~92 samples/s, a usual plate rate."""
LOADED_SHARE = 0.05
"""The plates enclose the sole over the samples where the foot carries this share of body
weight."""
COP_SHARE = 0.2
"""The plates also enclose the centre of pressure where the foot carries this share: at a
touch-down sample walk3d's centre of pressure is a quotient of small moments and can lie a
metre off the foot at 6 % of body weight (docs/c3d.md)."""
PLATE_MARGIN = 0.02
"""m added around the footprint on every side."""
SIDES = ("Right", "Left")


@dataclass(frozen=True)
class LabTrial:
    """Where the trial lies on the periodic prediction (module doc)."""

    samples: np.ndarray
    """(F,) unwrapped sample index of each frame: sample ``k % M`` moved ``k // M`` strides."""
    period_samples: int
    """``M = N - 1``: samples per period."""
    rate: float
    """Frames per second as written: ``M / T`` rounded by :func:`walk3d.io.c3d_write.file_rate`
    (under 10 ppm off at walk3d's rates)."""
    stride: np.ndarray
    """(3,) m, global displacement per period."""
    stances: np.ndarray
    """(2, 2) unwrapped first and last loaded sample of the [right, left] plate stance."""
    runs: np.ndarray
    """(2, 2) first loaded sample (0 <= k < M) and number of loaded samples, per foot."""


def _loaded_run(loaded: np.ndarray) -> tuple[int, int]:
    """First sample and length of the longest cyclic run of ``True`` ((0, 0) if none)."""
    m = loaded.size
    if loaded.all():
        return 0, m
    if not loaded.any():
        return 0, 0
    start = int(np.flatnonzero(~loaded)[0]) + 1  # scan from just after an unloaded sample
    best, k = (0, 0), 0
    while k < m:
        if loaded[(start + k) % m]:
            j = k
            while j < m and loaded[(start + j) % m]:
                j += 1
            if j - k > best[1]:
                best = ((start + k) % m, j - k)
            k = j
        else:
            k += 1
    return best


def lab_trial(pred: Any) -> LabTrial:
    """The trial's frames and plate stances on ``pred`` (module doc).

    Raises:
        ValueError: Fewer than 3 samples, or samples not evenly spaced.
    """
    t = pred.time
    if t.size < 3:
        raise ValueError(f"a lab trial needs at least 3 samples, got {t.size}")
    m = t.size - 1
    period = float(t[-1] - t[0])
    if not (period > 0 and np.allclose(np.diff(t), period / m, rtol=1e-6, atol=0.0)):
        raise ValueError("a lab trial needs evenly spaced samples over the period")
    force = pred.grf_force[:m]
    loaded = np.any(force != 0.0, axis=-1) | (pred.grf_free_moment[:m] != 0.0)  # (M, 2)
    runs = np.array([_loaded_run(loaded[:, k]) for k in range(2)])
    start = int(runs[0, 0])
    first_left = start + (int(runs[1, 0]) - start) % m
    stances = np.array([[start, start + max(runs[0, 1], 1) - 1],
                        [first_left, first_left + max(runs[1, 1], 1) - 1]])  # fmt: skip
    end = max(start + m, int(stances[:, 1].max()) + 1)
    return LabTrial(
        samples=np.arange(start, end + 1),
        period_samples=m,
        rate=file_rate(m / period),
        stride=pred.pelvis_position[-1] - pred.pelvis_position[0],
        stances=stances,
        runs=runs,
    )


def _unwrapped(trial: LabTrial, values: np.ndarray, k: np.ndarray) -> np.ndarray:
    """Positions ``values`` (N, ..., 3) at unwrapped samples ``k``, moved on by the strides."""
    m = trial.period_samples
    shift = (k // m).reshape((-1,) + (1,) * (values.ndim - 1)) * trial.stride
    return values[k % m] + shift


def _footprint(pred: Any, body: BodyModel, trial: LabTrial, foot: int) -> np.ndarray:
    """(4, 3) plate corners (walk3d frame, on the floor), C3D-numbered for a plate frame with
    x forward, y to the right and z down."""
    side = "rl"[foot]
    first, last = trial.stances[foot]
    k = np.arange(first, last + 1)
    weight = pred.body_mass * G
    fy = pred.grf_force[k % trial.period_samples, foot, 1]
    strong, firm = k[fy >= LOADED_SHARE * weight], k[fy >= COP_SHARE * weight]
    k = strong if strong.size else k
    sole = [Marker(n, f"foot_{side}", p) for n, p in zip("htam", body.foot.points(side),
                                                         strict=True)]  # fmt: skip
    pts = [_unwrapped(trial, marker_positions(pred, body, sole), k).reshape(-1, 3)]
    cop = _unwrapped(trial, pred.grf_cop[:, foot], firm)
    pts.append(cop[np.all(np.isfinite(cop), axis=1)])
    xz = np.concatenate(pts)[:, [0, 2]]
    (x0, z0), (x1, z1) = xz.min(axis=0) - PLATE_MARGIN, xz.max(axis=0) + PLATE_MARGIN
    return np.array([[x1, 0.0, z1], [x0, 0.0, z1], [x0, 0.0, z0], [x1, 0.0, z0]])


def plate_loads(
    pred: Any, trial: LabTrial, foot: int, corners: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Reaction force (N) and moment about the plate centre (N m) on ``foot``, walk3d frame,
    ``(F * ANALOG_RATIO, 3)`` each at the analog samples: linear between the frames of the
    stance, from its first sample (the foot strike) to the first unloaded one (the foot off),
    zero elsewhere."""
    m = trial.period_samples
    k = np.append(trial.samples, trial.samples[-1] + 1)
    on = (k >= trial.stances[foot, 0]) & (k <= trial.stances[foot, 1])
    force = np.where(on[:, None], pred.grf_force[k % m, foot], 0.0)
    cop = _unwrapped(trial, pred.grf_cop[:, foot], k)
    arm = np.where(np.isfinite(cop), cop - corners.mean(axis=0), 0.0)
    free = np.where(on, pred.grf_free_moment[k % m, foot], 0.0)
    moment = np.cross(arm, force) + free[:, None] * np.array([0.0, 1.0, 0.0])
    w = (np.arange(ANALOG_RATIO) / ANALOG_RATIO)[None, :, None]
    out = []
    for v in (force, moment):
        a = (1.0 - w) * v[:-1, None, :] + w * v[1:, None, :]
        a[~on[:-1]] = 0.0  # no ramp before the foot strike
        out.append(a.reshape(-1, 3))
    return out[0], out[1]


def _events(trial: LabTrial) -> list[C3dEvent]:
    m, first, last = trial.period_samples, trial.samples[0], trial.samples[-1]
    events = []
    for foot, (start, length) in enumerate(trial.runs):
        if length in (0, m):
            continue
        for label, at in (("Foot Strike", start), ("Foot Off", start + length)):
            k = first + (at - first) % m
            while k <= last:
                events.append(C3dEvent(SIDES[foot], label, float((k - first) / trial.rate)))
                k += m
    return sorted(events, key=lambda e: e.time)


def write_markers_c3d(path: str | PathLike[str], pred: Any, body: BodyModel) -> Path:
    """Write ``markers.c3d`` of ``pred`` (module doc), atomically; returns its path."""
    trial = lab_trial(pred)
    markers = marker_set(body)
    points = _unwrapped(trial, marker_positions(pred, body, markers), trial.samples)
    plates = []
    for foot in range(2):
        corners = _footprint(pred, body, trial, foot)
        force, moment = plate_loads(pred, trial, foot, corners)
        lab = LAB_FROM_WALK3D.T
        plates.append(PlateLoads(corners @ lab, -force @ lab, -moment @ lab))
    return write_c3d(
        path,
        [m.label for m in markers],
        points @ LAB_FROM_WALK3D.T,
        trial.rate,
        plates=plates,
        analog_ratio=ANALOG_RATIO,
        events=_events(trial),
        descriptions=[f"walk3d virtual marker on {m.segment}" for m in markers],
    )
