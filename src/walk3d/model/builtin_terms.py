"""The built-in criterion terms beyond the paper's two (docs/criteria.md has the formulas,
the sources of the scales and the x/y/z splits).

Every term is the cycle integral of a dimensionless square, in s, like C_tor. Each scale is
about the root-mean-square of its quantity in measured adult walking, so a human-like gait
scores about 1 per second on every term and weights near 1 give comparable contributions.
``2 q`` is a joint angle to first order (``q = sin(θ/2)`` about each axis).
"""

from __future__ import annotations

import math
from typing import Any

from walk3d import mathops as mo
from walk3d.body.model import BodyModel
from walk3d.constants import G
from walk3d.kinematics import quaternion as qt
from walk3d.kinematics.forward import Pose
from walk3d.model import effort
from walk3d.model.term import Node, Parts, Term
from walk3d.model.tracking import TRACK_REF

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


def _by_axis(node: Node, dofs: list[int], value: Any) -> Parts:
    """``Σ_i value(i) / len(dofs)`` over ``dofs``, each into its DoF's axis part."""
    parts = [node.zero, node.zero, node.zero]
    for i in dofs:
        parts[node.axes[i]] = parts[node.axes[i]] + value(i) / len(dofs)
    return parts[0], parts[1], parts[2]


def _accel(node: Node, ref: float) -> Parts:
    return _by_axis(node, list(range(24)), lambda i: (2.0 * node.coords[i][2] / ref) ** 2)


def _head(node: Node, ref: tuple[float, float]) -> Parts:
    ih = node.body.segment_index("head")
    a_h, w_h = node.pose.com[ih][2], node.pose.omega[ih]
    return tuple(0.5 * ((a_h[k] / ref[0]) ** 2 + (w_h[k] / ref[1]) ** 2) for k in range(3))


def _weight(node: Node) -> float:
    return node.body.mass * G


def _impact(node: Node, ref: float) -> Parts:
    above = mo.fmax(node.force[1] / _weight(node) - 1.0, node.zero)
    return node.zero, (above / ref) ** 2, node.zero


def _sag(node: Node, ref: float) -> Parts:
    below = mo.fmax(1.0 - node.force[1] / _weight(node), node.zero)
    return node.zero, (below / ref) ** 2, node.zero


def _shear(node: Node, ref: float) -> Parts:
    wf = _weight(node)
    return (node.force[0] / (wf * ref)) ** 2, node.zero, (node.force[2] / (wf * ref)) ** 2


def pose_targets(body: BodyModel) -> list[tuple[int, float]]:
    """``(DoF index, relaxed angle in rad)`` of the pose term's DoFs."""
    out = []
    for i, name in enumerate(body.dof_names):
        if name.startswith(POSE_DOFS):
            deg = next((v for k, v in NEUTRAL_DEG.items() if name.startswith(k)), 0.0)
            out.append((i, math.radians(deg)))
    return out


def _pose(node: Node, ref: float) -> Parts:
    targets = dict(pose_targets(node.body))
    return _by_axis(node, list(targets),
                    lambda i: ((2.0 * node.coords[i][0] - targets[i]) / ref) ** 2)  # fmt: skip


def _arms(node: Node, ref: float) -> Parts:
    arm = [i for i, name in enumerate(node.body.dof_names) if name.startswith(ARM_DOFS)]
    return _by_axis(node, arm, lambda i: (2.0 * node.coords[i][2] / ref) ** 2)


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


def _momentum_of(node: Node) -> tuple[Any, Any, Any]:
    return node.shared("angular_momentum", lambda n: angular_momentum(n.body, n.pose))


def _per_walker(node: Node) -> float:
    """Body mass × stature × 1.3 m/s, the unit of the momentum scales (kg m²/s)."""
    return node.body.mass * node.body.height * 1.3


def _momentum(node: Node, ref: float) -> Parts:
    h, h_ref = _momentum_of(node), ref * _per_walker(node)
    return tuple((h[k] / h_ref) ** 2 for k in range(3))


def _spin(node: Node, ref: float) -> Parts:
    h = _momentum_of(node)
    return node.zero, (h[1] / (ref * _per_walker(node))) ** 2, node.zero


def _pelvis(node: Node, ref: float) -> Parts:
    w_p = node.pose.omega[node.body.segment_index("pelvis")]
    return tuple((w_p[k] / ref) ** 2 for k in range(3))


def _effort_ratios(node: Node) -> list[Any]:
    """``u_i``, each DoF's active moment over its angle-dependent strength (shared)."""
    values = [c[0] for c in node.coords[:24]]
    return node.shared("effort_ratios", lambda n: effort.ratios(n.body, n.moments, values))


def _effort(node: Node, ref: float) -> Parts:
    u = _effort_ratios(node)
    return _by_axis(node, list(range(len(u))), lambda i: (u[i] / ref) ** 2)


def _effort3(node: Node, ref: float) -> Parts:
    u, eps = _effort_ratios(node), effort.CUBE_EPS
    return _by_axis(node, list(range(len(u))),
                    lambda i: ((u[i] / ref) ** 2 + eps) ** 1.5 - eps**1.5)  # fmt: skip


BUILTIN: tuple[Term, ...] = (
    Term("accel", _accel, ACCEL_REF, "the joint coordinates' accelerations (rad/s²)"),
    Term("jerk", None, JERK_REF, "the joint coordinates' third derivatives (rad/s³), exact on "
         "the Fourier coefficients (Parseval)"),
    Term("head", _head, (HEAD_ACCEL_REF, HEAD_RATE_REF),
         "the head's acceleration, gravity excluded (m/s²), and angular velocity (rad/s)"),
    Term("impact", _impact, IMPACT_REF, "the total vertical reaction above body weight (BW)"),
    Term("sag", _sag, IMPACT_REF, "the total vertical reaction below body weight (BW)"),
    Term("shear", _shear, SHEAR_REF, "the total horizontal reaction (BW)"),
    Term("pose", _pose, POSE_REF, "trunk, neck and arm angles from a relaxed posture (rad)"),
    Term("pelvis", _pelvis, PELVIS_RATE_REF, "the pelvis angular velocity (rad/s)"),
    Term("momentum", _momentum, MOMENTUM_REF,
         "the whole-body angular momentum (body mass × stature × 1.3 m/s)"),
    Term("spin", _spin, SPIN_REF, "its vertical part (body mass × stature × 1.3 m/s)"),
    Term("arms", _arms, ARM_ACCEL_REF, "the shoulders' and elbows' accelerations (rad/s²)"),
    Term("effort", _effort, effort.EFFORT_REF,
         "active moments over angle-dependent strengths, squared (1)", needs_moments=True),
    Term("effort3", _effort3, effort.EFFORT3_REF,
         "the same, cubed (1)", needs_moments=True),
    Term("track", None, TRACK_REF, "the joint angles' deviation from a measured gait (rad), "
         "on the coordinates at the nodes (ModelSettings.tracking)"),
)  # fmt: skip
"""The built-in terms, in the order they are reported."""
