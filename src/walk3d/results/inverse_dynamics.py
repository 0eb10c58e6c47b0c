"""walk3d's joint moments as OpenSim generalized forces (``inverse_dynamics.sto``).

OpenSim's InverseDynamicsTool reports, per coordinate of ``model.osim``, the generalized force
that coordinate needs: ``<coordinate>_moment`` for rotations (N m), ``<coordinate>_force`` for
translations (N). A generalized force is the joint load (parent on child, about the joint
centre) projected on that coordinate's axis as it lies in the current pose: for the body-fixed
Z-X-Y rotations of a ball joint (:mod:`walk3d.results.osim_model`) these are the moment about
the parent's z axis (flexion), about the x axis after the flexion (adduction) and about the
child's y axis (rotation). walk3d reports a ball joint's moment on the parent's x, y, z axes
(``Joint.axes``), so its adduction and rotation columns are converted here; flexion, hinge and
ankle moments are already generalized forces (see :mod:`walk3d.dynamics.newton_euler`).

The pelvis's six generalized forces are written as zero: walk3d's ground reactions are the
whole body's momentum change (paper Eq. 5), so the motion needs no residual load.
"""

from __future__ import annotations

from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np

from walk3d.body.model import BodyModel
from walk3d.io.storage import write_storage
from walk3d.results.opensim import OPENSIM_COORDINATES, PELVIS_COORDINATES

__all__ = ["generalized_force_labels", "generalized_forces", "write_inverse_dynamics"]


def _rotation(axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """(N, 3, 3) rotations by ``angle`` (N,) about the unit ``axis`` (Rodrigues)."""
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    s, c = np.sin(angle)[:, None, None], np.cos(angle)[:, None, None]
    return np.eye(3) + s * k + (1.0 - c) * (k @ k)


def generalized_force_labels(dof_names: tuple[str, ...] | list[str]) -> tuple[str, ...]:
    """Column labels, in the order of :func:`generalized_forces`."""
    pelvis = tuple(f"{c}_{'force' if c.endswith(('tx', 'ty', 'tz')) else 'moment'}"
                   for c in PELVIS_COORDINATES)  # fmt: skip
    return pelvis + tuple(f"{OPENSIM_COORDINATES.get(n, n)}_moment" for n in dof_names)


def generalized_forces(pred: Any, body: BodyModel) -> tuple[tuple[str, ...], np.ndarray]:
    """OpenSim generalized forces ``(labels, (N, 6 + D) values)`` of a prediction.

    Args:
        pred: A :class:`walk3d.results.prediction.PredictedCycle` (joint angles in OpenSim's
            decomposition, joint moments on walk3d's joint axes).
        body: Its body model (joint kinds and axes).
    """
    values: dict[str, np.ndarray] = {}
    angles = {name: pred.joint_angle[:, k] for k, name in enumerate(pred.dof_names)}
    for joint in body.joints:
        moment = pred.joint_moment[:, pred.joint_names.index(joint.name)]
        if joint.kind != "ball":
            values.update({d: moment[:, s] for d, s in zip(joint.dof_names, joint.dof_slots,
                                                           strict=True)})  # fmt: skip
            continue
        m_parent = moment @ joint.axes  # rows of axes are the slot directions
        add, _rot, flex = (angles[name] for name in joint.dof_names)
        e_add, e_rot, e_flex = joint.axes
        r1 = _rotation(e_flex, flex)
        r12 = r1 @ _rotation(e_add, add)
        values[joint.dof_names[0]] = np.einsum("ni,ni->n", m_parent, r1 @ e_add)
        values[joint.dof_names[1]] = np.einsum("ni,ni->n", m_parent, r12 @ e_rot)
        values[joint.dof_names[2]] = m_parent @ e_flex
    data = np.column_stack([np.zeros((pred.n_nodes, 6))] + [values[d] for d in pred.dof_names])
    return generalized_force_labels(pred.dof_names), data


def write_inverse_dynamics(
    path: str | PathLike[str], pred: Any, body: BodyModel, *, name: str = "walk3d_inverse_dynamics"
) -> Path:
    """Write ``inverse_dynamics.sto`` (:func:`generalized_forces`, ``inDegrees=no``), atomically."""
    labels, data = generalized_forces(pred, body)
    return write_storage(path, pred.time, labels, data, name=name, in_degrees=False)
