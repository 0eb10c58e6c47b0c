"""The double-support split left to the optimizer (``ModelSettings.split_terms``).

The paper prescribes the trailing foot's wrench in double support as ``e(τ) · W0``
(:mod:`walk3d.contact.transition`). With ``K`` free terms it is

    ``e(τ) · W0 + h (1 − h) · Σ_j h^j · C_j``,  j = 0 … K − 1,

with ``h`` the handover share (:func:`walk3d.contact.phases.handover_share`: 1 at heel strike,
0 at toe off and in single stance) and the ``C_j`` 6-vectors (force and moment about the
trailing ankle, body weights and body weights × m) that the NLP chooses. The added part is 0
at both ends of double support, so each foot's load stays continuous, and the leading foot
still carries the rest of the total: the feet always sum to the reaction of Eq. 5. Both feet
keep their unilateral, friction and centre-of-pressure rows. Evidence: docs/criteria.md.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

__all__ = ["MAX_TERMS", "MIRROR", "coefficient_count", "subject_split", "trailing_load"]

MAX_TERMS = 4
"""Largest ``K``: the split's shape over a double support of 10–30 % of the cycle needs few
terms (K = 2 and 3 gave the same gait, docs/criteria.md)."""
MIRROR = (1.0, 1.0, -1.0, -1.0, -1.0, 1.0)
"""Signs that carry a right-root half cycle's wrench to the left-root one: the lateral force
and the frontal and transverse moments flip (the mirror of the gait)."""


def coefficient_count(terms: int) -> int:
    """The NLP unknowns of ``terms`` free terms: one 6-vector (a wrench) each."""
    return 6 * terms


def trailing_load(w0: Sequence[Any], decay: Any, h: Any, coefficients: Sequence[Any]) -> list:
    """The trailing foot's wrench (6 entries, ``W0``'s units) from ``W0``, the paper's share
    ``decay``, the handover share ``h`` and the free terms' ``coefficients`` (``6 K`` entries,
    ``C_0`` first); any CasADi or NumPy type. No coefficients: ``decay · W0``."""
    out = [decay * w0[i] for i in range(6)]
    basis = h * (1 - h)
    for j in range(len(coefficients) // 6):
        for i in range(6):
            out[i] = out[i] + basis * coefficients[6 * j + i]
        basis = basis * h
    return out


def subject_split(c_ref: np.ndarray, s: float) -> np.ndarray:
    """The subject's coefficients ``(K, 6)`` from the reference subject's: forces per body
    weight are the same, moments per body weight ``s`` times larger (lengths × s,
    :mod:`walk3d.problem.similarity`)."""
    c = np.array(c_ref, dtype=float).reshape(-1, 6)
    c[:, 3:] *= s
    return c
