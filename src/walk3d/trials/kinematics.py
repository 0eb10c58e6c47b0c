"""Measured joint angles (OpenSim coordinates) as walk3d coordinates and poses.

:class:`MeasuredKinematics` holds angles keyed by walk3d DoF name (both sides, radians, walk3d
signs), the pelvis's OpenSim angles and origin, on a time axis. The conversions are the exact
inverses of walk3d's own reporting (:mod:`walk3d.results.angles`):

* ball joints: ``q = qz(flex) ⊗ qx(add) ⊗ qy(rot)`` (OpenSim's body-fixed Z-X-Y); walk3d's
  coordinates are its vector part. On the left this is the quaternion of the *anatomical*
  angles, which is what walk3d's mirrored left axes expect (``Σ c_k axes_k`` mirrors it back);
* hinges: ``sin(θ/2)``; universal ankle: ``sin(θ_tc/2), sin(θ_st/2)``, the axes being
  gait2392's talocrural and subtalar axes in both models.

:func:`segment_poses` runs walk3d's forward kinematics from the measured pelvis pose (OpenSim's
pelvis origin moved to walk3d's, midway between the hip centres, by :data:`PELVIS_TO_HIPS`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from walk3d.body.model import BodyModel
from walk3d.io.cycle_table import CycleTable
from walk3d.io.storage import Storage
from walk3d.kinematics import quaternion as qt
from walk3d.kinematics.forward import Pose, forward, joint_quaternions, stack_q, stack_v
from walk3d.results.opensim import OPENSIM_COORDINATES

__all__ = [
    "PELVIS_TO_HIPS",
    "MeasuredKinematics",
    "ankle_positions",
    "detect_knee_sign",
    "foot_pitch",
    "joint_coordinates",
    "kinematics_from_storage",
    "kinematics_from_table",
    "segment_poses",
    "zxy_quaternion",
]

PELVIS_TO_HIPS = np.array([-0.0707, -0.0661, 0.0])
"""Midpoint of the hip joint centres in OpenSim's pelvis frame, m, for a 1.80 m subject
(gait2392/gait2354 generic model: ``hip_r`` at (-0.0707, -0.0661, ±0.0835)); scaled by height."""
GENERIC_HEIGHT = 1.80

_COORD_TO_DOF = {v: k for k, v in OPENSIM_COORDINATES.items()}


@dataclass(frozen=True)
class MeasuredKinematics:
    """Measured angles on ``time`` (s): walk3d DoF name -> radians (walk3d signs)."""

    time: np.ndarray
    angles: dict[str, np.ndarray]
    pelvis_angles: np.ndarray | None = None
    """(N, 3) OpenSim pelvis tilt, list, rotation, rad."""
    pelvis_origin: np.ndarray | None = None
    """(N, 3) OpenSim pelvis_tx, ty, tz, m."""
    knee_sign: float = 1.0


def detect_knee_sign(knee: np.ndarray) -> float:
    """``+1`` if a knee-angle series is positive in flexion, ``-1`` if negative (see
    :mod:`walk3d.validation.reference`)."""
    k = np.asarray(knee, dtype=float)
    k = k[np.isfinite(k)]
    if k.size == 0:
        raise ValueError("no finite knee angles to detect the knee sign from")
    return 1.0 if abs(float(k.max())) >= abs(float(k.min())) else -1.0


def kinematics_from_storage(ik: Storage, knee_sign: float | str = "auto") -> MeasuredKinematics:
    """Angles of an IK storage (OpenSim names; degrees unless ``inDegrees=no``)."""
    to_rad = 1.0 if ik.in_degrees is False else np.pi / 180.0
    if knee_sign == "auto":
        knees = [ik.column(c) for c in ("knee_angle_r", "knee_angle_l") if ik.has_column(c)]
        knee_sign = detect_knee_sign(np.concatenate(knees)) if knees else 1.0
    angles = {}
    for col in ik.columns:
        dof = _COORD_TO_DOF.get(col)
        if dof is None:
            continue
        sign = float(knee_sign) if col.startswith("knee_angle") else 1.0
        angles[dof] = sign * to_rad * ik.column(col)
    pelvis = [c for c in ("pelvis_tilt", "pelvis_list", "pelvis_rotation") if ik.has_column(c)]
    p_ang = np.column_stack([to_rad * ik.column(c) for c in pelvis]) if len(pelvis) == 3 else None
    trans = [c for c in ("pelvis_tx", "pelvis_ty", "pelvis_tz") if ik.has_column(c)]
    p_org = np.column_stack([ik.column(c) for c in trans]) if len(trans) == 3 else None
    return MeasuredKinematics(ik.time.copy(), angles, p_ang, p_org, float(knee_sign))


def kinematics_from_table(
    table: CycleTable, period: float, knee_sign: float | str = "auto"
) -> MeasuredKinematics:
    """Right-side angles of a cycle table (``<coordinate>[_r]_deg`` or ``_rad`` columns, OpenSim
    names) on ``time = percent / 100 * period``: 0 is the right heel strike. Limb coordinates
    are the right side's; pelvis and lumbar columns are midline."""
    scale = {"deg": np.pi / 180.0, "rad": 1.0}

    def find(coord: str) -> np.ndarray | None:
        for name in (coord, f"{coord}_r"):
            for unit, factor in scale.items():
                if f"{name}_{unit}" in table.names:
                    return factor * table.column(f"{name}_{unit}")[0]
        return None

    knee = find("knee_angle")
    if knee_sign == "auto":
        knee_sign = detect_knee_sign(knee) if knee is not None else 1.0
    angles = {}
    for coord, dof in _COORD_TO_DOF.items():
        if coord.endswith("_l"):
            continue
        base = coord[:-2] if coord.endswith("_r") else coord
        value = find(base)
        if value is not None:
            angles[dof] = value * (float(knee_sign) if base == "knee_angle" else 1.0)
    pelvis = [find(c) for c in ("pelvis_tilt", "pelvis_list", "pelvis_rotation")]
    p_ang = None if any(v is None for v in pelvis) else np.column_stack(pelvis)
    time = np.asarray(table.percent, float) / 100.0 * period
    origin = None if p_ang is None else np.zeros((time.size, 3))
    return MeasuredKinematics(time, angles, p_ang, origin, float(knee_sign))


def zxy_quaternion(about_z, about_x, about_y) -> np.ndarray:
    """``(N, 4)`` quaternions of ``R = Rz(a) Rx(b) Ry(c)`` (rad; inverse of ``zxy_angles``)."""
    qz = qt.from_axis_angle(np.array([0.0, 0.0, 1.0]), np.asarray(about_z, float))
    qx = qt.from_axis_angle(np.array([1.0, 0.0, 0.0]), np.asarray(about_x, float))
    qy = qt.from_axis_angle(np.array([0.0, 1.0, 0.0]), np.asarray(about_y, float))
    return qt.multiply(qt.multiply(qz, qx), qy)


def joint_coordinates(
    body: BodyModel, angles: Mapping[str, np.ndarray], n: int
) -> dict[str, np.ndarray]:
    """walk3d coordinates (quaternion elements) of every DoF in ``angles``.

    A ball joint needs its three angles; a missing hinge or ankle angle is left out.
    """
    out: dict[str, np.ndarray] = {}
    for joint in body.joints:
        names = joint.dof_names
        if joint.kind == "ball":
            if not all(d in angles for d in names):
                continue
            add, rot, flex = (np.broadcast_to(angles[d], (n,)) for d in names)
            q = zxy_quaternion(flex, add, rot)
            q = q * np.sign(q[:, :1] + (q[:, :1] == 0))
            for k, d in enumerate(names):
                out[d] = q[:, 1 + k]
        else:
            for d in names:
                if d in angles:
                    out[d] = np.sin(np.broadcast_to(angles[d], (n,)) / 2.0)
    return out


def segment_poses(body: BodyModel, kin: MeasuredKinematics) -> Pose:
    """walk3d forward kinematics (positions only) from the measured pelvis pose.

    DoFs absent from ``kin`` are held at zero. Needs ``pelvis_angles`` and ``pelvis_origin``.
    """
    if kin.pelvis_angles is None or kin.pelvis_origin is None:
        raise ValueError("segment poses need the pelvis angles and position")
    n = kin.time.size
    coords = joint_coordinates(body, kin.angles, n)
    zero = np.zeros(n)
    dof = [(coords.get(d, zero), zero, zero) for d in body.dof_names]
    jq = joint_quaternions(body, dof)
    qp = zxy_quaternion(*kin.pelvis_angles.T)
    offset = PELVIS_TO_HIPS * (body.height / GENERIC_HEIGHT)
    origin = kin.pelvis_origin + qt.rotate(qp, np.broadcast_to(offset, (n, 3)))
    q_triple = (tuple(qp.T), (zero,) * 4, (zero,) * 4)
    p_triple = (tuple(origin.T), (zero,) * 3, (zero,) * 3)
    return forward(body, jq, 0, q_triple, p_triple)


def foot_pitch(body: BodyModel, kin: MeasuredKinematics, side: str) -> np.ndarray:
    """Global sagittal rotation of a foot (rad, toes up positive): the about-z angle of the
    foot's Z-X-Y decomposition, from the measured pelvis orientation and leg angles."""
    from walk3d.results.angles import zxy_angles

    pose = segment_poses(body, kin)
    q = stack_q(pose.orientation[body.segment_index(f"foot_{side[0]}")][0])
    return zxy_angles(q)[:, 0]


def ankle_positions(body: BodyModel, kin: MeasuredKinematics, side: str) -> np.ndarray:
    """(N, 3) global ankle joint centre of one foot from :func:`segment_poses`, m."""
    pose = segment_poses(body, kin)
    return stack_v(pose.origin[body.segment_index(f"foot_{side[0]}")][0])
