"""Gait events from vertical ground reaction force, and cycle normalisation.

Contact detection is a Schmitt trigger: a contact starts when the vertical force rises above
``threshold`` and ends when it falls below ``threshold - hysteresis``. Contacts shorter than
``min_contact`` are dropped first (noise spikes, a foot brushing the plate), then contacts
separated by a gap shorter than ``min_gap`` are merged (force dipping during a stance). Event
times are linearly interpolated between samples at the level crossed. A contact already under
way at the first sample has no heel strike, and one still under way at the last sample has no
toe off. NaN forces count as "no contact".

All arrays have time as their first axis; cycle-normalised arrays have percent of cycle as
their first axis and cycles as their second.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

__all__ = [
    "FootEvents",
    "detect_contacts",
    "detect_foot_events",
    "mean_sd",
    "normalize_cycles",
    "percent_axis",
    "stride_periods",
]


@dataclass(frozen=True)
class FootEvents:
    """Heel-strike and toe-off times (s) of one foot, each sorted ascending."""

    heel_strikes: np.ndarray
    toe_offs: np.ndarray

    @property
    def stride_times(self) -> np.ndarray:
        """Durations between consecutive heel strikes (s)."""
        return np.diff(self.heel_strikes)


def _crossing(time: np.ndarray, force: np.ndarray, i: int, level: float) -> float:
    """Time at which the force crosses ``level`` between samples ``i - 1`` and ``i``."""
    f0, f1 = force[i - 1], force[i]
    if not (np.isfinite(f0) and np.isfinite(f1)) or f1 == f0:
        return float(time[i])
    frac = min(max((level - f0) / (f1 - f0), 0.0), 1.0)
    return float(time[i - 1] + frac * (time[i] - time[i - 1]))


def detect_contacts(
    time: ArrayLike,
    vertical_force: ArrayLike,
    threshold: float = 20.0,
    *,
    hysteresis: float | None = None,
    min_contact: float = 0.1,
    min_gap: float = 0.05,
) -> FootEvents:
    """Heel strikes and toe offs of one foot (or plate) from its vertical force.

    Args:
        time: Sample times (s), shape ``(N,)``, increasing.
        vertical_force: Vertical force (N), shape ``(N,)``; positive when loaded.
        threshold: Force (N) above which a contact starts.
        hysteresis: A contact ends below ``threshold - hysteresis``; default a quarter of
            ``threshold``. Must satisfy ``0 <= hysteresis < threshold``.
        min_contact: Contacts shorter than this (s) are ignored.
        min_gap: Gaps between contacts shorter than this (s) are bridged.
    """
    t = np.asarray(time, dtype=float).reshape(-1)
    f = np.asarray(vertical_force, dtype=float).reshape(-1)
    if t.shape != f.shape:
        raise ValueError(f"time {t.shape} and force {f.shape} differ in length")
    if t.size > 1 and np.any(np.diff(t) <= 0):
        raise ValueError("time must be strictly increasing")
    hyst = 0.25 * threshold if hysteresis is None else float(hysteresis)
    if threshold <= 0 or not 0 <= hyst < threshold:
        raise ValueError("need threshold > 0 and 0 <= hysteresis < threshold")
    off_level = threshold - hyst

    intervals: list[list[float]] = []
    on = bool(t.size) and np.isfinite(f[0]) and f[0] > threshold
    start = -np.inf if on else np.nan
    for i in range(1, t.size):
        fi = f[i]
        if not on and np.isfinite(fi) and fi > threshold:
            on, start = True, _crossing(t, f, i, threshold)
        elif on and not (np.isfinite(fi) and fi >= off_level):
            on = False
            intervals.append([start, _crossing(t, f, i, off_level)])
    if on:
        intervals.append([start, np.inf])

    kept = [
        iv for iv in intervals if not (np.isfinite(iv[1] - iv[0]) and iv[1] - iv[0] < min_contact)
    ]
    merged: list[list[float]] = []
    for interval in kept:
        if merged and interval[0] - merged[-1][1] < min_gap:
            merged[-1][1] = interval[1]
        else:
            merged.append(interval)
    strikes = np.array([a for a, _ in merged if np.isfinite(a)], dtype=float)
    offs = np.array([b for _, b in merged if np.isfinite(b)], dtype=float)
    return FootEvents(strikes, offs)


def detect_foot_events(
    time: ArrayLike,
    vertical_forces: Mapping[str, ArrayLike],
    threshold: float = 20.0,
    **options: float,
) -> dict[str, FootEvents]:
    """:func:`detect_contacts` for each named force, e.g. ``{"right": fy_r, "left": fy_l}``."""
    return {
        side: detect_contacts(time, force, threshold, **options)
        for side, force in vertical_forces.items()
    }


def percent_axis(n: int = 101) -> np.ndarray:
    """``n`` equally spaced percent-of-cycle values from 0 to 100."""
    return np.linspace(0.0, 100.0, n)


def normalize_cycles(
    time: ArrayLike, signal: ArrayLike, heel_strikes: ArrayLike, n: int = 101
) -> np.ndarray:
    """Cut ``signal`` into cycles between consecutive heel strikes, each resampled to ``n`` points.

    Only cycles that lie entirely within ``[time[0], time[-1]]`` are used; values are linearly
    interpolated. Point ``k`` of a cycle is at ``k / (n - 1) * 100`` % (0 % and 100 % are the two
    heel strikes).

    Args:
        time: ``(N,)`` increasing sample times.
        signal: ``(N, ...)`` samples.
        heel_strikes: Heel-strike times of one foot.
        n: Points per cycle (at least 2).

    Returns:
        Array of shape ``(n, n_cycles, ...)`` (percent first, then cycles).
    """
    t = np.asarray(time, dtype=float).reshape(-1)
    y = np.asarray(signal, dtype=float)
    if y.shape[:1] != t.shape:
        raise ValueError(f"signal's first axis {y.shape[:1]} must match time {t.shape}")
    if n < 2:
        raise ValueError("n must be at least 2")
    hs = np.sort(np.asarray(heel_strikes, dtype=float).reshape(-1))
    flat = y.reshape(t.size, -1)
    cycles = []
    for start, stop in zip(hs[:-1], hs[1:], strict=True):
        if t.size < 2 or start < t[0] or stop > t[-1] or stop <= start:
            continue
        grid = np.linspace(start, stop, n)
        cycles.append(np.column_stack([np.interp(grid, t, col) for col in flat.T]))
    out = np.stack(cycles, axis=1) if cycles else np.empty((n, 0, flat.shape[1]))
    return out.reshape((n, len(cycles), *y.shape[1:]))


def mean_sd(*cycle_sets: ArrayLike, ddof: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Mean and standard deviation across cycles, pooling cycles of several trials.

    Args:
        cycle_sets: One or more arrays ``(n, n_cycles_i, ...)`` from :func:`normalize_cycles`
            (same ``n`` and trailing shape); their cycles are pooled.
        ddof: Delta degrees of freedom of the SD (1: sample SD).

    Returns:
        ``(mean, sd)``, each ``(n, ...)``. NaN samples are ignored; where fewer than
        ``ddof + 1`` values remain the SD is NaN (and the mean NaN where none remain).
    """
    if not cycle_sets:
        raise ValueError("mean_sd needs at least one set of cycles")
    pooled = np.concatenate([np.asarray(c, dtype=float) for c in cycle_sets], axis=1)
    valid = np.isfinite(pooled)
    count = valid.sum(axis=1)
    total = np.where(valid, pooled, 0.0).sum(axis=1)
    mean = np.divide(total, count, out=np.full(total.shape, np.nan), where=count > 0)
    dev = np.where(valid, pooled - np.expand_dims(mean, 1), 0.0)
    denom = count - ddof
    var = np.divide((dev**2).sum(axis=1), denom, out=np.full(total.shape, np.nan), where=denom > 0)
    return mean, np.sqrt(var)


def stride_periods(events: Mapping[str, FootEvents] | Sequence[FootEvents]) -> np.ndarray:
    """All heel-strike-to-heel-strike durations (s) of the given feet, pooled."""
    items = events.values() if isinstance(events, Mapping) else events
    parts = [e.stride_times for e in items]
    return np.concatenate(parts) if parts else np.zeros(0)
