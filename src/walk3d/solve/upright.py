"""Is a converged optimum crouched? The hip's flexion in mid-stance, read from the NLP's nodes.

The check itself, its mid-stance window and threshold, is :mod:`walk3d.contact.crouch`, which
the gait checks of the evaluated cycle (:mod:`walk3d.results.gait_checks`) apply too. Here it
reads the mean right-hip flexion over the nodes in the middle third of the right stance, which
every node grid covers (the nodes span the half cycle from the right heel strike).
"""

from __future__ import annotations

import numpy as np

from walk3d.contact.crouch import midstance_mean
from walk3d.contact.phases import GaitPhases
from walk3d.problem import layout

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
    return midstance_mean(hip, tau, phases)
