"""One number for how human a prediction is: the yardstick's errors, each over its bar.

Every part is dimensionless and reads 1 at the bar of issue #59 (the realism benchmark's
limits), so no unit dominates by its size:

* angle and GRF RMSE over their bar (:data:`RMSE_BARS`);
* the knee's peak in loading (0–40 % of the cycle, as ``shared/tools/realism.py``) against the
  measured one, over :data:`KNEE_PEAK_SCALE`;
* ``(1 − r) / (1 − bar)`` of the sagittal moments (:data:`MOMENT_R_BARS`), where measured;
* guards that count only beyond their limit (:data:`GUARDS`): pelvis rotation range, step
  width, roughness;
* ``|Td − Td_measured| / (0.15 Td_measured)`` when Td was predicted and a measured Td is known.

The score is the mean of the parts present, each capped at :data:`CAP` so that one wild row
cannot hide the rest; a solve that did not converge, or a gait that does not walk, scores
:data:`FAILED`. Lower is better; below 1 every row is within its bar on average.

A reference that lacks some :data:`SCORED` quantities gives a *partial* score
(:attr:`Score.missing` names them): the mean of fewer parts, which may read better than a full
one and is not comparable with it. A reference that holds none of them scores nothing
(:func:`check_scored`): the guards alone would read 0, better than any real comparison.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from walk3d.results.labels import is_converged
from walk3d.validation.compare import Comparison
from walk3d.validation.reference import Reference

__all__ = ["CAP", "FAILED", "GUARDS", "KNEE_PEAK_SCALE", "MOMENT_R_BARS", "RMSE_BARS", "SCORED",
           "Score", "check_scored", "knee_loading_peak", "missing_scored", "score",
           "score_json", "scored_name"]  # fmt: skip

RMSE_BARS: dict[str, float] = {
    "angle:knee_flexion": 7.0,
    "angle:hip_flexion": 7.0,
    "angle:ankle_dorsiflexion": 5.0,
    "grf:grf_vertical": 1.2,
    "grf:grf_fore_aft": 0.6,
}
"""RMSE bars (deg, N/kg): issue #59's done-when rows for the Falisse subject."""
MOMENT_R_BARS: dict[str, float] = {
    "moment:knee_flexion": 0.8,
    "moment:ankle_dorsiflexion": 0.9,
    "moment:hip_flexion": 0.6,
}
"""Lowest acceptable r of the sagittal moments (issue #41's bar)."""
SCORED = (*RMSE_BARS, *MOMENT_R_BARS)
"""The measured quantities the score compares (the knee's peak comes with the knee angle)."""
KNEE_PEAK_SCALE = 8.0
"""deg: a loading knee 8° from the measured peak costs as much as an angle at its bar (the
measured adults' loading peaks span about 22–28°)."""
GUARDS: dict[str, tuple[float, float, float]] = {
    "pelvis_rotation_range_deg": (0.0, 12.0, 12.0),
    "step_width_m": (0.05, 0.15, 0.05),
    "roughness_worst": (0.0, 0.15, 0.15),
}
"""``(low, high, scale)`` of the reference-free checks (summary ``gait_checks``): a part is
the distance outside ``[low, high]`` over ``scale``, zero inside."""
TD_SCALE = 0.15
"""Fraction of the measured Td that a predicted Td may miss by at the bar (issue #59)."""
CAP = 5.0
"""Largest value of one part."""
FAILED = 10.0
"""Score of a solve that did not converge or a gait that does not walk: worse than any
capped mean."""
LOADING_END = 40
"""Last percent of the cycle that counts as loading for the knee's peak (the yardstick's)."""


@dataclass(frozen=True)
class Score:
    """A prediction's score and the parts behind it (all dimensionless)."""

    total: float
    parts: dict[str, float] = field(default_factory=dict)
    figures: dict[str, float] = field(default_factory=dict)
    """The raw figures (deg, N/kg, r, m) the parts come from."""
    failed: str | None = None
    """Why the prediction scored :data:`FAILED` (None when it was scored)."""
    missing: tuple[str, ...] = ()
    """The :data:`SCORED` quantities the reference lacks: the score is partial when any."""

    @property
    def partial(self) -> bool:
        """Whether the reference lacked a scored quantity (module doc)."""
        return bool(self.missing)


def scored_name(key: str) -> str:
    """``knee_flexion angle`` for the key ``angle:knee_flexion``."""
    group, _, name = key.partition(":")
    return f"{name} {group}" if group != "grf" else name


def missing_scored(reference: Reference) -> tuple[str, ...]:
    """The :data:`SCORED` quantities (keys such as ``angle:knee_flexion``) ``reference``
    lacks."""
    return tuple(key for key in SCORED if not reference.has(key))


def check_scored(reference: Reference) -> None:
    """Raise ValueError (one line) when ``reference`` holds none of the :data:`SCORED`
    quantities: there is nothing to score it by."""
    if len(missing_scored(reference)) == len(SCORED):
        names = ", ".join(scored_name(key) for key in SCORED)
        raise ValueError(f"the reference {reference.name} holds none of the scored quantities "
                         f"({names}): nothing to compare the prediction with")  # fmt: skip


def knee_loading_peak(series: np.ndarray) -> float:
    """deg: the largest knee flexion over 0–40 % of a 101-sample cycle from heel strike."""
    return float(np.nanmax(np.asarray(series, float)[: LOADING_END + 1]))


def _capped(value: float) -> float:
    return float(min(CAP, max(0.0, value)))


def _guard(value: float, low: float, high: float, scale: float) -> float:
    return _capped(max(low - value, value - high, 0.0) / scale)


def score(comparison: Comparison, summary: dict, measured_td: float | None = None) -> Score:
    """The score of one prediction (its ``comparison`` with a reference and its ``summary``).
    ``measured_td`` (s): the measured double support, scored when the summary says Td was
    predicted."""
    missing = missing_scored(comparison.reference)
    if not is_converged(summary):  # only a recorded true: "no" is not converged
        return Score(FAILED, failed=f"did not converge ({summary.get('status')})", missing=missing)
    checks = summary.get("gait_checks") or {}
    if not checks.get("looks_like_walking"):
        return Score(FAILED, failed="does not look like walking", missing=missing)
    parts: dict[str, float] = {}
    figures: dict[str, float] = {}
    rows = {r.quantity.key: r for r in comparison.rows}
    for key, bar in RMSE_BARS.items():
        row = rows.get(key)
        if row is not None and np.isfinite(row.rmse):
            figures[key] = row.rmse
            parts[key] = _capped(row.rmse / bar)
    for key, bar in MOMENT_R_BARS.items():
        row = rows.get(key)
        if row is not None and np.isfinite(row.r):
            figures[f"{key}:r"] = row.r
            parts[f"{key}:r"] = _capped((1.0 - row.r) / (1.0 - bar))
    knee = "angle:knee_flexion"
    if knee in comparison.predicted and comparison.reference.has(knee):
        peak = knee_loading_peak(comparison.predicted[knee])
        measured = knee_loading_peak(comparison.reference.mean[knee])
        figures["knee_loading_peak_deg"] = peak
        figures["knee_loading_peak_measured_deg"] = measured
        parts["knee_loading_peak"] = _capped(abs(peak - measured) / KNEE_PEAK_SCALE)
    for key, (low, high, scale) in GUARDS.items():
        value = checks.get(key)
        if isinstance(value, int | float) and np.isfinite(value):
            figures[key] = float(value)
            parts[key] = _guard(float(value), low, high, scale)
    td = (summary.get("descriptors") or {}).get("double_support")
    predicted = "double_support" in ((summary.get("descriptors") or {}).get("predicted") or ())
    if predicted and measured_td and isinstance(td, int | float):
        figures["double_support_s"] = float(td)
        parts["double_support"] = _capped(abs(td - measured_td) / (TD_SCALE * measured_td))
    total = float(np.mean(list(parts.values()))) if parts else FAILED
    return Score(total, parts, figures, missing=missing)


def score_json(result: Score) -> dict:
    """``result`` as strict JSON (``score.json`` of a validation folder; NaN as null);
    ``partial`` and ``missing`` say which scored quantities the reference lacked."""

    def clean(values: dict) -> dict:
        return {k: float(v) if np.isfinite(v) else None for k, v in values.items()}

    return {"score": result.total, "partial": result.partial, "missing": list(result.missing),
            "parts": clean(result.parts), "figures": clean(result.figures),
            "failed": result.failed,
            "bars": {"rmse": RMSE_BARS, "moment_r": MOMENT_R_BARS,
                     "knee_loading_peak_deg": KNEE_PEAK_SCALE, "cap": CAP}}  # fmt: skip
