"""Fifth-order Fourier series over one gait cycle (paper Eq. 9), with analytic derivatives.

A series is ``λ(t) = a0 + Σ_{k=1..K} (a_k cos(kωt) + b_k sin(kωt))`` with ``ω = 2π/T``.
Its coefficient vector is ordered ``[a0, a1, b1, a2, b2, ..., aK, bK]`` (``2K + 1`` entries,
11 for the paper's K = 5). The series is linear in the coefficients, so value and derivatives
are basis matrices times the coefficients; the basis is numeric for a numeric period, which
keeps the optimization problem's coefficient-to-node map linear.
"""

from __future__ import annotations

import numpy as np

ORDER = 5
N_COEF = 2 * ORDER + 1


def basis(
    t: np.ndarray, period: float, order: int = ORDER
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Basis matrices ``(B, B_dot, B_ddot)``, each ``(len(t), 2*order+1)``.

    ``B @ c`` is the series at times ``t``; ``B_dot @ c`` and ``B_ddot @ c`` its first and
    second time derivatives.
    """
    t = np.asarray(t, dtype=float).reshape(-1)
    w = 2.0 * np.pi / period
    n = 2 * order + 1
    b0 = np.zeros((t.size, n))
    b1 = np.zeros((t.size, n))
    b2 = np.zeros((t.size, n))
    b0[:, 0] = 1.0
    for k in range(1, order + 1):
        kw = k * w
        c, s = np.cos(kw * t), np.sin(kw * t)
        b0[:, 2 * k - 1], b0[:, 2 * k] = c, s
        b1[:, 2 * k - 1], b1[:, 2 * k] = -kw * s, kw * c
        b2[:, 2 * k - 1], b2[:, 2 * k] = -kw * kw * c, -kw * kw * s
    return b0, b1, b2


def half_cycle_shift(order: int = ORDER) -> np.ndarray:
    """Diagonal map ``S`` with ``series(t + T/2) = series_with(S @ c)(t)``.

    Harmonic ``k`` changes sign by ``(-1)^k`` under a half-period shift.
    """
    d = [1.0]
    for k in range(1, order + 1):
        d += [(-1.0) ** k] * 2
    return np.diag(d)


def harmonic_parity_mask(parity: str, order: int = ORDER) -> np.ndarray:
    """Boolean mask of coefficients of ``even`` (incl. a0) or ``odd`` harmonics."""
    if parity not in ("even", "odd"):
        raise ValueError("parity must be 'even' or 'odd'")
    ks = [0] + [k for k in range(1, order + 1) for _ in range(2)]
    return np.array([(k % 2 == 0) == (parity == "even") for k in ks])


def fit(t: np.ndarray, values: np.ndarray, period: float, order: int = ORDER) -> np.ndarray:
    """Least-squares Fourier coefficients of samples ``values`` (time first) at times ``t``."""
    b0, _, _ = basis(t, period, order)
    coef, *_ = np.linalg.lstsq(b0, np.asarray(values, dtype=float), rcond=None)
    return coef
