"""Forward kinematics from the stance foot (paper Eqs. 1–3).

The chain starts at the root (stance) foot: its global orientation is one rotation about the
foot axis, its ankle follows the roll-over shape (Eq. 1). Walking up the leg by inverse joint
rotations gives the pelvis; from the pelvis, joint rotations give every other segment (Eq. 2).
Positions, velocities and accelerations are propagated exactly with the quaternion product rule
(Eq. 3), and ω, α follow from ``2 L Λ̇`` and ``2 L Λ̈``.

Joint coordinates (``dof`` below, 24 in :data:`walk3d.body.model.JOINT_NAMES` order) are
quaternion elements, not angles:

* ball joint: the quaternion's vector part along the joint axes ``(x, y, z)``;
* hinge: ``sin(θ/2)``;
* universal: ``sin(θ1/2), sin(θ2/2)``.

Everything works on component tuples whose entries are NumPy arrays over time nodes or CasADi
expressions (see :mod:`walk3d.mathops`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from walk3d.body.model import MIRROR_AXIAL, BodyModel, Joint
from walk3d.kinematics import quaternion as qt
from walk3d.kinematics.quaternion import QTriple, VTriple

Triple = tuple[Any, Any, Any]


@dataclass(frozen=True)
class Pose:
    """Kinematics of all segments (component form, lists in segment order)."""

    orientation: list[QTriple]
    """Segment-to-global quaternion triples (value, first, second time derivative)."""
    origin: list[VTriple]
    """Proximal joint centre (segment frame origin) triples, global."""
    com: list[VTriple]
    """Centre-of-mass triples, global."""
    omega: list[qt.V]
    """Global angular velocities."""
    alpha: list[qt.V]
    """Global angular accelerations."""


def joint_quaternion(joint: Joint, coords: list[Triple]) -> QTriple:
    """Joint quaternion triple (child to parent) from its coordinate triples."""
    if joint.kind == "ball":
        ax = joint.axes
        comp = [
            tuple(sum(ax[k, i] * coords[k][d] for k in range(3)) for i in range(3))
            for d in range(3)
        ]
        return qt.from_vector_triple(*comp)
    if joint.kind == "hinge":
        return qt.from_sine_triple(tuple(joint.axis), *coords[0])
    q1 = qt.from_sine_triple(tuple(joint.axis), *coords[0])
    q2 = qt.from_sine_triple(tuple(joint.axis2), *coords[1])
    return qt.qmul_triple(q1, q2)


def joint_quaternions(body: BodyModel, dof: list[Triple]) -> list[QTriple]:
    """All 12 joint quaternion triples from 24 coordinate triples."""
    out, i = [], 0
    for joint in body.joints:
        out.append(joint_quaternion(joint, dof[i : i + joint.n_dof]))
        i += joint.n_dof
    if i != len(dof):
        raise ValueError(f"expected {i} joint coordinates, got {len(dof)}")
    return out


def root_foot_triples(
    body: BodyModel, side: str, s_ft: Triple, anchor_xz: tuple[Any, Any]
) -> tuple[QTriple, VTriple]:
    """Orientation and ankle-position triples of a stance foot.

    ``s_ft`` = ``sin(θ_ft/2)`` with derivatives; ``anchor_xz`` = global x, z of the ankle at foot
    flat. The left foot uses the mirrored axis and lateral displacement.
    """
    axis = body.foot_axis * (MIRROR_AXIAL if side == "l" else 1.0)
    q = qt.from_sine_triple(tuple(axis), *s_ft)
    p, pd, pdd = body.rollover.ankle_triple(*s_ft)
    sz = -1.0 if side == "l" else 1.0
    pos = (
        (anchor_xz[0] + p[0], p[1], anchor_xz[1] + sz * p[2]),
        (pd[0], pd[1], sz * pd[2]),
        (pdd[0], pdd[1], sz * pdd[2]),
    )
    return q, pos


def forward(
    body: BodyModel,
    joint_q: list[QTriple],
    root_segment: int,
    root_orientation: QTriple,
    root_origin: VTriple,
) -> Pose:
    """Kinematics of every segment given one segment's global pose and all joint rotations.

    ``root_segment`` is usually a foot (its origin is the ankle joint centre); any segment works
    (the pelvis with a prescribed pose gives plain forward kinematics).
    """
    n = len(body.segments)
    ori: list[QTriple | None] = [None] * n
    org: list[VTriple | None] = [None] * n
    ori[root_segment], org[root_segment] = root_orientation, root_origin
    # walk up to the pelvis with inverse joint rotations
    seg = root_segment
    for j in body.path_to_pelvis(root_segment):
        joint = body.joints[j]
        parent = joint.parent
        ori[parent] = qt.qmul_triple(ori[seg], qt.qconj_triple(joint_q[j]))
        org[parent] = qt.vsub_triple(org[seg], qt.rotate_triple(ori[parent], tuple(joint.offset)))
        seg = parent
    # then down the tree from the pelvis (joints are ordered parent-before-child)
    for j, joint in enumerate(body.joints):
        c = joint.child
        if ori[c] is not None:
            continue
        p = joint.parent
        ori[c] = qt.qmul_triple(ori[p], joint_q[j])
        org[c] = qt.vadd_triple(org[p], qt.rotate_triple(ori[p], tuple(joint.offset)))
    com, omega, alpha = [], [], []
    for i, segment in enumerate(body.segments):
        com.append(qt.vadd_triple(org[i], qt.rotate_triple(ori[i], tuple(segment.com))))
        w_b, a_b = qt.omega_alpha_body(ori[i])
        omega.append(qt.qrot(ori[i][0], w_b))
        alpha.append(qt.qrot(ori[i][0], a_b))
    return Pose(ori, org, com, omega, alpha)  # type: ignore[arg-type]


def blended_root(
    root: tuple[QTriple, VTriple],
    chain: tuple[QTriple, VTriple],
    expected: tuple[QTriple, VTriple],
    share: Triple,
) -> tuple[QTriple, VTriple]:
    """The root foot's pose moved by ``share`` of the rigid motion that takes the other foot from
    where the chain puts it (``chain``: orientation, ankle) to its own roll-over pose
    (``expected``). The motion's rotation vector (the vector part of ``q_exp q_chain*``) is
    scaled, about the other foot's ankle; share 1 roots the body at the other foot, 0 leaves it."""
    (q_root, p_root), (q_ch, p_ch), (q_ex, p_ex) = root, chain, expected
    corr = qt.qmul_triple(q_ex, qt.qconj_triple(q_ch))
    vec = tuple((c[1], c[2], c[3]) for c in corr)
    q_s = qt.from_vector_triple(*qt.scale_triple(share, vec))  # type: ignore[arg-type]
    arm = qt.rotate_moving_triple(q_s, qt.vsub_triple(p_root, p_ch))
    shift = qt.scale_triple(share, qt.vsub_triple(p_ex, p_ch))
    return qt.qmul_triple(q_s, q_root), qt.vadd_triple(qt.vadd_triple(p_ch, shift), arm)


def point_triple(pose: Pose, segment: int, local: np.ndarray) -> VTriple:
    """Global position triple of a point fixed in a segment."""
    return qt.vadd_triple(
        pose.origin[segment], qt.rotate_triple(pose.orientation[segment], tuple(local))
    )


# --------------------------------------------------------------------------------------------
# NumPy conveniences
# --------------------------------------------------------------------------------------------
def stack_v(v: qt.V) -> np.ndarray:
    """Component tuple of (N,) arrays -> (N, 3) array."""
    return np.stack([np.broadcast_to(np.asarray(c, float), np.shape(v[0])) for c in v], axis=-1)


def stack_q(q: qt.Q) -> np.ndarray:
    """Component tuple of (N,) arrays -> (N, 4) array, scalar first."""
    return np.stack([np.broadcast_to(np.asarray(c, float), np.shape(q[1])) for c in q], axis=-1)
