"""Everything the prediction needs at one instant, written once for NumPy and CasADi.

:func:`evaluate` turns the 26 coordinates (24 joint coordinates + both stance-foot rotations,
each with first and second time derivatives) into kinematics, the split ground reaction, joint
moments, joint rates, and the quantities the constraints bound. Entries are NumPy arrays over
time nodes (results, tests) or CasADi ``SX`` scalars (the per-node function of the NLP).

The root of the chain is the foot that struck last; the other foot is expected on its own
roll-over path around ``anchor_other`` — in double support (closed loop) and at its heel strike.
With a handover share ``h`` (:func:`walk3d.contact.phases.handover_share`) the body is moved by
``h`` of the rigid motion that puts the trailing foot onto its own roll-over pose
(:func:`walk3d.kinematics.forward.blended_root`): at heel strike it is rooted at the trailing
foot as just before, so its velocity is continuous there. The closed-loop rows still read the
chain from the root foot.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from walk3d import mathops as mo
from walk3d.body.model import BodyModel
from walk3d.contact.transition import heel_strike_wrench, split
from walk3d.dynamics.newton_euler import (
    Wrench,
    inertial_loads,
    joint_loads,
    resolve_joint_moments,
    total_ground_reaction,
)
from walk3d.kinematics import quaternion as qt
from walk3d.kinematics.forward import (
    Pose,
    blended_root,
    forward,
    joint_quaternions,
    point_triple,
    root_foot_triples,
)
from walk3d.model.coordinates import I_FOOT_L, I_FOOT_R


@dataclass(frozen=True)
class GaitState:
    """Outputs of :func:`evaluate` (component form; see field docs)."""

    pose: Pose
    root: str
    total: Wrench
    """Total ground reaction, moment about the origin."""
    feet: dict[str, Wrench]
    """Ground wrench per foot ('r', 'l'), moment about the origin."""
    moments: list[qt.V]
    """Joint moments on the joint axes, 12 × (x, y, z) slots."""
    rates: list[list[Any]]
    """Per joint, the angular rate about each DoF axis (rad/s), in DoF order."""
    hs_wrench: Wrench
    """Total reaction as ``(F0, M0 about the non-root ankle)`` (used at heel strike)."""
    loop_position: qt.V
    loop_orientation: qt.V
    loop_velocity: qt.V
    loop_omega: qt.V
    """Closed-loop residuals of the non-root foot against its own roll-over path."""
    other_points_y: list[Any]
    """Heights of the non-root foot's heel, toe, met1, met5."""
    ankle_z: dict[str, Any]
    torso_orientation: qt.Q


def _dof_rates(body: BodyModel, pose: Pose, dof: list) -> list[list[Any]]:
    rates, i = [], 0
    for joint in body.joints:
        if joint.kind == "ball":
            w_rel = qt.vsub(pose.omega[joint.child], pose.omega[joint.parent])
            w_p = qt.qrot_inv(pose.orientation[joint.parent][0], w_rel)
            rates.append([qt.vdot(w_p, tuple(joint.axes[k])) for k in range(3)])
        else:
            rates.append(
                [
                    2.0 * dof[i + k][1] / mo.sqrt(1.0 - dof[i + k][0] ** 2)
                    for k in range(joint.n_dof)
                ]
            )
        i += joint.n_dof
    return rates


def evaluate(
    body: BodyModel,
    coords: list[tuple[Any, Any, Any]],
    root: str,
    anchor_root: tuple[Any, Any],
    anchor_other: tuple[Any, Any],
    decay: Any,
    w0: Wrench | None,
    dynamics: bool = True,
    balance: bool = True,
    split_total: bool = False,
    handover: tuple[Any, Any, Any] | None = None,
) -> GaitState:
    """Evaluate the gait at the nodes described by ``coords`` (26 triples).

    ``decay`` is the trailing-foot share ``e(τ)`` (0 in single stance); ``w0`` the trailing foot's
    heel-strike wrench (force, moment about its ankle), or None to use this instant's own total
    (which makes the trailing foot carry everything: the heel-strike instant itself).
    With ``dynamics=False`` only kinematic outputs and the total ground reaction are computed
    (no joint moments); the root foot is given that total (so a first stage can keep it
    pushing, within friction and under the feet), the other foot and all moments are zero.
    With ``balance=False`` as well, the total is zero too: geometry only. ``split_total`` (with
    ``dynamics=False, balance=True``): the total is shared between the feet as with dynamics
    (transition function, heel-strike wrench), still without joint moments. ``handover``:
    the share ``(h, ḣ, ḧ)`` of the trailing foot in the root (module doc), None for none.
    """
    other = "l" if root == "r" else "r"
    dof = coords[:24]
    s_foot = {"r": coords[I_FOOT_R], "l": coords[I_FOOT_L]}
    i_root = body.segment_index(f"foot_{root}")
    i_other = body.segment_index(f"foot_{other}")
    jq = joint_quaternions(body, dof)
    q_root, p_root = root_foot_triples(body, root, s_foot[root], anchor_root)
    pose = forward(body, jq, i_root, q_root, p_root)

    q_exp, p_exp = root_foot_triples(body, other, s_foot[other], anchor_other)
    q_chain = pose.orientation[i_other]
    p_chain = pose.origin[i_other]
    loop_pose = pose
    if handover is not None:
        root_pose = blended_root((q_root, p_root), (q_chain, p_chain), (q_exp, p_exp), handover)
        pose = forward(body, jq, i_root, *root_pose)
    rel = qt.qmul(qt.qconj(q_exp[0]), q_chain[0])
    w_exp_b, _ = qt.omega_alpha_body(q_exp)
    w_exp = qt.qrot(q_exp[0], w_exp_b)

    ankle_other = pose.origin[i_other][0]
    zero = 0.0 * ankle_other[0]
    z3 = (zero, zero, zero)
    inertial = inertial_loads(body, pose) if dynamics else None
    total = total_ground_reaction(body, pose) if dynamics or balance else (z3, z3)
    if dynamics or balance and split_total:  # the trailing foot's share from its heel strike
        hs = heel_strike_wrench(total, ankle_other)
        root_w, other_w = split(total, decay, hs if w0 is None else w0, ankle_other)
    else:  # the root foot carries the whole total (zero in a geometry-only stage)
        root_w, hs, other_w = total, (z3, z3), (z3, z3)
    if dynamics:
        loads = joint_loads(body, pose, {i_root: root_w, i_other: other_w}, inertial=inertial)
        moments = resolve_joint_moments(body, pose, loads)
    else:
        moments = [z3] * len(body.joints)
    pts = body.foot.points(other)
    return GaitState(
        pose=pose,
        root=root,
        total=total,
        feet={root: root_w, other: other_w},
        moments=moments,
        rates=_dof_rates(body, pose, dof),
        hs_wrench=hs,
        loop_position=qt.vsub(p_chain[0], p_exp[0]),
        loop_orientation=(rel[1], rel[2], rel[3]),
        loop_velocity=qt.vsub(p_chain[1], p_exp[1]),
        loop_omega=qt.vsub(loop_pose.omega[i_other], w_exp),
        other_points_y=[point_triple(loop_pose, i_other, p)[0][1] for p in pts],
        ankle_z={root: loop_pose.origin[i_root][0][2], other: p_chain[0][2]},
        torso_orientation=pose.orientation[body.segment_index("torso")][0],
    )


def dof_moment_terms(body: BodyModel, state: GaitState) -> tuple[list[Any], list[Any], list[int]]:
    """Per DoF: moment about its axis, its angular rate, and its axis label (0=x, 1=y, 2=z)."""
    moments, rates, axes = [], [], []
    for j, joint in enumerate(body.joints):
        for k, slot in enumerate(joint.dof_slots):
            moments.append(state.moments[j][slot])
            rates.append(state.rates[j][k])
            axes.append(slot)
    return moments, rates, axes


def strength_weights(body: BodyModel) -> tuple[np.ndarray, np.ndarray]:
    """``a, b`` with ``|M|/M_max(direction) = a|M| + bM`` per DoF (direction-dependent strength)."""
    pos = np.concatenate([j.strength_pos for j in body.joints])
    neg = np.concatenate([j.strength_neg for j in body.joints])
    return 0.5 * (1 / pos + 1 / neg), 0.5 * (1 / pos - 1 / neg)
