"""Is a converged optimum crouched? The hip's flexion in mid-stance, read from the NLP's nodes.

Most random standing starts end in crouched local optima (C_tor 4–7 against 1.9–3.7 for
walking, docs/solver.md): the knee still flexes in swing, but the hip stays flexed through
stance. A long stride flexes the hip as much at heel strike, and extends it by mid-stance, so
the check reads mid-stance (:attr:`walk3d.contact.phases.GaitPhases.mid_stance`): the mean
right-hip flexion over the nodes in the middle third of the right stance, which every node
grid covers (the nodes span the half cycle from the right heel strike).
:mod:`walk3d.results.gait_checks` applies the same threshold to the evaluated cycle.
"""

from __future__ import annotations

import numpy as np

from walk3d.contact.phases import GaitPhases
from walk3d.problem import layout

HIP_MIDSTANCE_MAX_DEG = 27.0
"""Mean hip flexion over the middle third of stance above which a gait counts as crouched,
deg: between walk3d's walking optima (at most 25°, the man at 1.9 m/s) and its crouched ones
(32° and more); measured adults: 5° (Falisse 2019). Evidence: docs/solver.md, the crouch
check that reads mid-stance."""
HIP_FLEXION_COORD = 14
"""Coordinate index of the right hip's flexion (about its z axis; :data:`layout.COORD_SOURCE`)."""
CROUCHED = "Crouched_Optimum"
"""The status a rejected full stage is given (not a success, so the plan retries)."""


def midstance_hip_flexion_deg(z: np.ndarray, lay: layout.NlpLayout, tau: np.ndarray,
                              phases: GaitPhases) -> float:  # fmt: skip
    """Mean right-hip flexion over the nodes in mid-stance, deg (``2 asin q`` of the flexion
    coordinate, the flexion angle to first order); ``tau`` holds the nodes' times since the
    right heel strike, s, and ``phases`` the period and double support they belong to."""
    y = np.asarray(z)[lay.z("y")].reshape(lay.nodes, layout.N_Y)
    hip = np.degrees(2 * np.arcsin(np.clip(y[:, HIP_FLEXION_COORD], -1.0, 1.0)))
    lo, hi = phases.mid_stance
    inside = (np.asarray(tau) >= lo) & (np.asarray(tau) <= hi)
    return float(hip[inside].mean())
