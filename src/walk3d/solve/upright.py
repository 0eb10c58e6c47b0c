"""Is a converged optimum crouched? The hip's flexion in stance, read from the NLP's nodes.

Most random standing starts end in crouched local optima (C_tor 4–7 against 1.9–3.7 for
walking, docs/solver.md): the knee still flexes in swing, but the hip flexes 52–67° in stance,
where walking stays within about 40°. :func:`stance_hip_flexion_deg` reads the right hip's
flexion coordinate at the nodes (the right foot's stance: every node of the half cycle), so
the check needs no evaluation of the cycle. The threshold is that of
:data:`walk3d.results.gait_checks.HIP_STANCE_MAX_DEG`.
"""

from __future__ import annotations

import numpy as np

from walk3d.problem import layout

HIP_FLEXION_COORD = 14
"""Coordinate index of the right hip's flexion (about its z axis; :data:`layout.COORD_SOURCE`)."""
CROUCH_HIP_DEG = 45.0
"""Stance hip flexion above which an optimum counts as crouched, deg."""
CROUCHED = "Crouched_Optimum"
"""The status a rejected full stage is given (not a success, so the plan retries)."""


def stance_hip_flexion_deg(z: np.ndarray, lay: layout.NlpLayout) -> float:
    """Largest right-hip flexion at the nodes of the decision vector ``z``, deg (``2 asin q``
    of the flexion coordinate, which is the flexion angle to first order)."""
    y = np.asarray(z)[lay.z("y")].reshape(lay.nodes, layout.N_Y)
    q = np.clip(y[:, HIP_FLEXION_COORD], -1.0, 1.0)
    return float(np.degrees(2 * np.arcsin(q)).max())


def crouched(z: np.ndarray, lay: layout.NlpLayout) -> bool:
    """Whether ``z`` flexes the stance hip more than :data:`CROUCH_HIP_DEG`."""
    return stance_hip_flexion_deg(z, lay) > CROUCH_HIP_DEG
