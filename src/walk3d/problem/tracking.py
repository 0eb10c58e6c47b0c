"""The ``track`` criterion term in the NLP: exact, on the lifted coordinates at the nodes.

At node ``k`` the lifted values ``Y_k`` hold the 26 coordinates, so the term's integrand
(:func:`walk3d.model.tracking.integrand`) is a diagonal quadratic in ``z``; integrated with the
objective's own quadrature weights ``W_k`` it is ``Σ q_j z_j² + c_j z_j + const``
(:func:`track_quadratic`), whose gradient and Hessian the structured derivatives add directly.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from walk3d.contact.phases import GaitPhases
from walk3d.model import terms
from walk3d.problem import layout
from walk3d.problem.settings import PredictionSettings


@dataclass(frozen=True)
class Quadratic:
    """``Σ_j q_j z_j² + c_j z_j + const`` over the entries ``index`` of ``z``."""

    index: np.ndarray
    q: np.ndarray
    c: np.ndarray
    const: float


def node_phases(settings: PredictionSettings, times: np.ndarray) -> np.ndarray:
    """Phase of the gait cycle (cycles, [0, 1)) from right heel strike at prediction times."""
    g = settings.gait
    t_hs = GaitPhases(g.period, g.double_support, settings.model.load_ramp).heel_strike_r
    return np.mod((np.asarray(times) - t_hs) / g.period, 1.0)


def track_quadratic(
    settings: PredictionSettings, times: np.ndarray, weights: np.ndarray, scale: float
) -> Quadratic | None:
    """The track term of ``settings`` at the nodes ``times`` with quadrature ``weights`` (s,
    the objective's), times ``scale`` (the objective row's units per criterion unit) and its
    weight in the criterion; None without tracking."""
    tr = settings.model.tracking
    w_track = terms.extras(settings.model.criterion).get("track")
    if tr is None or not w_track:
        return None
    target = tr.target(node_phases(settings, times))  # (n, 24)
    f = tr.factors()
    dofs = np.flatnonzero(f)
    n = len(times)
    a = w_track * scale * np.asarray(weights, dtype=float)[:, None] * f[None, dofs]  # (n, m)
    index = layout.N_X + np.arange(n)[:, None] * layout.N_Y + dofs[None, :]
    tau = target[:, dofs]
    return Quadratic(index.ravel(), (4 * a).ravel(), (-4 * a * tau).ravel(),
                     float(np.sum(a * tau * tau)))  # fmt: skip
