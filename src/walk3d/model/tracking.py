"""Tracking a measured gait: the target and the ``track`` criterion term's integrand.

The target is each DoF's coordinate ``τ_i = 2 q*_i`` (``q = sin(θ/2)`` for hinges and the ankle
axes, the quaternion's vector part along each axis for ball joints; ``2 q`` is the angle to
first order) as a Fourier series over the phase of the gait cycle from right heel strike.
The integrand, per s, is the weighted mean square deviation on the measured DoFs:

``track = Σ_i w_i ((2 q_i − τ_i) / scale)² / Σ_i w_i``, split by DoF axis (x, y, z),

so a gait within ``scale`` RMS of the data scores about 1 per second. The NLP adds it exactly on
its lifted coordinates (:mod:`walk3d.problem.tracking`); the evaluated cycle integrates it on
its samples, with the same function.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from pydantic import BaseModel, ConfigDict, field_validator, model_validator

__all__ = ["ORDER", "TRACK_REF", "Tracking", "fit_series", "integrand"]

ORDER = 10
"""Harmonics of each target series: the measured cycles' content above 10 per cycle is below
their noise (a 5th-order model series cannot follow it anyway)."""
TRACK_REF = math.radians(2.0)
"""rad: the scale of the deviation, about the between-trial SD of a healthy adult's sagittal
joint angles (Falisse 2019 mean ± SD: 2–5°)."""


def _basis(phase: np.ndarray, order: int) -> np.ndarray:
    """(n, 2·order + 1) ``[1, cos 2πφ, sin 2πφ, …]`` at the phases ``φ`` (cycles)."""
    w = 2 * np.pi * np.asarray(phase, dtype=float)[:, None] * np.arange(1, order + 1)
    out = np.empty((w.shape[0], 2 * order + 1))
    out[:, 0] = 1.0
    out[:, 1::2], out[:, 2::2] = np.cos(w), np.sin(w)
    return out


def fit_series(phase: np.ndarray, values: np.ndarray, order: int = ORDER) -> np.ndarray:
    """Least-squares Fourier coefficients (columns, 2·order + 1) of ``values`` (n, m) sampled at
    the phases ``phase`` (n,), periodic with period 1."""
    coef, *_ = np.linalg.lstsq(_basis(phase, order), np.asarray(values, dtype=float), rcond=None)
    return coef.T


class Tracking(BaseModel):
    """A measured gait to track (``ModelSettings.tracking``): target series, per-DoF weights and
    the deviation scale."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    coefficients: tuple[tuple[float, ...], ...]
    """Per DoF (24, walk3d's order), the Fourier coefficients ``[a0, a1, b1, …]`` of ``τ_i``
    over the phase from right heel strike."""
    weights: tuple[float, ...]
    """Per DoF, its weight in the mean (0: not measured)."""
    scale: float = TRACK_REF
    """rad: a deviation of this size RMS costs 1 per second."""
    source: str = ""
    """What was measured (one line)."""

    @field_validator("coefficients", "weights")
    @classmethod
    def _finite(cls, v: Any) -> Any:
        if not np.all(np.isfinite(np.asarray(v, dtype=float))):
            raise ValueError("tracking target values must be finite")
        return v

    @model_validator(mode="after")
    def _shape(self) -> Tracking:
        c = np.asarray(self.coefficients, dtype=float)
        if c.ndim != 2 or c.shape[0] != 24 or c.shape[1] % 2 != 1:
            raise ValueError(f"tracking coefficients must be 24 series of 2k+1, got {c.shape}")
        w = np.asarray(self.weights, dtype=float)
        if w.shape != (24,) or np.any(w < 0) or not np.any(w > 0):
            raise ValueError("tracking weights must be 24 numbers >= 0, one of them > 0")
        if not 0 < self.scale < 1:
            raise ValueError(f"tracking scale must be in (0, 1) rad, got {self.scale}")
        return self

    def target(self, phase: np.ndarray) -> np.ndarray:
        """``τ`` (n, 24) at the phases ``phase`` (cycles from right heel strike)."""
        c = np.asarray(self.coefficients, dtype=float)
        return _basis(phase, (c.shape[1] - 1) // 2) @ c.T

    def factors(self) -> np.ndarray:
        """(24,) ``w_i / (Σ w · scale²)``: the integrand is ``Σ_i f_i (2 q_i − τ_i)²``."""
        w = np.asarray(self.weights, dtype=float)
        return w / (w.sum() * self.scale**2)


def integrand(tracking: Tracking, values: list[Any], target: np.ndarray, axes: list[int]):
    """The ``track`` integrand per s, split ``(x, y, z)`` by DoF axis, from the 24 coordinate
    values ``q_i`` (arrays over samples) and the target ``τ`` (n, 24) at those samples."""
    f = tracking.factors()
    parts = [0.0 * values[0]] * 3
    for i in np.flatnonzero(f):
        parts[axes[i]] = parts[axes[i]] + f[i] * (2.0 * values[i] - target[:, i]) ** 2
    return tuple(parts)
