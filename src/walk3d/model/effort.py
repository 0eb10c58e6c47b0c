"""The muscle-like ``effort`` terms: joint moments over angle-dependent strengths (#41).

``effort = (1/24) Σ_i (u_i / EFFORT_REF)²`` and ``effort3`` the same cubed (smoothly), where
``u_i = |M_i| / M_max,i(θ_i, direction of M_i)``. ``M_max`` is the DoF's table strength
(``strength_pos_Nm``, ``strength_neg_Nm``) times, for hip, knee and ankle flexion/extension, the
cosine of Anderson, Madigan & Nussbaum (2007) J Biomech 40:3105, Table 3 (young adults, by
sex), floored smoothly at :data:`STRENGTH_FLOOR` (docs/stance-model.md §3); other DoFs keep
their constant strengths. ``θ_i = 2 asin(q_i)``, exact for hinge and universal DoFs and the
rotation vector's component for ball joints (equal to first order to results/angles' angles).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from walk3d import mathops as mo
from walk3d.body.model import BodyModel

ANDERSON_2007: dict[str, dict[str, tuple[float, float, float, float]]] = {
    "male": {"hip_flexion": (0.738, -0.214, 0.958, 0.932),
             "knee_flexion": (0.869, 0.522, 1.258, 1.133),
             "ankle_dorsiflexion": (1.510, -0.187, 1.391, 0.408)},
    "female": {"hip_flexion": (0.650, -0.350, 0.697, 1.242),
               "knee_flexion": (0.873, 0.635, 1.187, 1.274),
               "ankle_dorsiflexion": (1.079, -0.302, 1.399, 0.424)},
}  # fmt: skip
"""``(c2⁺, c3⁺, c2⁻, c3⁻)`` per DoF: Anderson et al. 2007 Table 3 means, young adults (RBDL
``Millard2016TorqueMuscle.cc`` ``Anderson2007Table3Mean``), ``c3`` in rad, for the positive
moment (hip flexors, knee flexors, dorsiflexors) and the negative one (extensors, plantarflexors).
Within walk3d's joint ranges ``|c2(θ − c3)| < π``, so the cosine has one peak there."""
STRENGTH_FLOOR = 0.3
"""The smallest angle factor: without a floor the knee extensors' strength reaches zero near
full extension (docs/stance-model.md §3 recommends 0.3–1, measured by #41)."""
FLOOR_WIDTH = 0.05
"""Width of the smooth floor ``((c + f) + sqrt((c − f)² + w²)) / 2``: within ``w²/(4|c − f|)``
of ``max(c, f)`` (0.0025 at 0.25 from the floor, 0.0009 at the peak ``c = 1``)."""
EFFORT_REF = 0.21
"""RMS of ``u`` over the 24 DoFs and the cycle of the shipped ``natural`` atlas's female entry at
1.3 m/s (62 kg, 1.70 m, the default prediction's start): 0.212, so that a human-like gait
scores about 1 per second (docs/criteria.md)."""
EFFORT3_REF = 0.32
"""The cube root of the mean ``u³`` on the same gait (0.317), for ``effort3``."""
CUBE_EPS = 1e-6
"""The smooth cube ``(v² + ε)^{3/2} − ε^{3/2}`` of ``effort3`` (``v = u / EFFORT3_REF``)."""


def angle_factor(theta: Any, c2: float, c3: float) -> Any:
    """``cos(c2 (θ − c3))`` floored smoothly at :data:`STRENGTH_FLOOR` (1 at the peak angle)."""
    c = mo.cos(c2 * (theta - c3))
    f = STRENGTH_FLOOR
    return 0.5 * ((c + f) + mo.sqrt((c - f) ** 2 + FLOOR_WIDTH**2))


def strengths(body: BodyModel, i: int, theta: Any) -> tuple[Any, Any]:
    """``(M_max⁺, M_max⁻)`` of DoF ``i`` at its angle ``θ`` (rad), N·m."""
    pos = np.concatenate([j.strength_pos for j in body.joints])[i]
    neg = np.concatenate([j.strength_neg for j in body.joints])[i]
    name = body.dof_names[i].removesuffix("_r").removesuffix("_l")
    coef = ANDERSON_2007["female" if body.sex == "female" else "male"].get(name)
    if coef is None:
        return pos, neg
    return pos * angle_factor(theta, *coef[:2]), neg * angle_factor(theta, *coef[2:])


def ratio(body: BodyModel, i: int, moment: Any, value: Any) -> Any:
    """``u_i = |M_i| / M_max,i(θ_i, direction)`` of DoF ``i`` from its moment (N·m) and its
    coordinate value ``q_i`` (``θ = 2 asin q``); written ``a|M| + bM`` as C_tor is."""
    sp, sn = strengths(body, i, 2.0 * mo.asin(value))
    a, b = 0.5 * (1.0 / sp + 1.0 / sn), 0.5 * (1.0 / sp - 1.0 / sn)
    return a * mo.fabs(moment) + b * moment


def ratios(body: BodyModel, moments: list[Any], values: list[Any]) -> list[Any]:
    """:func:`ratio` of every DoF, from the DoF moments (N·m) and the coordinate values."""
    return [ratio(body, i, m, values[i]) for i, m in enumerate(moments)]
