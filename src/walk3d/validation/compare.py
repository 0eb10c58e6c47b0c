"""Table 2: a prediction against a measured reference, quantity by quantity.

Alignment. Measured cycles run from right heel strike (0 %) to the next (100 %). A walk3d cycle
starts at right toe off (:mod:`walk3d.contact.phases`): right heel strike is at
``t_hs = T/2 - Td``. The prediction, periodic by construction, is therefore read at
``t = (t_hs + p T / 100) mod T`` for ``p = 0, 1, ..., 100`` (101 samples, the two ends being the
same instant), with linear interpolation between its time nodes. ``T`` and ``Td`` come from the
settings the prediction's summary records (:func:`walk3d.problem.settings.recorded_settings`),
refused unless T is the span of ``pred.time`` (:func:`walk3d.results.period.summary_period`);
without them, ``T`` is the span of ``pred.time`` and the heel
strike is where the right foot's vertical force first rises above 20 N.

Scores, per quantity, over the 101 samples: RMSE between prediction and reference mean, and
Pearson's correlation coefficient ``r`` (NaN when either series is constant). A quantity missing
on either side is kept as a row with status ``missing in reference`` / ``missing in
prediction`` and NaN scores, never dropped; one whose r or R² cannot be computed has status
``constant reference`` or ``constant prediction`` (never ``ok``).
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass

import numpy as np

from walk3d.problem.settings import recorded_settings
from walk3d.results.period import summary_period
from walk3d.results.prediction import PredictedCycle
from walk3d.trials.events import detect_contacts
from walk3d.validation.quantities import QUANTITIES, Quantity, prediction_series
from walk3d.validation.reference import N_PERCENT, Reference

__all__ = ["Comparison", "Row", "align_prediction", "compare", "cycle_timing", "r_squared", "rmse"]


@dataclass(frozen=True)
class Row:
    """One line of Table 2."""

    quantity: Quantity
    rmse: float
    r: float
    status: str
    """``ok``, ``missing in reference``, ``missing in prediction``, or ``constant reference`` /
    ``constant prediction`` when r or R² cannot be computed."""
    reference_sd: float
    """Mean SD of the reference over the cycle (NaN when unknown): the scale of the measured
    variability against which the RMSE can be read."""
    n_cycles: int | None
    reference_range: float = float("nan")
    """Peak-to-peak of the reference mean over the cycle (NaN when missing)."""
    r2: float = float("nan")
    """Coefficient of determination ``1 − Σ(p − m)² / Σ(m − m̄)²`` (the prediction as a model of
    the reference mean; negative when it explains less than the reference's own mean)."""

    @property
    def rmse_of_range(self) -> float:
        """RMSE as a fraction of the reference's range."""
        ok = np.isfinite(self.reference_range) and self.reference_range > 0
        return self.rmse / self.reference_range if ok else float("nan")


@dataclass(frozen=True)
class Comparison:
    """Table 2 plus the aligned series behind it (for figures)."""

    prediction_name: str
    reference: Reference
    percent: np.ndarray
    predicted: dict[str, np.ndarray]
    rows: tuple[Row, ...]

    def row(self, key: str) -> Row:
        for r in self.rows:
            if r.quantity.key == key:
                return r
        raise KeyError(f"no row {key!r}")


def rmse(a: np.ndarray, b: np.ndarray) -> float:
    """Root mean square of ``a - b`` over samples where both are finite (NaN if none)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    ok = np.isfinite(a) & np.isfinite(b)
    return float(np.sqrt(np.mean((a[ok] - b[ok]) ** 2))) if ok.any() else float("nan")


def _pearson(a: np.ndarray, b: np.ndarray) -> float:
    ok = np.isfinite(a) & np.isfinite(b)
    a, b = a[ok], b[ok]
    if a.size < 3 or np.ptp(a) == 0 or np.ptp(b) == 0:
        return float("nan")
    return float(np.corrcoef(a, b)[0, 1])


def r_squared(p: np.ndarray, m: np.ndarray) -> float:
    """``1 − Σ(p − m)² / Σ(m − m̄)²`` over samples where both are finite (NaN if ``m`` does not
    vary beyond rounding: a constant reference explains nothing)."""
    p, m = np.asarray(p, float), np.asarray(m, float)
    ok = np.isfinite(p) & np.isfinite(m)
    ss = float(np.sum((m[ok] - m[ok].mean()) ** 2)) if ok.sum() > 2 else 0.0
    varies = ss > 1e-20 * float(np.sum(m[ok] ** 2))
    return 1.0 - float(np.sum((p[ok] - m[ok]) ** 2)) / ss if ss > 0 and varies else float("nan")


def cycle_timing(pred: PredictedCycle) -> tuple[float, float]:
    """``(T, t_hs)``: the period and the right heel-strike time of a prediction (module doc).
    Raises ValueError (one line) for a recorded T that is not its time span, or a bad Td."""
    inputs = recorded_settings(pred.summary) if isinstance(pred.summary, dict) else {}
    period, td = inputs.get("period"), inputs.get("double_support")
    t = pred.time
    group = "settings.gait." if isinstance(pred.summary.get("settings"), dict) else "inputs."
    if period is not None:
        period = summary_period(t, period, f"{group}period")
    if period is not None and td is not None:
        real = isinstance(td, numbers.Real) and not isinstance(td, bool)
        if not (real and 0.0 <= float(td) < period):
            raise ValueError(f"the summary's {group}double_support {td!r:.40} is not a "
                             f"duration within the period {period:.6g} s")  # fmt: skip
        return period, period / 2 - float(td)
    period = float(t[-1] - t[0]) if period is None else period
    if period <= 0:
        raise ValueError("the prediction has no period: summary lacks inputs and time is empty")
    strikes = detect_contacts(t, pred.grf_force[:, 0, 1], 20.0, min_contact=0.0).heel_strikes
    if strikes.size == 0:
        raise ValueError("cannot find the right heel strike in the prediction")
    return period, float(strikes[0] - t[0])


def on_percent(pred: PredictedCycle, values: np.ndarray) -> np.ndarray:
    """``values`` (time first, any trailing shape) of ``pred`` at 0–100 % from right heel
    strike (module doc), :data:`N_PERCENT` samples."""
    period, t_hs = cycle_timing(pred)
    t = pred.time - pred.time[0]
    keep = t < period - 1e-9 * period  # t = T repeats t = 0
    percent = np.linspace(0.0, 100.0, N_PERCENT)
    query = np.mod(t_hs + percent / 100.0 * period, period)
    values = np.asarray(values, dtype=float)
    flat = values.reshape(values.shape[0], -1)
    out = np.column_stack([np.interp(query, t[keep], v[keep], period=period) for v in flat.T])
    return out.reshape((N_PERCENT, *values.shape[1:]))


def align_prediction(pred: PredictedCycle) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Prediction quantities on 0–100 % from right heel strike (module doc), 101 samples."""
    series = prediction_series(pred)
    keys = list(series)
    stacked = on_percent(pred, np.column_stack([series[k] for k in keys]))
    return np.linspace(0.0, 100.0, N_PERCENT), {k: stacked[:, i] for i, k in enumerate(keys)}


def compare(pred: PredictedCycle, reference: Reference, name: str = "prediction") -> Comparison:
    """Table 2 of ``pred`` against ``reference`` (module doc)."""
    percent, predicted = align_prediction(pred)
    rows = []
    for q in QUANTITIES:
        have_p, have_r = q.key in predicted, reference.has(q.key)
        if not have_r or not have_p:
            status = "missing in reference" if not have_r else "missing in prediction"
            rows.append(Row(q, np.nan, np.nan, status, np.nan, None))
            continue
        p, m = predicted[q.key], reference.mean[q.key]
        sd = reference.sd.get(q.key)
        sd_mean = float(np.nanmean(sd)) if sd is not None and np.isfinite(sd).any() else np.nan
        span = float(np.nanmax(m) - np.nanmin(m)) if np.isfinite(m).any() else np.nan
        r, r2 = _pearson(p, m), r_squared(p, m)
        status = (
            "ok"
            if np.isfinite(r) and np.isfinite(r2)
            else ("constant prediction" if np.isfinite(r2) else "constant reference")
        )
        rows.append(Row(q, rmse(p, m), r, status, sd_mean,
                        reference.n_cycles.get(q.key), span, r2))  # fmt: skip
    return Comparison(name, reference, percent, predicted, tuple(rows))
