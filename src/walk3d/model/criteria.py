"""The criteria of paper Eqs. 10–11, exact and smoothed, with their x/y/z split (Table 3).

* ``C_tor = ∫ Σ |M_k| / M_max,k(direction) dt`` over every DoF axis (α = 1 axes only: moments
  about locked axes are carried by ligaments and bone and are not penalized). With
  ``a = (1/M⁺ + 1/M⁻)/2`` and ``b = (1/M⁺ - 1/M⁻)/2`` this is ``a|M| + bM`` exactly, so only
  ``|M|`` needs smoothing.
* ``C_en = ∫ Σ |M_k ω_rel,k| dt``: the absolute joint power about each DoF axis.

The solver sees ``|x| ≈ sqrt(x² + ε²)``, with ``ε = smoothing × M_max`` for moments and
``ε = smoothing × 50 W`` for powers; results always report the exact criteria.
Axis labels: 0 = x (frontal plane), 1 = y (transverse), 2 = z (sagittal).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from walk3d import mathops as mo
from walk3d.body.model import BodyModel

POWER_SCALE_W = 50.0


def node_terms(
    moments: list[Any], rates: list[Any], a: np.ndarray, b: np.ndarray, smoothing: float | None
) -> tuple[list[Any], list[Any]]:
    """Per-DoF integrands of C_tor and C_en at the nodes (exact if ``smoothing`` is None)."""
    m_ref = 1.0 / a  # harmonic-mean strength of each DoF
    tor, en = [], []
    for i, (m, w) in enumerate(zip(moments, rates, strict=True)):
        p = m * w
        if smoothing is None:
            tor.append(a[i] * mo.fabs(m) + b[i] * m)
            en.append(mo.fabs(p))
        else:
            eps_m = smoothing * m_ref[i]
            eps_p = smoothing * POWER_SCALE_W
            tor.append(a[i] * mo.sqrt(m * m + eps_m**2) + b[i] * m)
            en.append(mo.sqrt(p * p + eps_p**2))
    return tor, en


def signed_integrands(
    body: BodyModel, base: str, moments: list[Any], rates: list[Any]
) -> tuple[list[Any], list[Any]]:
    """Per DoF, ``(u⁺, u⁻)`` with ``max(u⁺, u⁻)`` the exact integrand of the ``base`` criterion
    (``tor`` or ``en``), for slack variables. C_tor: ``u⁺ = M/M⁺``, ``u⁻ = -M/M⁻``
    (direction-dependent strength); C_en: ``±P/P_ref``, ``P_ref`` = :data:`POWER_SCALE_W`."""
    if base == "tor":
        pos = np.concatenate([j.strength_pos for j in body.joints])
        neg = np.concatenate([j.strength_neg for j in body.joints])
        return [m / pos[i] for i, m in enumerate(moments)], [
            -m / neg[i] for i, m in enumerate(moments)
        ]
    powers = [m * w / POWER_SCALE_W for m, w in zip(moments, rates, strict=True)]
    return powers, [-p for p in powers]


def split_by_axis(values: np.ndarray, axes: list[int]) -> dict[str, float]:
    """Sum per-DoF integrals ``values`` (n_dof,) by axis label: {'x', 'y', 'z', 'total'}."""
    out = {k: 0.0 for k in ("x", "y", "z")}
    for v, ax in zip(values, axes, strict=True):
        out["xyz"[ax]] += float(v)
    out["total"] = out["x"] + out["y"] + out["z"]
    return out
