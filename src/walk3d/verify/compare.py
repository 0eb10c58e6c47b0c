"""Pure comparisons of ``walk3d verify``: OpenSim's inverse dynamics against walk3d's, and the
stance foot's drift when the motion is replayed on ``model.osim``.

The bars are issue 26's: for the hip, knee and ankle flexion moments of both legs, Pearson's
r ≥ 0.99 and an RMSE ≤ 2 % of the moment's peak (walk3d's largest magnitude); the pelvis's
residual forces (``pelvis_tx/ty/tz_force``, which walk3d's motion does not need) ≤ 2 % of body
weight at every sample; the stance foot moving less than 5 mm during foot-flat.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

__all__ = [
    "BARS",
    "FLEXION_COORDINATES",
    "RESIDUAL_FORCES",
    "Bars",
    "Comparison",
    "MomentRow",
    "ResidualRow",
    "compare_generalized_forces",
    "foot_flat_mask",
    "largest_drift",
    "smooth_mask",
]

FLEXION_COORDINATES = (
    "hip_flexion_r", "knee_angle_r", "ankle_angle_r",
    "hip_flexion_l", "knee_angle_l", "ankle_angle_l",
)  # fmt: skip
RESIDUAL_FORCES = ("pelvis_tx_force", "pelvis_ty_force", "pelvis_tz_force")


@dataclass(frozen=True)
class Bars:
    r_min: float = 0.99
    rmse_max_pct_peak: float = 2.0
    residual_max_pct_bw: float = 2.0
    drift_max_m: float = 0.005


BARS = Bars()


@dataclass(frozen=True)
class MomentRow:
    coordinate: str
    r: float
    rmse: float
    """N m."""
    peak: float
    """walk3d's largest magnitude, N m."""

    @property
    def rmse_pct_peak(self) -> float:
        return 100.0 * self.rmse / self.peak if self.peak > 0 else float("inf")

    def passes(self, bars: Bars = BARS) -> bool:
        return bool(self.r >= bars.r_min and self.rmse_pct_peak <= bars.rmse_max_pct_peak)


@dataclass(frozen=True)
class ResidualRow:
    column: str
    peak_pct_bw: float
    """Largest magnitude over the samples compared, % of body weight."""
    rms_pct_bw: float

    def passes(self, bars: Bars = BARS) -> bool:
        return bool(self.peak_pct_bw <= bars.residual_max_pct_bw)


@dataclass(frozen=True)
class Comparison:
    moments: tuple[MomentRow, ...]
    residuals: tuple[ResidualRow, ...]
    n_samples: int

    def passes(self, bars: Bars = BARS) -> bool:
        return all(r.passes(bars) for r in (*self.moments, *self.residuals))


def _pearson(a: np.ndarray, b: np.ndarray) -> float:
    a, b = a - a.mean(), b - b.mean()
    den = np.sqrt(np.sum(a * a) * np.sum(b * b))
    return float(np.sum(a * b) / den) if den > 0 else float("nan")


def compare_generalized_forces(
    walk3d: Mapping[str, np.ndarray],
    opensim: Mapping[str, np.ndarray],
    body_weight: float,
    mask: np.ndarray | None = None,
    coordinates: tuple[str, ...] = FLEXION_COORDINATES,
) -> Comparison:
    """Compare generalized forces sampled at the same times.

    Args:
        walk3d: ``{label: (N,)}`` from ``inverse_dynamics.sto`` (``<coordinate>_moment``...).
        opensim: The same labels from OpenSim's InverseDynamicsTool.
        body_weight: N.
        mask: ``(N,)`` bool, the samples to compare (default: all).
        coordinates: The moments compared (default: hip, knee and ankle flexion, both legs).

    Raises:
        KeyError: a label is missing from either side.
    """
    n = len(next(iter(walk3d.values())))
    keep = np.ones(n, bool) if mask is None else np.asarray(mask, bool)
    rows = []
    for c in coordinates:
        label = f"{c}_moment"
        a, b = np.asarray(walk3d[label])[keep], np.asarray(opensim[label])[keep]
        rmse = float(np.sqrt(np.mean((a - b) ** 2)))
        rows.append(MomentRow(c, _pearson(a, b), rmse, float(np.max(np.abs(a)))))
    residuals = []
    for label in RESIDUAL_FORCES:
        f = (np.asarray(opensim[label]) - np.asarray(walk3d[label]))[keep]
        residuals.append(
            ResidualRow(
                label,
                100.0 * float(np.max(np.abs(f))) / body_weight,
                100.0 * float(np.sqrt(np.mean(f**2))) / body_weight,
            )
        )
    return Comparison(tuple(rows), tuple(residuals), int(np.sum(keep)))


def smooth_mask(vertical_force: np.ndarray, halfwidth: int = 2) -> np.ndarray:
    """Samples more than ``halfwidth`` samples away from every foot's touch-down and from the
    ends of the record.

    walk3d's motion changes its acceleration abruptly at heel strike (the body's momentum rate,
    i.e. the total ground reaction, jumps there) and a record of one cycle has two ends; an
    inverse dynamics that differentiates splines through the sampled coordinates cannot follow
    either. ``vertical_force`` is ``(N, feet)``; a touch-down is a sample whose foot is loaded
    after an unloaded one.
    """
    fy = np.asarray(vertical_force, float)
    n = fy.shape[0]
    keep = np.ones(n, bool)
    keep[:halfwidth] = keep[n - halfwidth :] = False
    loaded = fy > 0
    for k in np.flatnonzero(np.any(loaded[1:] & ~loaded[:-1], axis=1)) + 1:
        keep[max(0, k - 1 - halfwidth) : k + halfwidth + 1] = False
    return keep


def foot_flat_mask(pitch: np.ndarray, loaded: np.ndarray, tolerance: float) -> np.ndarray:
    """Samples where a loaded foot is within ``tolerance`` (rad) of flat."""
    return np.asarray(loaded, bool) & (np.abs(np.asarray(pitch, float)) <= tolerance)


def largest_drift(points: np.ndarray, mask: np.ndarray) -> float:
    """The largest distance between two positions of a point within one run of ``mask``, m.

    ``points`` ``(N, 3)``; each maximal run of consecutive ``True`` samples is one foot-flat
    period (NaN when there is none: nothing was checked, which fails the bar).
    """
    mask = np.asarray(mask, bool)
    if not mask.any():
        return float("nan")
    worst = 0.0
    edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.astype(int), [0]])))
    for start, stop in zip(edges[::2], edges[1::2], strict=True):
        p = np.asarray(points, float)[start:stop]
        d = np.linalg.norm(p[:, None, :] - p[None, :, :], axis=-1)
        worst = max(worst, float(d.max()))
    return worst
