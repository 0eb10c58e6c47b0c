"""Newton–Euler inverse dynamics (paper Eqs. 4–5).

Sign conventions:

* ``inertial_loads``: ``F_i = m_i (a_i - g)`` and ``τ_i = I_i α_i + ω_i × I_i ω_i`` (about the
  centre of mass, global frame): the net external force and moment each segment needs.
* External loads are given per segment as ``(F, M_O)``: force and moment about the global origin.
* Joint loads ``(F_j, M_j)`` are exerted **by the parent on the child**, the moment taken about
  the joint centre, global frame.

Joint loads are solved segment by segment from the leaves: bottom-up from each foot to the hip,
top-down from the head and each forearm to the torso; the waist load then follows from the torso
("from above"). The pelvis equation gives it again "from below" (:func:`waist_from_below`); the
two agree exactly when the ground reaction equals the whole-body momentum change (Eq. 5).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from walk3d.body.model import BodyModel
from walk3d.constants import G
from walk3d.kinematics import quaternion as qt
from walk3d.kinematics.forward import Pose
from walk3d.kinematics.quaternion import V, vadd, vcross, vscale, vsub

Wrench = tuple[V, V]
"""``(force, moment)``; the moment's reference point is stated where a wrench is used."""


def _vsum(vs: list[V], like: Any) -> V:
    out: V = (0.0 * like, 0.0 * like, 0.0 * like)
    for v in vs:
        out = vadd(out, v)
    return out


def inertial_loads(body: BodyModel, pose: Pose) -> tuple[list[V], list[V]]:
    """``(F_i, τ_i)`` per segment: ``m(a - g)`` and the rate of angular momentum about the COM."""
    forces, torques = [], []
    for i, seg in enumerate(body.segments):
        a = pose.com[i][2]
        forces.append((seg.mass * a[0], seg.mass * (a[1] + G), seg.mass * a[2]))
        q = pose.orientation[i][0]
        w_b = qt.qrot_inv(q, pose.omega[i])
        a_b = qt.qrot_inv(q, pose.alpha[i])
        inertia = seg.inertia
        iw = (inertia[0] * w_b[0], inertia[1] * w_b[1], inertia[2] * w_b[2])
        ia = (inertia[0] * a_b[0], inertia[1] * a_b[1], inertia[2] * a_b[2])
        torques.append(qt.qrot(q, vadd(ia, vcross(w_b, iw))))
    return forces, torques


def total_ground_reaction(body: BodyModel, pose: Pose) -> Wrench:
    """Eq. 5: total ground force and its moment about the global origin."""
    forces, torques = inertial_loads(body, pose)
    like = pose.com[0][0][0]
    f = _vsum(forces, like)
    mo = _vsum([vadd(t, vcross(pose.com[i][0], forces[i])) for i, t in enumerate(torques)], like)
    return f, mo


@dataclass(frozen=True)
class JointLoads:
    """Joint loads per joint (parent on child, moment about the joint centre, global)."""

    force: list[V]
    moment: list[V]


def joint_loads(
    body: BodyModel, pose: Pose, external: dict[int, Wrench], inertial=None
) -> JointLoads:
    """Solve Eq. 4 from the leaves towards the pelvis.

    ``external`` maps segment index to an applied ``(F, M_O)`` (moment about the origin), e.g.
    the ground reactions on the feet. ``inertial`` may pass precomputed :func:`inertial_loads`.
    """
    forces, torques = inertial if inertial is not None else inertial_loads(body, pose)
    n_j = len(body.joints)
    fj: list[V | None] = [None] * n_j
    mj: list[V | None] = [None] * n_j
    children: dict[int, list[int]] = {}
    for j, joint in enumerate(body.joints):
        children.setdefault(joint.parent, []).append(j)
    for j in reversed(range(n_j)):
        c = body.joints[j].child
        rc = pose.com[c][0]
        rj = pose.origin[c][0]
        f = forces[c]
        m = torques[c]
        for k in children.get(c, []):
            rk = pose.origin[body.joints[k].child][0]
            f = vadd(f, fj[k])
            m = vadd(m, vadd(mj[k], vcross(vsub(rk, rc), fj[k])))
        if c in external:
            fe, me = external[c]
            f = vsub(f, fe)
            m = vsub(m, vsub(me, vcross(rc, fe)))
        fj[j] = f
        mj[j] = vsub(m, vcross(vsub(rj, rc), f))
    return JointLoads(fj, mj)  # type: ignore[arg-type]


def waist_from_below(
    body: BodyModel, pose: Pose, loads: JointLoads, external: dict[int, Wrench], inertial=None
) -> Wrench:
    """The waist load (pelvis on torso) from the pelvis equation, i.e. from the legs up."""
    forces, torques = inertial if inertial is not None else inertial_loads(body, pose)
    waist = body.joint_index("waist")
    rc = pose.com[0][0]
    rw = pose.origin[body.joints[waist].child][0]
    f = vscale(-1.0, forces[0])
    m = vscale(-1.0, torques[0])
    for k, joint in enumerate(body.joints):
        if joint.parent != 0 or k == waist:
            continue
        rk = pose.origin[joint.child][0]
        f = vsub(f, loads.force[k])
        m = vsub(m, vadd(loads.moment[k], vcross(vsub(rk, rc), loads.force[k])))
    if 0 in external:
        fe, me = external[0]
        f = vadd(f, fe)
        m = vadd(m, vsub(me, vcross(rc, fe)))
    return f, vsub(m, vcross(vsub(rw, rc), f))


def segment_residuals(
    body: BodyModel, pose: Pose, loads: JointLoads, external: dict[int, Wrench]
) -> list[Wrench]:
    """Newton–Euler residuals ``(ΣF - m(a-g), ΣM_com - τ)`` of every segment."""
    forces, torques = inertial_loads(body, pose)
    out = []
    for i in range(len(body.segments)):
        rc = pose.com[i][0]
        f = vscale(-1.0, forces[i])
        m = vscale(-1.0, torques[i])
        for k, joint in enumerate(body.joints):
            rk = pose.origin[joint.child][0]
            if joint.child == i:  # load from the parent
                f = vadd(f, loads.force[k])
                m = vadd(m, vadd(loads.moment[k], vcross(vsub(rk, rc), loads.force[k])))
            elif joint.parent == i:  # reaction of the child
                f = vsub(f, loads.force[k])
                m = vsub(m, vadd(loads.moment[k], vcross(vsub(rk, rc), loads.force[k])))
        if i in external:
            fe, me = external[i]
            f = vadd(f, fe)
            m = vadd(m, vsub(me, vcross(rc, fe)))
        out.append((f, m))
    return out


def resolve_joint_moments(body: BodyModel, pose: Pose, loads: JointLoads) -> list[V]:
    """Joint moments on each joint's axes, slots ``(x, y, z)`` = (frontal, transverse, sagittal).

    Ball joints: components along the joint axes in the parent frame. Hinges: the sagittal slot
    holds the moment about the hinge axis (the generalized force of the joint angle), the other
    slots the structural components along the parent axes. Universal joints: slot z about the
    first (talocrural) axis, slot x about the second (subtalar) axis in its current direction,
    slot y structural.
    """
    out = []
    for j, joint in enumerate(body.joints):
        qp = pose.orientation[joint.parent][0]
        mp = qt.qrot_inv(qp, loads.moment[j])
        slots = [qt.vdot(mp, tuple(joint.axes[k])) for k in range(3)]
        if joint.kind == "hinge":
            slots[2] = qt.vdot(mp, tuple(joint.axis))
        elif joint.kind == "universal":
            slots[2] = qt.vdot(mp, tuple(joint.axis))
            u2 = qt.qrot(pose.orientation[joint.child][0], tuple(joint.axis2))
            slots[0] = qt.vdot(loads.moment[j], u2)
        out.append(tuple(slots))
    return out
