"""Gait descriptors V, T and Td of a measured trial (IK ``.mot`` + GRF ``.mot``).

* **Events**: heel strikes and toe offs of each foot from its vertical force
  (:func:`walk3d.trials.events.detect_foot_events`, 20 N threshold by default). Feet are
  assigned to plates by :func:`walk3d.io.extract_foot_loads`.
* **Period T**, first method that applies:

  1. ``strides``: the mean heel-strike-to-heel-strike time of the same foot, when some foot
     struck twice on the plates (treadmills, long walkways);
  2. ``kinematic half-cycle lag``: twice the time shift that best maps the right leg's sagittal
     angles (hip flexion, knee, ankle) onto the left leg's, searched within ±30 % of the plate
     step time. Overground trials usually have one plate per foot and so no stride; the lag uses
     the whole trial instead of a single step, which makes it insensitive to the step-to-step
     asymmetry a single step carries (the Falisse 2019 trial: step 0.555 s, lag 0.536 s);
  3. ``steps``: twice the mean time between heel strikes of opposite feet.
* **Double support Td**: the mean time from a heel strike to the other foot's toe off, over the
  double-support phases fully seen on the plates.
* **Speed V**: the slope of ``pelvis_tx`` over the IK trial (least squares). A treadmill trial
  does not progress (|slope| < 0.2 m/s): pass the belt speed.
* **Stance fraction**: mean duration of complete contacts / T (a check: ``0.5 + Td/T`` in a
  symmetric gait).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from os import PathLike

import numpy as np

from walk3d.io.external_loads import FootLoads, extract_foot_loads, find_plates
from walk3d.io.storage import Storage, read_storage
from walk3d.trials.events import FootEvents, detect_foot_events, stride_periods

__all__ = [
    "GaitDescriptors",
    "descriptors_from_trial",
    "foot_events",
    "foot_loads",
    "half_cycle_lag",
]

_SAGITTAL = ("hip_flexion", "knee_angle", "ankle_angle")


@dataclass(frozen=True)
class GaitDescriptors:
    """Measured descriptors of a trial (SI units)."""

    speed: float
    period: float
    double_support: float
    stance_fraction: float
    period_method: str
    events: dict[str, FootEvents] = field(default_factory=dict)
    notes: tuple[str, ...] = ()

    def as_dict(self) -> dict:
        return {
            "speed_m_per_s": self.speed,
            "period_s": self.period,
            "double_support_s": self.double_support,
            "stance_fraction": self.stance_fraction,
            "period_method": self.period_method,
            "notes": list(self.notes),
        }


def _as_storage(x: Storage | str | PathLike[str]) -> Storage:
    return x if isinstance(x, Storage) else read_storage(x)


def foot_loads(x: FootLoads | Storage | str | PathLike[str]) -> FootLoads:
    """Foot loads of a GRF file or storage (a clear error when it has no plate columns)."""
    if isinstance(x, FootLoads):
        return x
    storage = _as_storage(x)
    if not find_plates(storage):
        where = storage.path.name if storage.path is not None else "the GRF storage"
        raise ValueError(f"{where} has no ground reaction columns (ground_force_v[xyz])")
    return extract_foot_loads(storage)


def foot_events(loads: FootLoads, threshold: float = 20.0) -> dict[str, FootEvents]:
    """Heel strikes and toe offs of ``right`` and ``left`` from the feet's vertical forces."""
    forces = {"right": loads.right.force[:, 1], "left": loads.left.force[:, 1]}
    return detect_foot_events(loads.time, forces, threshold)


def _steps(events: dict[str, FootEvents]) -> np.ndarray:
    strikes = sorted([(float(t), side) for side, ev in events.items() for t in ev.heel_strikes])
    return np.array(
        [b[0] - a[0] for a, b in zip(strikes[:-1], strikes[1:], strict=True) if a[1] != b[1]]
    )


def half_cycle_lag(ik: Storage, guess: float | None = None, spread: float = 0.3) -> float:
    """Shift ``τ`` (s) minimising the mismatch of ``q_l(t)`` and ``q_r(t - τ)`` and of
    ``q_r(t)`` and ``q_l(t - τ)`` (sagittal leg angles), searched in ``guess·(1 ± spread)``
    (default guess 0.55 s) and refined by a parabola through the best three shifts."""
    t = ik.time
    pairs = []
    for c in _SAGITTAL:
        if ik.has_column(f"{c}_r") and ik.has_column(f"{c}_l"):
            pairs.append((ik.column(f"{c}_r"), ik.column(f"{c}_l")))
    if not pairs:
        raise ValueError("the IK file has no left and right sagittal leg angles")
    g = 0.55 if guess is None else float(guess)
    lo, hi = g * (1 - spread), min(g * (1 + spread), 0.8 * (t[-1] - t[0]))
    # half the median sampling step, but no finer than 4 lags per sample over the span
    dt = max(float(np.median(np.diff(t))), (hi - lo) / (2 * len(t)))
    short = not (hi - lo > dt)  # fewer than 3 lags dt/2 apart: known before any is made
    lags = np.zeros(0) if short else np.arange(lo, hi, dt / 2)
    if lags.size < 3:
        raise ValueError("the IK trial is too short to find the half-cycle lag")
    cost = np.zeros(lags.size)
    for i, tau in enumerate(lags):
        m = t + tau <= t[-1]
        total = 0.0
        for r, left in pairs:
            total += np.mean((np.interp(t[m] + tau, t, r) - left[m]) ** 2)
            total += np.mean((np.interp(t[m] + tau, t, left) - r[m]) ** 2)
        cost[i] = total
    k = int(np.clip(np.argmin(cost), 1, lags.size - 2))
    c0, c1, c2 = cost[k - 1 : k + 2]
    denom = c0 - 2 * c1 + c2
    shift = 0.5 * (c0 - c2) / denom if denom > 0 else 0.0
    return float(lags[k] + np.clip(shift, -1, 1) * (lags[1] - lags[0]))


def _double_supports(events: dict[str, FootEvents], loads: FootLoads, threshold: float):
    out = []
    for side, other in (("right", "left"), ("left", "right")):
        f_other = loads.foot(other).force[:, 1]
        for hs in events[side].heel_strikes:
            loaded = np.interp(hs, loads.time, f_other) > threshold
            later = events[other].toe_offs[events[other].toe_offs > hs]
            if loaded and later.size:
                out.append(float(later[0] - hs))
    return np.array(out)


def _stances(events: dict[str, FootEvents]) -> np.ndarray:
    out = []
    for ev in events.values():
        for hs in ev.heel_strikes:
            later = ev.toe_offs[ev.toe_offs > hs]
            if later.size:
                out.append(float(later[0] - hs))
    return np.array(out)


def descriptors_from_trial(
    ik: Storage | str | PathLike[str] | None,
    grf: FootLoads | Storage | str | PathLike[str],
    *,
    threshold: float = 20.0,
    speed: float | None = None,
) -> GaitDescriptors:
    """V, T and Td of a trial (see the module doc).

    Args:
        ik: IK coordinates (``pelvis_tx`` for V, leg angles for the half-cycle lag); may be
            None when ``speed`` is given and some foot strikes twice on the plates.
        grf: Ground reactions (path, storage or already assigned foot loads).
        speed: Known speed (e.g. a treadmill's belt speed), m/s; replaces the pelvis estimate.

    Raises:
        ValueError: Too few events for a period or a double support, or no usable speed.
        DataFileError: A file is malformed.
    """
    loads = foot_loads(grf)
    storage = None if ik is None else _as_storage(ik)
    events = foot_events(loads, threshold)
    notes = []
    strides = stride_periods(events)
    steps = _steps(events)
    if strides.size:
        period, method = float(np.mean(strides)), "strides"
    elif storage is not None and steps.size:
        period = 2.0 * half_cycle_lag(storage, guess=float(np.mean(steps)))
        method = "kinematic half-cycle lag"
        notes.append(f"plate step time {np.mean(steps):.4f} s (x2 = {2 * np.mean(steps):.4f} s)")
    elif steps.size:
        period, method = 2.0 * float(np.mean(steps)), "steps"
    else:
        raise ValueError("no stride or step on the force plates: cannot find the gait period")
    ds = _double_supports(events, loads, threshold)
    if ds.size == 0:
        raise ValueError("no double-support phase fully on the force plates: cannot find Td")
    double_support = float(np.mean(ds))
    stances = _stances(events)
    stance = float(np.mean(stances)) / period if stances.size else 0.5 + double_support / period
    if speed is None:
        if storage is None or not storage.has_column("pelvis_tx"):
            raise ValueError("the speed needs pelvis_tx in an IK file (or pass the speed)")
        slope = float(np.polyfit(storage.time, storage.column("pelvis_tx"), 1)[0])
        if abs(slope) < 0.2:
            raise ValueError(
                f"the pelvis progresses at {slope:.3f} m/s only (treadmill?): pass the belt speed"
            )
        if slope < 0:
            notes.append("the subject walks along -x: speed taken as |slope|")
        speed = abs(slope)
    notes.append(f"{ds.size} double-support phase(s), {stances.size} complete stance(s)")
    return GaitDescriptors(
        float(speed), period, double_support, stance, method, events, tuple(notes)
    )
