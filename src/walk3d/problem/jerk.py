"""The ``jerk`` criterion term on the Fourier coefficients: exact and diagonal (Parseval), so
the NLP adds it to its objective on the decision vector rather than at the nodes.

``∫ (1/24) Σ_i (2 q⃛_i / JERK_REF)² dt`` over the cycle, ``JERK_REF`` the term's scale
(:data:`walk3d.model.builtin_terms.JERK_REF`).
"""

from __future__ import annotations

import numpy as np

from walk3d.kinematics import fourier
from walk3d.model import terms
from walk3d.problem import layout


def jerk_per_coefficient(period: float) -> np.ndarray:
    """(N_COEF,) ``w_j`` with ``∫ (1/24) (2 q⃛ / JERK_REF)² dt = Σ_j w_j c_j²`` for one series
    over the cycle (Parseval: ``(T/2) (kω)⁶`` per cosine and sine coefficient, 0 for ``a0``)."""
    w = 2 * np.pi / period
    k = np.array([0] + [j for j in range(1, fourier.ORDER + 1) for _ in range(2)], dtype=float)
    return 0.5 * period * (k * w) ** 6 * 4.0 / (24.0 * terms.get("jerk").scale ** 2)


def jerk_per_dof(x: np.ndarray, period: float) -> np.ndarray:
    """``∫ (1/24) (2 q⃛_i / JERK_REF)² dt`` over the cycle for each of the 24 DoFs, exactly (a
    half-cycle shift keeps every amplitude, so a DoF has its series' value)."""
    c = layout.coefficients(np.asarray(x, dtype=float))
    per_series = (c * c) @ jerk_per_coefficient(period)
    return per_series[[s for s, _ in layout.COORD_SOURCE[:24]]]


def jerk_per_dof_full(xf: np.ndarray, period: float) -> np.ndarray:
    """:func:`jerk_per_dof` for the full-cycle problem's ``X`` (``layout.N_XF``): each DoF from
    its own side's series."""
    per = jerk_per_coefficient(period)
    xf = np.asarray(xf, dtype=float)
    sides = [((c * c) @ per) for c in (layout.coefficients(xf[: layout.N_X]),
                                       layout.coefficients(xf[layout.N_X :]))]  # fmt: skip
    return np.array([sides[int(shifted)][s] for s, shifted in layout.COORD_SOURCE[:24]])


def coefficient_weights(period: float) -> np.ndarray:
    """``q`` (N_X,) with ``C_jerk = Σ_i q_i x_i²`` (:func:`jerk_per_dof` summed)."""
    count = np.bincount([s for s, _ in layout.COORD_SOURCE[:24]], minlength=layout.N_SERIES)
    return np.concatenate([np.outer(count, jerk_per_coefficient(period)).ravel(), [0.0]])
