"""Anatomical angles from quaternions, in OpenSim's body-fixed Z-X-Y convention.

OpenSim's ball-like joints (Rajagopal et al. 2016: hip, lumbar, shoulder, ground-pelvis) rotate
the child first about the parent's z axis (flexion/extension, pelvis tilt), then about the new x
axis (adduction, bending, pelvis list) and last about the new y axis (axial rotation, pelvis
rotation), so that

    R = Rz(flexion) @ Rx(adduction) @ Ry(rotation).

walk3d reports ball joints in slot order (x, y, z) = (adduction, rotation, flexion), the order of
:attr:`walk3d.body.model.Joint.axes`. OpenSim's left joints have their x and y axes negated, the
mirror image of the right joints; :func:`ball_joint_angles` therefore mirrors a left quaternion
through the sagittal plane first, so equal angles on both sides mean mirror-image postures (the
same anatomical signs). All angles are in radians.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from walk3d.kinematics import quaternion

__all__ = ["ball_joint_angles", "pelvis_angles", "zxy_angles"]


def _as_quaternions(q: ArrayLike) -> np.ndarray:
    arr = np.asarray(q, dtype=float)
    if arr.ndim != 2 or arr.shape[1] != 4:
        raise ValueError(f"quaternions must have shape (N, 4), got {arr.shape}")
    norm = np.linalg.norm(arr, axis=1, keepdims=True)
    if not np.all(np.isfinite(norm)) or np.any(norm < 1e-9):
        raise ValueError("quaternions must be finite and non-zero")
    return arr / norm


def zxy_angles(q: ArrayLike) -> np.ndarray:
    """Body-fixed Z-X-Y angles ``(N, 3)`` ``[about z, about x, about y]`` of ``(N, 4)`` rotations.

    The rotation matrix of each (scalar-first, normalised here) quaternion is
    ``Rz(a) @ Rx(b) @ Ry(c)`` with ``a, c`` in ``(-pi, pi]`` and ``b`` in ``[-pi/2, pi/2]``
    (the usual principal ranges; ``b = ±pi/2`` is the gimbal lock, where ``a`` and ``c`` are
    not unique).
    """
    r = quaternion.to_matrix(_as_quaternions(q))
    # R[2, :] = [-cos b sin c, sin b, cos b cos c]; R[:, 1] = [-sin a cos b, cos a cos b, sin b]
    about_x = np.arcsin(np.clip(r[:, 2, 1], -1.0, 1.0))
    about_z = np.arctan2(-r[:, 0, 1], r[:, 1, 1])
    about_y = np.arctan2(-r[:, 2, 0], r[:, 2, 2])
    return np.column_stack([about_z, about_x, about_y])


def ball_joint_angles(q: ArrayLike, side: str | None = "r") -> np.ndarray:
    """OpenSim angles ``(N, 3)`` of a ball joint, in walk3d slot order (x, y, z).

    Args:
        q: ``(N, 4)`` scalar-first joint quaternions mapping the child frame to the parent
            frame (expressed in the parent frame).
        side: ``"r"`` (or ``None`` for midline joints such as the waist) uses the quaternion as
            is; ``"l"`` mirrors it first (``[w, x, y, z] -> [w, -x, -y, z]``), matching
            OpenSim's left joints whose x and y axes are negated.

    Returns:
        Columns ``[adduction, axial rotation, flexion]`` in radians (for the waist:
        ``[bending, rotation, extension]``), from the Z-X-Y decomposition
        ``R = Rz(flexion) Rx(adduction) Ry(rotation)``.
    """
    if side not in ("r", "l", None):
        raise ValueError(f"side must be 'r', 'l' or None, got {side!r}")
    quats = _as_quaternions(q)
    if side == "l":
        quats = quaternion.mirror(quats)
    zxy = zxy_angles(quats)
    return zxy[:, [1, 2, 0]]


def pelvis_angles(q: ArrayLike) -> np.ndarray:
    """OpenSim pelvis angles ``(N, 3)`` ``[pelvis_tilt, pelvis_list, pelvis_rotation]``, rad.

    ``q`` is the ``(N, 4)`` scalar-first pelvis orientation (pelvis frame -> global). Tilt is
    about z (positive: posterior tilt, the pelvis's y axis leaning back), list about x and
    rotation about y, from the same body-fixed Z-X-Y decomposition OpenSim's ground-pelvis
    joint uses.
    """
    return zxy_angles(q)
