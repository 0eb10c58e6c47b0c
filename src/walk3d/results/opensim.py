"""OpenSim motion (``.mot``) and ground-reaction files of a walk3d prediction.

:func:`write_motion` writes the pelvis's six coordinates and every DoF under OpenSim
Rajagopal et al. (2016) coordinate names (:data:`OPENSIM_COORDINATES`), angles in degrees
(``inDegrees=yes``) and translations in metres. :func:`write_grf` writes the two feet's ground
reactions with :func:`walk3d.io.external_loads.write_grf_storage` and the matching
ExternalLoads XML.

``pred`` is a :class:`walk3d.results.prediction.PredictedCycle`; it is not imported here, because
:func:`walk3d.results.prediction.save_prediction` writes these files (no import cycle).
"""

from __future__ import annotations

from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np

from walk3d.io.external_loads import write_external_loads_xml, write_grf_storage
from walk3d.io.storage import write_storage
from walk3d.results.angles import pelvis_angles

__all__ = [
    "OPENSIM_COORDINATES",
    "PELVIS_COORDINATES",
    "motion_columns",
    "motion_table",
    "write_grf",
    "write_motion",
]

PELVIS_COORDINATES = (
    "pelvis_tilt", "pelvis_list", "pelvis_rotation", "pelvis_tx", "pelvis_ty", "pelvis_tz",
)  # fmt: skip
"""The ground-pelvis coordinates written first (angles from the pelvis orientation's body-fixed
Z-X-Y decomposition, see :func:`walk3d.results.angles.pelvis_angles`; translations are the
pelvis frame origin, midway between the hip joint centres: the pelvis origin of the folder's
``model.osim``, not of the Rajagopal model, whose origin lies about 6 cm ahead of and 8 cm above
its hip centres' midpoint; docs/opensim.md)."""


def _both_sides(pairs: dict[str, str]) -> dict[str, str]:
    out = {}
    for side in ("r", "l"):
        out.update({f"{k}_{side}": f"{v}_{side}" for k, v in pairs.items()})
    return out


OPENSIM_COORDINATES: dict[str, str] = {
    "lumbar_bending": "lumbar_bending",
    "lumbar_rotation": "lumbar_rotation",
    "lumbar_extension": "lumbar_extension",
    "neck_flexion": "neck_flexion",
    **_both_sides(
        {
            "arm_add": "arm_add",
            "arm_rot": "arm_rot",
            "arm_flex": "arm_flex",
            "elbow_flex": "elbow_flex",
            "hip_adduction": "hip_adduction",
            "hip_rotation": "hip_rotation",
            "hip_flexion": "hip_flexion",
            "knee_flexion": "knee_angle",
            "ankle_dorsiflexion": "ankle_angle",
            "subtalar_inversion": "subtalar_angle",
        }
    ),
}
"""walk3d DoF name -> OpenSim Rajagopal et al. (2016) coordinate name.

Every mapped coordinate has the same sign as its walk3d DoF, no sign flips:

* lumbar_extension (+ extension), lumbar_bending (+ bending to the right), lumbar_rotation
  (+ rotation to the left), from the Z-X-Y decomposition OpenSim's back joint uses;
* hip_flexion (+ flexion), hip_adduction (+ adduction), hip_rotation (+ internal rotation);
  likewise arm_flex, arm_add, arm_rot (+ internal rotation) at the shoulder;
* knee_flexion -> knee_angle (+ flexion; Rajagopal's knee, unlike gait2392's, is positive in
  flexion); ankle_dorsiflexion -> ankle_angle (+ dorsiflexion); subtalar_inversion ->
  subtalar_angle (+ inversion); elbow_flex (+ flexion, but about walk3d's arm26-style axis,
  which differs from Rajagopal's elbow axis);
* left coordinates carry the same anatomical signs as the right ones (OpenSim's left joint
  axes are mirrored, as walk3d's are).

``neck_flexion`` (+ flexion) has no Rajagopal counterpart (its torso and head are one body)
and keeps its walk3d name. Rajagopal coordinates walk3d lacks (``pro_sup``, ``wrist_*``,
``mtp_angle``) are not written; OpenSim holds them at their defaults.
"""


def motion_columns(dof_names: tuple[str, ...] | list[str]) -> tuple[str, ...]:
    """Data column labels of :func:`write_motion` for these DoF (time excluded).

    Unknown DoF names are kept as they are.
    """
    return PELVIS_COORDINATES + tuple(OPENSIM_COORDINATES.get(n, n) for n in dof_names)


def motion_table(pred: Any) -> tuple[tuple[str, ...], np.ndarray]:
    """The columns of :func:`write_motion` and their values ``(N, 6 + D)`` in SI units (rad, m).

    The pelvis translation is walk3d's pelvis frame origin, midway between the hip joint
    centres (``pred.pelvis_position``), not the Rajagopal model's pelvis origin.
    """
    pelvis = pelvis_angles(pred.segment_orientation[:, 0, :])
    data = np.hstack([pelvis, pred.pelvis_position, pred.joint_angle])
    return motion_columns(pred.dof_names), data


def write_motion(path: str | PathLike[str], pred: Any, *, name: str = "walk3d") -> Path:
    """Write ``pred`` as an OpenSim coordinates file (``inDegrees=yes``), atomically.

    Columns: ``time`` (= ``pred.time``), :data:`PELVIS_COORDINATES` (angles in degrees,
    translations in m) and one column per DoF in ``pred.dof_names`` order, named by
    :data:`OPENSIM_COORDINATES`, in degrees (:func:`motion_table`).

    Returns:
        The path written.
    """
    columns, data = motion_table(pred)
    angular = np.array([c not in PELVIS_COORDINATES[3:] for c in columns])
    data = np.where(angular, np.degrees(data), data)
    return write_storage(path, pred.time, columns, data, name=name, in_degrees=True)


def write_grf(
    path: str | PathLike[str],
    pred: Any,
    *,
    xml_path: str | PathLike[str] | None = None,
    name: str = "walk3d_grf",
) -> tuple[Path, Path]:
    """Write ``pred``'s ground reactions and the OpenSim ExternalLoads XML, atomically.

    The storage has the columns of :func:`walk3d.io.external_loads.write_grf_storage`
    (``ground_force_r_vx`` ... ``ground_torque_l_z``), forces in N, points in m, torques in
    N m. Where the centre of pressure is undefined (NaN: foot off the ground, zero force) it is
    written as 0, since OpenSim cannot read NaN points.

    Args:
        path: The GRF ``.mot``.
        xml_path: The ExternalLoads XML (default: ``path`` with suffix ``.xml``); its
            ``datafile`` is the GRF file name relative to the XML's folder when both share a
            folder, otherwise the absolute path.

    Returns:
        The paths of the storage and the XML.
    """
    grf = Path(path)
    xml = grf.with_suffix(".xml") if xml_path is None else Path(xml_path)
    cop = np.where(np.isnan(pred.grf_cop), 0.0, pred.grf_cop)
    write_grf_storage(grf, pred.time, pred.grf_force, cop, pred.grf_free_moment, name=name)
    same_folder = grf.resolve().parent == xml.resolve().parent
    datafile = grf.name if same_folder else str(grf.resolve())
    write_external_loads_xml(xml, datafile)
    return grf, xml
