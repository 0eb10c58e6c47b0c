"""Criterion terms beyond the paper's two, and the weighted criteria that combine them.

Every term is the cycle integral of a dimensionless square, in s, like C_tor. Each reference
scale is the root-mean-square of its quantity in measured adult walking, so a human-like gait
scores about 1 per second on every term and weights near 1 give comparable contributions
(docs/criteria.md has the formulas, the sources of the scales and the x/y/z splits):

* ``accel``: ``(1/24) Σ_i (2 q̈_i / 15 rad/s²)²``, the joint coordinates' accelerations
  (``2 q`` is the joint angle to first order: ``q = sin(θ/2)`` about each axis);
* ``jerk``: ``(1/24) Σ_i (2 q⃛_i / 400 rad/s³)²``, the same for the third derivative. Exact and
  diagonal in the Fourier coefficients (Parseval), so it is added to the NLP's objective on the
  coefficients (:func:`coefficient_weights`), not at the nodes;
* ``head``: ``½ (|a_head|² / (2 m/s²)² + |ω_head|² / (0.5 rad/s)²)``, the head's linear
  acceleration (gravity excluded) and angular velocity in the global frame;
* ``impact``: ``(max(F_y / body weight − 1, 0) / 0.25)²``, the total vertical ground reaction
  above body weight (the heel-strike and push-off peaks; the mid-stance dip is free);
* ``sag``: ``(max(1 − F_y / body weight, 0) / 0.25)²``, the same below body weight (the
  mid-stance dip; the force's mean is body weight, so a deep dip needs high peaks);
* ``shear``: ``(F_x² + F_z²) / (0.25 body weight)²``, the total horizontal ground reaction
  (braking, propulsion, lateral): the horizontal acceleration of the centre of mass;
* ``pose``: ``(1/12) Σ_i ((2 q_i − θ0_i) / 0.25 rad)²`` over the trunk, neck, shoulder and
  elbow DoFs, the deviation from a relaxed standing posture ``θ0`` (elbow 20°, others 0);
* ``pelvis``: ``|ω_pelvis|² / (0.7 rad/s)²``, the pelvis angular velocity in the global frame;
* ``momentum``: ``|H_com|² / (0.02 m h 1.3 m/s)²``, the whole body's angular momentum about its
  centre of mass;
* ``spin``: ``H_y² / (0.006 m h 1.3 m/s)²``, its vertical part alone, which arms swinging
  against the legs cancel (the sagittal part dominates ``momentum``);
* ``arms``: ``(1/8) Σ_i (2 q̈_i / 3 rad/s²)²`` over the shoulder and elbow DoFs, the arms'
  angular accelerations on the scale of a measured arm swing (it keeps the arms from swinging
  at twice the stride frequency to offset the trunk's fore-aft ground reaction);
* ``effort``, ``effort3``: ``(1/24) Σ_i (u_i / ref)^p``, p = 2 and 3, ``u_i = |M_i| /
  M_max,i(θ_i)`` the active joint moment over its angle-dependent strength
  (:mod:`walk3d.problem.effort`; the moments are passed in, :func:`integrands`).

Written on component tuples (:mod:`walk3d.mathops`): one code for the NLP nodes (CasADi) and
the evaluated cycle (NumPy).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from walk3d import mathops as mo
from walk3d.body.model import BodyModel
from walk3d.constants import G
from walk3d.kinematics import fourier
from walk3d.kinematics import quaternion as qt
from walk3d.kinematics.forward import Pose
from walk3d.problem import effort, layout

BASES = ("tor", "en")
"""The paper's criteria; a weighted criterion holds exactly one of them (its absolute values
are the exact slack variables of the NLP)."""
EXTRAS = ("accel", "jerk", "head", "impact", "sag", "shear", "pose", "pelvis", "momentum",
          "spin", "arms", *effort.NAMES)  # fmt: skip
"""Terms that can be added to a base, in the order they are reported."""
ACCEL_REF = 15.0
"""rad/s²: RMS joint angular acceleration over the DoFs of a measured adult (Falisse 2019
``gait_1``, 6 Hz low-pass: 15.9 rad/s²)."""
ARM_ACCEL_REF = 3.0
"""rad/s²: RMS angular acceleration of a walking adult's shoulder flexion, whose swing is about
±5° at the stride frequency (Falisse 2019 ``gait_1``: 5.0° first harmonic, 1.2° second)."""
ARM_DOFS = ("arm_", "elbow")
"""Prefixes of the DoFs the arms term covers: both shoulders (3 each) and elbows."""
JERK_REF = 400.0
"""rad/s³: RMS joint angular jerk over the DoFs of a measured adult (Falisse 2019 ``gait_1``,
6 Hz low-pass)."""
HEAD_ACCEL_REF = 2.0
"""m/s²: the order of magnitude of a walking adult's head acceleration (not fitted)."""
HEAD_RATE_REF = 0.5
"""rad/s: the order of magnitude of a walking adult's head angular velocity (not fitted)."""
IMPACT_REF = 0.25
"""Body weights: the total vertical reaction of walking deviates about ±0.25 BW from 1."""
SHEAR_REF = 0.25
"""Body weights: the fore-aft reaction of walking peaks at about ±0.2 BW."""
POSE_REF = 0.25
"""rad (14°): the spread of arm and trunk angles about their mean in measured walking."""
MOMENTUM_REF = 0.02
"""Whole-body angular momentum about the centre of mass, in units of body mass × stature ×
1.3 m/s: people keep it within about ±0.02–0.05 of that in walking (Herr & Popovic 2008)."""
SPIN_REF = 0.006
"""The vertical part of the whole-body angular momentum, same units as :data:`MOMENTUM_REF`:
the RMS of the `natural` preset's walk on the Falisse subject without this term (arms that
swing against the legs lower it)."""
PELVIS_RATE_REF = 0.7
"""rad/s: RMS pelvis angular velocity of a measured adult (Falisse 2019 ``gait_1``: 0.71)."""
NEUTRAL_DEG = {"elbow_flex": 20.0}
"""Relaxed standing posture, deg, for the pose term's DoFs; the rest are 0 (anatomical)."""
POSE_DOFS = ("lumbar", "neck", "arm_", "elbow")
"""Prefixes of the DoFs the pose term covers: trunk, neck, shoulders and elbows."""
PRESETS: dict[str, dict[str, float]] = {
    "natural": {"tor": 1.0, "accel": 0.5, "jerk": 1.0, "head": 0.5, "impact": 5.0, "shear": 1.0,
                "pose": 0.5, "pelvis": 1.0, "spin": 2.0, "arms": 1.0},
}  # fmt: skip
"""Named weighted criteria (docs/criteria.md: how the weights were chosen)."""
DEFAULT_PRESET = "natural"


def canonical(spec: str) -> str:
    """The criterion ``spec`` in canonical form: ``tor``, ``en``, or ``name=w,...`` in
    :data:`BASES` + :data:`EXTRAS` order with zero weights dropped. A preset name expands to
    its weights, so that the form says what is solved. Raises ValueError with one line."""
    weights = parse(spec)
    if set(weights) == {"tor"} and weights["tor"] == 1.0:
        return "tor"
    if set(weights) == {"en"} and weights["en"] == 1.0:
        return "en"
    return ",".join(f"{k}={weights[k]:g}" for k in BASES + EXTRAS if k in weights)


def parse(spec: str) -> dict[str, float]:
    """Weights by term name from ``tor``, ``en``, a preset name, or ``name=w,...``."""
    s = str(spec).strip()
    if s in BASES:
        return {s: 1.0}
    if s in PRESETS:
        return dict(PRESETS[s])
    known = ", ".join(BASES + EXTRAS)
    if "=" not in s:
        raise ValueError(f"criterion must be tor, en, a preset ({', '.join(PRESETS)}) or "
                         f"weights like 'tor=1,accel=0.5'; got {s!r}")  # fmt: skip
    weights: dict[str, float] = {}
    for part in filter(None, (p.strip() for p in s.split(","))):
        name, _, value = part.partition("=")
        name = name.strip()
        if name not in BASES + EXTRAS:
            raise ValueError(f"unknown criterion term {name!r} (known: {known})")
        try:
            w = float(value)
        except ValueError:
            raise ValueError(
                f"criterion weight of {name} must be a number, got {value!r}"
            ) from None
        if not math.isfinite(w) or w < 0:
            raise ValueError(f"criterion weight of {name} must be finite and ≥ 0, got {value!r}")
        if name in weights:
            raise ValueError(f"criterion term {name} is given twice")
        if w > 0:
            weights[name] = w
    bases = [b for b in BASES if b in weights]
    if len(bases) != 1:
        raise ValueError("a weighted criterion needs exactly one of tor and en with a weight > 0 "
                         f"(got {s!r})")  # fmt: skip
    return weights


def base(spec: str) -> str:
    """``tor`` or ``en``: the paper criterion inside ``spec`` (canonical or not)."""
    return next(b for b in BASES if b in parse(spec))


def extras(spec: str) -> dict[str, float]:
    """The weights of the terms of ``spec`` beyond its base, possibly empty."""
    return {k: w for k, w in parse(spec).items() if k in EXTRAS}


def label(spec: str) -> str:
    """Short name for tables and progress lines: ``C_tor``, ``C_en`` or ``C_weighted``."""
    return f"C_{spec}" if spec in BASES else "C_weighted"


def minimized(objective: dict, spec: str) -> float | None:
    """The criterion value the solver minimized, from a summary's ``objective``: ``C_weighted``'s
    total (the weighted terms and any what-if part: overload, step asymmetry), else the value of
    :func:`label` (older summaries), or None."""
    weighted = objective.get("C_weighted")
    if isinstance(weighted, dict) and isinstance(weighted.get("total"), (int, float)):
        return float(weighted["total"])
    return (objective.get(label(spec)) or {}).get("total")


def preset_name(spec: str) -> str | None:
    """The preset whose weights ``spec`` has, or None."""
    w = parse(spec)
    return next((n for n, p in PRESETS.items() if p == w), None)


def _pose_targets(body: BodyModel) -> list[tuple[int, float]]:
    out = []
    for i, name in enumerate(body.dof_names):
        if name.startswith(POSE_DOFS):
            deg = next((v for k, v in NEUTRAL_DEG.items() if name.startswith(k)), 0.0)
            out.append((i, math.radians(deg)))
    return out


def integrands(
    body: BodyModel,
    coords: list[tuple[Any, Any, Any]],
    pose: Pose,
    force: tuple[Any, Any, Any],
    moments: list[Any] | None = None,
) -> dict[str, tuple[Any, Any, Any]]:
    """Per term of :data:`EXTRAS`, its integrand split into ``(x, y, z)`` parts whose sum is the
    integrand (dimensionless, per s). ``accel`` and ``pose`` split by DoF axis as in
    :mod:`walk3d.problem.criteria` (x frontal, y transverse, z sagittal); ``head`` and
    ``pelvis`` by global axis; ``impact`` is all y; ``shear`` x and z.

    ``coords``: the 26 coordinate triples (value, rate, acceleration) of
    :func:`walk3d.problem.gait.evaluate`; ``pose`` its kinematics; ``force`` the total ground
    reaction, N; ``moments``: the 24 active DoF moments, N·m (the ``effort`` terms are left out
    without them)."""
    zero = 0.0 * force[1]
    axes = [slot for j in body.joints for slot in j.dof_slots]
    acc = [zero, zero, zero]
    for i in range(24):
        acc[axes[i]] = acc[axes[i]] + (2.0 * coords[i][2] / ACCEL_REF) ** 2 / 24.0
    ih = body.segment_index("head")
    a_h, w_h = pose.com[ih][2], pose.omega[ih]
    head = tuple(0.5 * ((a_h[k] / HEAD_ACCEL_REF) ** 2 + (w_h[k] / HEAD_RATE_REF) ** 2)
                 for k in range(3))  # fmt: skip
    wf = body.mass * G
    above = mo.fmax(force[1] / wf - 1.0, zero)
    impact = (zero, (above / IMPACT_REF) ** 2, zero)
    below = mo.fmax(1.0 - force[1] / wf, zero)
    sag = (zero, (below / IMPACT_REF) ** 2, zero)
    shear = ((force[0] / (wf * SHEAR_REF)) ** 2, zero, (force[2] / (wf * SHEAR_REF)) ** 2)
    targets = _pose_targets(body)
    posture = [zero, zero, zero]
    for i, theta0 in targets:
        dev = (2.0 * coords[i][0] - theta0) / POSE_REF
        posture[axes[i]] = posture[axes[i]] + dev**2 / len(targets)
    arm = [i for i, name in enumerate(body.dof_names) if name.startswith(ARM_DOFS)]
    arms = [zero, zero, zero]
    for i in arm:
        arms[axes[i]] = arms[axes[i]] + (2.0 * coords[i][2] / ARM_ACCEL_REF) ** 2 / len(arm)
    h = angular_momentum(body, pose)
    h_ref = MOMENTUM_REF * body.mass * body.height * 1.3
    momentum = tuple((h[k] / h_ref) ** 2 for k in range(3))
    spin = (zero, (h[1] / (SPIN_REF * body.mass * body.height * 1.3)) ** 2, zero)
    w_p = pose.omega[body.segment_index("pelvis")]
    pelvis = tuple((w_p[k] / PELVIS_RATE_REF) ** 2 for k in range(3))
    out = {"accel": tuple(acc), "head": head, "impact": impact, "sag": sag, "shear": shear,
           "pose": tuple(posture), "pelvis": pelvis, "momentum": momentum,
           "spin": spin, "arms": tuple(arms)}  # fmt: skip
    if moments is not None:
        out.update(effort.integrands(body, moments, [c[0] for c in coords[:24]], axes[:24]))
    return out


def jerk_per_coefficient(period: float) -> np.ndarray:
    """(N_COEF,) ``w_j`` with ``∫ (1/24) (2 q⃛ / JERK_REF)² dt = Σ_j w_j c_j²`` for one series
    over the cycle (Parseval: ``(T/2) (kω)⁶`` per cosine and sine coefficient, 0 for ``a0``)."""
    w = 2 * np.pi / period
    k = np.array([0] + [j for j in range(1, fourier.ORDER + 1) for _ in range(2)], dtype=float)
    return 0.5 * period * (k * w) ** 6 * 4.0 / (24.0 * JERK_REF**2)


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


def angular_momentum(body: BodyModel, pose: Pose) -> tuple[Any, Any, Any]:
    """Whole-body angular momentum about the centre of mass, global frame, kg m²/s:
    ``Σ_i R_i I_i R_iᵀ ω_i + m_i (r_i − r_c) × v_i``."""
    like = pose.com[0][0][0]
    m = [seg.mass for seg in body.segments]
    total = sum(m)
    rc = tuple(sum(m[i] * pose.com[i][0][k] for i in range(len(m))) / total for k in range(3))
    h = [0.0 * like, 0.0 * like, 0.0 * like]
    for i, seg in enumerate(body.segments):
        q = pose.orientation[i][0]
        w_b = qt.qrot_inv(q, pose.omega[i])
        iw = qt.qrot(q, tuple(seg.inertia[k] * w_b[k] for k in range(3)))
        r = qt.vsub(pose.com[i][0], rc)
        mv = qt.vscale(m[i], pose.com[i][1])
        own = qt.vadd(iw, qt.vcross(r, mv))
        h = [h[k] + own[k] for k in range(3)]
    return tuple(h)


def weighted(weights: dict[str, float], terms: dict[str, tuple[Any, Any, Any]]) -> Any:
    """``Σ_j w_j term_j`` over the node terms in ``weights`` (terms as from :func:`integrands`;
    ``jerk`` is not a node term)."""
    total = 0.0
    for name in EXTRAS:
        if name in weights and name in terms:
            x, y, z = terms[name]
            total = total + weights[name] * (x + y + z)
    return total


__all__ = ["BASES", "DEFAULT_PRESET", "EXTRAS", "PRESETS", "angular_momentum", "base",
           "canonical", "coefficient_weights", "extras", "integrands", "jerk_per_dof", "label",
           "parse", "preset_name", "weighted"]  # fmt: skip
