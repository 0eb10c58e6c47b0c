"""The period a result's summary records, checked against its time axis: a damaged value
(``Infinity``, ``1e7``, ``[1]``) is refused with one line rather than sizing arrays or
misaligning the cycle."""

from __future__ import annotations

import math
import numbers

import numpy as np

__all__ = ["PERIOD_TOLERANCE", "summary_period"]

PERIOD_TOLERANCE = 1e-6
"""Relative difference allowed between a recorded period and the time axis's span."""


def summary_period(time: np.ndarray, value: object, name: str) -> float:
    """``value`` (the summary's ``name``) as the period of the cycle sampled at ``time``: the
    span of ``time`` (a closed cycle) or up to one sample step more (the sample at T not
    stored). Raises ValueError, one line naming ``name``, for any other value."""
    t = np.asarray(time, dtype=float) - float(time[0])
    span = float(t[-1])
    real = isinstance(value, numbers.Real) and not isinstance(value, bool)
    if real and math.isfinite(float(value)) and span > 0.0:
        given = float(value)
        step = float(np.max(np.diff(t))) if t.size > 1 else 0.0
        if abs(given - span) <= PERIOD_TOLERANCE * span:
            return span
        if span < given <= (span + step) * (1.0 + PERIOD_TOLERANCE):
            return given
    raise ValueError(f"the summary's {name} {value!r:.40} is not the cycle's period: its time "
                     f"spans {span:.6g} s")  # fmt: skip
