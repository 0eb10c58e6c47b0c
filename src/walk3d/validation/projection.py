"""Measured stance legs projected onto walk3d's stance-foot constraint.

walk3d's stance foot only pitches: its global orientation is a rotation by ``θ`` about the
foot axis (global z), zero at foot flat. A measured foot also rolls and yaws during stance (and
an OpenSim foot frame is not exactly level at foot flat), so driving walk3d's chain, which starts
at the stance foot, with the measured joint angles tilts the whole body by the foot's roll: on
the Falisse 2019 cycle the pelvis then sways laterally with accelerations of ~2 g.

The projection keeps the measured upper body and leg inclination instead. At every sample
where a leg is in stance, its six angles (hip adduction, rotation, flexion, knee, ankle,
subtalar) and ``θ`` are moved as little as possible (weighted least squares, radians, see
:data:`ANGLE_WEIGHTS`) such that the chain from the pure-pitch foot reproduces the measured
pelvis orientation (weight 100: to a small fraction of a degree),

    q_pelvis = q_foot(θ) ⊗ conj(q_hip ⊗ q_knee ⊗ q_ankle),

and the measured direction of the shank's long axis (weight 10; otherwise the foot's roll
reappears as a lean of the whole leg, which moves the pelvis sideways by ~7 cm). ``θ`` is held
close to the measured foot pitch minus its foot-flat value (weight 10). In swing
the correction is interpolated linearly (in cycle phase) between its values at toe off and heel
strike, so the corrected angles stay continuous: a jump would make the Fourier fit ring, and
ringing of a stance leg's angles is amplified by the leg's length into large accelerations.
The changes are reported per DoF (RMS over stance, degrees).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from walk3d.body.model import MIRROR_AXIAL, BodyModel
from walk3d.kinematics import quaternion as qt
from walk3d.trials.kinematics import MeasuredKinematics, zxy_quaternion

__all__ = ["LEG_DOFS", "ProjectedStance", "joint_quaternion_from_angles", "project_stance"]

LEG_DOFS = ("hip_adduction", "hip_rotation", "hip_flexion", "knee_flexion",
            "ankle_dorsiflexion", "subtalar_inversion")  # fmt: skip
ORIENTATION_WEIGHT = 100.0
SHANK_WEIGHT = 10.0
FOOT_WEIGHT = 10.0
ANGLE_WEIGHTS = (1.0, 0.3, 1.0, 1.0, 0.2, 0.2)
"""Cost of moving hip adduction, rotation, flexion, knee, ankle, subtalar (per radian): the two
ankle axes are cheap, so that they absorb the difference between the measured foot and walk3d's
pure-pitch foot, hip rotation is cheap-ish (it takes up the yaw the oblique subtalar axis
brings), and the thigh and shank keep their measured inclinations."""


@dataclass(frozen=True)
class ProjectedStance:
    """Projected angles (a copy of the measured ones with stance samples replaced)."""

    angles: dict[str, np.ndarray]
    foot_rotation: dict[str, np.ndarray]
    """walk3d stance-foot rotation θ per side ('r', 'l'), rad, on every sample (swing samples:
    measured pitch minus its foot-flat value)."""
    change_deg: dict[str, float]
    """RMS change of each leg DoF over its stance samples, deg."""
    residual_deg: float
    """Largest remaining pelvis-orientation mismatch, deg."""


def joint_quaternion_from_angles(joint, angles: np.ndarray) -> np.ndarray:
    """``(N, 4)`` child-to-parent quaternion of a joint from anatomical angles (N, n_dof) in
    DoF order (the inverse of walk3d's angle reporting)."""
    a = np.atleast_2d(angles)
    if joint.kind == "ball":
        q = zxy_quaternion(a[:, 2], a[:, 0], a[:, 1])
        return qt.mirror(q) if joint.side == "l" else q
    q = qt.from_axis_angle(joint.axis, a[:, 0])
    if joint.kind == "universal":
        q = qt.multiply(q, qt.from_axis_angle(joint.axis2, a[:, 1]))
    return q


def _joints(body: BodyModel, side: str):
    return [body.joints[body.joint_index(f"{j}_{side}")] for j in ("hip", "knee", "ankle")]


def _thigh_shank(joints, leg: np.ndarray) -> np.ndarray:
    """Hip ⊗ knee quaternion (shank relative to pelvis) of leg angles (6,)."""
    hip, knee, _ = joints
    q = joint_quaternion_from_angles(hip, leg[None, 0:3])
    return qt.multiply(q, joint_quaternion_from_angles(knee, leg[None, 3:4]))


def _rotvec(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Small rotation (rad) from orientation ``a`` to ``b``, both (1, 4)."""
    e = qt.multiply(qt.conjugate(a), b)[0]
    return 2.0 * e[1:] * (1.0 if e[0] >= 0 else -1.0)


def _solve(body, side, q_pelvis, leg0, theta0):
    joints = _joints(body, side)
    axis = body.foot_axis * (MIRROR_AXIAL if side == "l" else 1.0)
    up = np.array([[0.0, 1.0, 0.0]])
    shank_axis = qt.rotate(qt.multiply(q_pelvis[None], _thigh_shank(joints, leg0)), up)[0]
    weights = np.array(ANGLE_WEIGHTS)

    def residual(z):
        q_foot = qt.from_axis_angle(axis, z[6])[None]
        q_shank = qt.multiply(
            q_foot, qt.conjugate(joint_quaternion_from_angles(joints[2], z[None, 4:6]))
        )
        q_rec = qt.multiply(q_shank, qt.conjugate(_thigh_shank(joints, z[:6])))
        return np.concatenate([
            ORIENTATION_WEIGHT * _rotvec(q_pelvis[None], q_rec),
            SHANK_WEIGHT * (qt.rotate(q_shank, up)[0] - shank_axis),
            weights * (z[:6] - leg0),
            [FOOT_WEIGHT * (z[6] - theta0)],
        ])  # fmt: skip

    z0 = np.append(leg0, theta0)
    sol = least_squares(residual, z0, method="lm", xtol=1e-10, ftol=1e-10)
    err = residual(sol.x)[:3] / ORIENTATION_WEIGHT
    return sol.x, float(np.degrees(np.linalg.norm(err)))


def _blend_swing(phase: np.ndarray, stance: np.ndarray, correction: np.ndarray, period: float):
    """Correction on every sample: as solved in stance, linear in phase across swing."""
    if not stance.any():
        return np.zeros_like(correction)
    order = np.argsort(phase[stance])
    ps, cs = phase[stance][order], correction[stance][order]
    out = np.interp(phase, ps, cs, period=period)
    out[stance] = correction[stance]
    return out


def project_stance(
    body: BodyModel,
    kin: MeasuredKinematics,
    stance: dict[str, np.ndarray],
    pitch: dict[str, np.ndarray],
    flat_pitch: dict[str, float],
    phase: np.ndarray,
    period: float,
) -> ProjectedStance:
    """Project each stance sample (module doc).

    Args:
        stance: Per side ('r', 'l'), a boolean mask of the samples in stance.
        pitch: Per side, the measured global foot pitch (rad).
        flat_pitch: Per side, the measured pitch at foot flat (rad).
        phase: walk3d time of each sample (s), for blending the correction across swing.
        period: Gait period T (s).
    """
    if kin.pelvis_angles is None:
        raise ValueError("the projection needs the measured pelvis orientation")
    q_pelvis = zxy_quaternion(*kin.pelvis_angles.T)
    angles = {k: np.array(v, dtype=float) for k, v in kin.angles.items()}
    theta_out, change, worst = {}, {}, 0.0
    for side in pitch:
        names = [f"{d}_{side}" for d in LEG_DOFS]
        theta = pitch[side] - flat_pitch[side]
        theta_out[side] = theta.copy()
        if not all(n in angles for n in names):
            continue
        leg = np.column_stack([angles[n] for n in names])
        new = leg.copy()
        for i in np.flatnonzero(stance[side]):
            z, err = _solve(body, side, q_pelvis[i], leg[i], theta[i])
            new[i], theta_out[side][i] = z[:6], z[6]
            worst = max(worst, err)
        mask = stance[side]
        for k, n in enumerate(names):
            delta = _blend_swing(np.mod(phase, period), mask, new[:, k] - leg[:, k], period)
            angles[n] = leg[:, k] + delta
            d = new[mask, k] - leg[mask, k]
            change[n] = float(np.degrees(np.sqrt(np.mean(d**2)))) if mask.any() else 0.0
    return ProjectedStance(angles, theta_out, change, worst)
