"""Passive joint moments: exponential range stops plus damping (``ModelSettings.passive``, #41).

``M_passive = k1 exp(k2 (θ − θ2)) + k3 exp(k4 (θ − θ1)) − d θ̇`` per DoF (Anderson & Pandy 1999
form; parameters of PredSim ``default_coord_lim_torq_coeff.csv`` = 3dpredictsim
``PassiveMomentsData.m``, docs/stance-model.md §2.2), in walk3d's anatomical signs on both sides.
``θ = 2 asin(q)`` (exact for hinge and universal DoFs, the rotation vector's component for ball
joints); ``θ̇`` is the DoF's angular rate (:func:`walk3d.model.state.dof_moment_terms`). With the
setting on, C_tor and the effort see ``M_active = M − M_passive``; reported moments stay the net.
"""

from __future__ import annotations

import dataclasses
from typing import Any

from walk3d import mathops as mo
from walk3d.body.model import BodyModel
from walk3d.model.element import Element
from walk3d.model.state import GaitState

LIMIT_TORQUES: dict[str, tuple[float, float, float, float, float, float]] = {
    "hip_flexion": (-2.44, 5.05, 1.51, -21.88, -0.6981, 1.81),
    "hip_adduction": (-0.03, 14.94, 0.03, -14.94, -0.5, 0.5),
    "hip_rotation": (-0.03, 14.94, 0.03, -14.94, -0.92, 0.92),
    "knee_flexion": (-11.03, 11.33, 6.09, -33.94, -0.13, 2.4),
    "ankle_dorsiflexion": (-2.03, 38.11, 0.18, -12.12, -0.74, 0.52),
    "subtalar_inversion": (-60.21, 16.32, 60.21, -16.32, -0.65, 0.65),
    "lumbar_extension": (-0.35, 30.72, 0.25, -20.36, -0.5236, 0.17),
    "lumbar_bending": (-0.25, 20.36, 0.25, -20.36, -0.3491, 0.3491),
    "lumbar_rotation": (-0.25, 20.36, 0.25, -20.36, -0.3491, 0.3491),
}
"""``(k1 N·m, k2 1/rad, k3 N·m, k4 1/rad, θ1 rad, θ2 rad)`` per DoF (side suffix dropped): PredSim
a50fb31dba ``PreProcessing/default_coord_lim_torq_coeff.csv`` (Anderson & Pandy 1999 form).
The knee is mapped from OpenSim's ``knee_angle`` (negative in flexion): ``θ = −knee_angle``, the
moment negated, so the stops swap (``k1' = −k3``, ``k2' = −k4``, ``θ2' = −θ1``, and back)."""
ANDERSON_PASSIVE: dict[str, dict[str, tuple[float, float, float, float]]] = {
    "male": {"hip_flexion": (1.210, -6.351, -0.476, 5.910),
             "knee_flexion": (0.0, 0.0, 6.250, -4.521),
             "ankle_dorsiflexion": (0.000578, -5.819, -0.967, 6.090)},
    "female": {"hip_flexion": (1.753, -6.358, -0.239, 3.872),
               "knee_flexion": (0.0, 0.0, 8.033, -5.250),
               "ankle_dorsiflexion": (0.005218, -4.875, -0.470, 6.425)},
}  # fmt: skip
"""``(b1 N·m, k1 1/rad, b2 N·m, k2 1/rad)``: the whole joint's passive moment ``b1 exp(k1 θ) +
b2 exp(k2 θ)`` (muscles, tendons and ligaments) of Anderson, Madigan & Nussbaum (2007) J Biomech
40:3105, Table 3, young adults by sex (RBDL ``Anderson2007Table3Mean``; the rows of the hip
flexors, knee flexors and dorsiflexors, so positive flexes or dorsiflexes), docs/stance-model.md
§3. Not scaled by body mass, as published. At 0° the knee gets 6–8 N·m of flexion, and 20° of
hip extension 11–16 N·m of flexion."""
DAMPING = 0.1
"""N·m·s/rad on each DoF of :data:`LIMIT_TORQUES` (PredSim's ``damping_coefficient_all_dofs``)."""


def limit_moment(name: str, theta: Any) -> Any:
    """The range-stop moment of DoF ``name`` (no side suffix) at angle ``θ`` (rad), N·m; 0 for
    a DoF without a stop."""
    if name not in LIMIT_TORQUES:
        return 0.0 * theta
    k1, k2, k3, k4, lo, hi = LIMIT_TORQUES[name]
    return k1 * mo.exp(k2 * (theta - hi)) + k3 * mo.exp(k4 * (theta - lo))


def joint_moment(name: str, theta: Any, sex: str) -> Any:
    """The whole joint's passive moment of DoF ``name`` (no side suffix) at ``θ`` (rad), N·m
    (:data:`ANDERSON_PASSIVE`); 0 for the DoFs it does not cover."""
    coef = ANDERSON_PASSIVE["female" if sex == "female" else "male"].get(name)
    if coef is None:
        return 0.0 * theta
    b1, k1, b2, k2 = coef
    return b1 * mo.exp(k1 * theta) + b2 * mo.exp(k2 * theta)


def passive_moments(
    body: BodyModel, values: list[Any], rates: list[Any], total: bool = False
) -> list[Any]:
    """Per DoF, the passive moment (N·m) from the coordinate values ``q`` and the DoF angular
    rates (rad/s): range stop minus damping where :data:`LIMIT_TORQUES` has the DoF, else 0;
    ``total`` adds the whole joint's passive moment (:func:`joint_moment`)."""
    out = []
    for i, dof in enumerate(body.dof_names):
        name = dof.removesuffix("_r").removesuffix("_l")
        if name in LIMIT_TORQUES:
            theta = 2.0 * mo.asin(values[i])
            m = limit_moment(name, theta) - DAMPING * rates[i]
            out.append(m + joint_moment(name, theta, body.sex) if total else m)
        else:
            out.append(0.0 * rates[i])
    return out


def active_state(
    body: BodyModel, st: GaitState, values: list[Any], total: bool = False
) -> GaitState:
    """``st`` with each DoF's moment replaced by its active part ``M − M_passive`` (the moments
    about locked axes are unchanged); ``values``: the 24 joint coordinates ``q``; ``total``: as
    :func:`passive_moments`."""
    rates = [r for j in st.rates for r in j]
    passive = passive_moments(body, values, rates, total)
    moments, i = [], 0
    for j, joint in enumerate(body.joints):
        m = list(st.moments[j])
        for slot in joint.dof_slots:
            m[slot] = m[slot] - passive[i]
            i += 1
        moments.append(tuple(m))
    return dataclasses.replace(st, moments=moments)


ELEMENT = Element("passive", lambda body, model, st, values: active_state(
    body, st, values, model.passive_total))  # fmt: skip
"""The passive joints as a model element: on with ``ModelSettings.passive``."""
