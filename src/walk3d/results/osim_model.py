"""The OpenSim model of walk3d's own skeleton, as a plain description (no OpenSim needed).

:func:`osim_model` turns a :class:`walk3d.body.model.BodyModel` into an :class:`OsimModel`:
13 bodies with walk3d's segment masses, centres of mass and principal inertias, 13 joints
(``ground_pelvis`` plus walk3d's 12) with walk3d's joint centres and axes, and the 30
coordinates :func:`walk3d.results.opensim.write_motion` writes. :mod:`walk3d.io.osim` writes
it as ``model.osim``.

Frames. Every body frame is walk3d's segment frame: origin at the proximal joint centre, the
pelvis's midway between the hip joint centres, axes along the global ones in upright standing.
So ``motion.mot``'s ``pelvis_tx/ty/tz`` (walk3d's pelvis origin) is this model's pelvis origin.

Joints are OpenSim ``CustomJoint`` s whose rotations are body-fixed (each axis turns with the
rotations before it), matching how ``motion.mot``'s angles are computed
(:mod:`walk3d.results.angles`):

* ``ground_pelvis``: ``pelvis_tilt`` (z), ``pelvis_list`` (x), ``pelvis_rotation`` (y), then
  ``pelvis_tx/ty/tz`` along the ground axes;
* ball joints (``back``, ``acromial_*``, ``hip_*``): flexion/extension about z, then
  adduction/bending about x, then axial rotation about y, R = Rz Rx Ry; the left side's x and y
  axes are negated (the mirror image), as in Rajagopal et al. (2016);
* hinges (``neck``, ``elbow_*``, ``knee_*``): one rotation about walk3d's hinge axis;
* the universal ankle (``ankle_*``): ``ankle_angle`` about the talocrural axis fixed in the
  tibia, then ``subtalar_angle`` about the subtalar axis fixed in the foot, R = R1 R2, which
  is walk3d's joint quaternion ``q1 ⊗ q2``; the third rotation is held at zero.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from walk3d.body.model import MIRROR_POINT, BodyModel, Joint
from walk3d.constants import G
from walk3d.problem.settings import PredictionSettings, body_for
from walk3d.results.opensim import OPENSIM_COORDINATES, motion_table

__all__ = [
    "BODY_NAMES",
    "JOINT_NAMES",
    "RANGE_MARGIN_DEG",
    "OsimBody",
    "OsimCoordinate",
    "OsimJoint",
    "OsimModel",
    "motion_extent",
    "osim_model",
    "prediction_body",
]

BODY_NAMES = {
    "pelvis": "pelvis", "torso": "torso", "head": "head",
    "upper_arm_r": "humerus_r", "forearm_r": "forearm_r",
    "upper_arm_l": "humerus_l", "forearm_l": "forearm_l",
    "thigh_r": "femur_r", "shank_r": "tibia_r", "foot_r": "calcn_r",
    "thigh_l": "femur_l", "shank_l": "tibia_l", "foot_l": "calcn_l",
}  # fmt: skip
"""walk3d segment -> OpenSim body (Rajagopal et al. 2016 names where a body matches; the
forearm carries the hand, the foot the talus; ``grf.xml`` applies the ground reactions to
``calcn_r``/``calcn_l``)."""

JOINT_NAMES = {
    "waist": "back", "neck": "neck", "shoulder_r": "acromial_r", "elbow_r": "elbow_r",
    "shoulder_l": "acromial_l", "elbow_l": "elbow_l", "hip_r": "hip_r", "knee_r": "knee_r",
    "ankle_r": "ankle_r", "hip_l": "hip_l", "knee_l": "knee_l", "ankle_l": "ankle_l",
}  # fmt: skip
"""walk3d joint -> OpenSim joint name."""


RANGE_MARGIN_DEG = 5.0
"""Each coordinate's range is walk3d's anatomical range widened by this much at both ends:
walk3d bounds its quaternion coordinates at the solver's nodes, while ``motion.mot`` holds
Euler angles sampled between the nodes too (e.g. an elbow at -0.75°)."""

_PELVIS_RANGES = {
    "pelvis_tilt": (-90.0, 90.0), "pelvis_list": (-90.0, 90.0),
    "pelvis_rotation": (-90.0, 90.0),
}  # fmt: skip
_PELVIS_TRANSLATION_RANGES = {"pelvis_tx": (-10.0, 10.0), "pelvis_ty": (-1.0, 3.0),
                              "pelvis_tz": (-5.0, 5.0)}  # fmt: skip


@dataclass(frozen=True)
class OsimCoordinate:
    name: str
    axis: tuple[float, float, float]
    """Rotation (or translation) axis: in the parent frame for the first rotation, then
    body-fixed (turned by the rotations before it); translations along the parent axes."""
    kind: str
    """``rotation`` or ``translation``."""
    range: tuple[float, float]
    """rad or m."""
    default: float = 0.0


@dataclass(frozen=True)
class OsimBody:
    name: str
    mass: float
    com: tuple[float, float, float]
    inertia: tuple[float, float, float]
    """Principal moments about the centre of mass, along the body axes, kg m²."""
    shape_centre: tuple[float, float, float]
    """Centre of the ellipsoid drawn for the body, body frame, m (display only)."""
    shape_radii: tuple[float, float, float]


@dataclass(frozen=True)
class OsimJoint:
    name: str
    parent: str
    """``ground`` or a body name."""
    child: str
    location: tuple[float, float, float]
    """Joint centre in the parent frame (the child frame sits at the child body's origin)."""
    rotations: tuple[OsimCoordinate, ...]
    """1 to 3 rotations, body-fixed, in order."""
    translations: tuple[OsimCoordinate, ...] = ()


@dataclass(frozen=True)
class OsimModel:
    name: str
    gravity: tuple[float, float, float]
    bodies: tuple[OsimBody, ...]
    joints: tuple[OsimJoint, ...]

    @property
    def coordinates(self) -> tuple[OsimCoordinate, ...]:
        return tuple(c for j in self.joints for c in (*j.rotations, *j.translations))

    @property
    def mass(self) -> float:
        return float(sum(b.mass for b in self.bodies))


def _vec(v) -> tuple[float, float, float]:
    a = np.asarray(v, dtype=float)
    return (float(a[0]), float(a[1]), float(a[2]))


def _range(joint: Joint, k: int, extent: dict[str, tuple[float, float]], name: str):
    lo, hi = (float(v) for v in joint.range[k])
    margin = np.radians(RANGE_MARGIN_DEG)
    lo, hi = lo - margin, hi + margin
    if name in extent:
        lo, hi = min(lo, extent[name][0]), max(hi, extent[name][1])
    return (lo, hi)


def _rotations(joint: Joint, extent: dict[str, tuple[float, float]]):
    names = [OPENSIM_COORDINATES.get(n, n) for n in joint.dof_names]
    if joint.kind == "ball":
        # slots (x, y, z) = (adduction, rotation, flexion); OpenSim order z, x, y
        return tuple(
            OsimCoordinate(names[k], _vec(joint.axes[k]), "rotation",
                           _range(joint, k, extent, names[k]))
            for k in (2, 0, 1)
        )  # fmt: skip
    axes = [joint.axis] if joint.kind == "hinge" else [joint.axis, joint.axis2]
    return tuple(
        OsimCoordinate(names[k], _vec(axes[k]), "rotation", _range(joint, k, extent, names[k]))
        for k in range(joint.n_dof)
    )


def _shape(body: BodyModel, i: int) -> tuple[tuple, tuple]:
    """An ellipsoid from the segment's origin to its far end (display only)."""
    seg = body.segments[i]
    name = seg.name
    side = -1.0 if name.endswith("_l") else 1.0
    if name.startswith("foot"):
        heel, toe = body.foot.heel, body.foot.toe
        centre = 0.5 * (heel + toe) * np.array([1.0, 0.5, 1.0])
        radii = (0.5 * body.foot.length, 0.5 * body.foot.ankle_height, 0.2 * body.foot.length)
        return _vec(centre * (MIRROR_POINT if side < 0 else 1.0)), _vec(radii)
    children = [j for j in body.joints if j.parent == i]
    if name == "torso":
        end = np.array(next(j.offset for j in children if j.name == "neck"))
    elif children:
        end = np.array(children[0].offset)
    else:  # head up, forearm (with hand) down
        end = np.array([0.0, seg.length if name == "head" else -seg.length, 0.0])
    width = {"pelvis": 0.9, "torso": 0.6, "head": 0.35}.get(name, 0.14)
    depth = {"pelvis": 0.5, "torso": 0.4, "head": 0.4}.get(name, 0.14)
    half = 0.5 * abs(end[1])
    return _vec(0.5 * end), _vec((depth * seg.length, half, width * seg.length))


def osim_model(
    body: BodyModel,
    extent: dict[str, tuple[float, float]] | None = None,
    name: str = "walk3d",
) -> OsimModel:
    """The OpenSim description of ``body`` (see the module doc).

    Args:
        body: The subject's body model.
        extent: Optional ``{coordinate: (min, max)}`` of a motion (rad, m) that the ranges
            must contain; each range is walk3d's anatomical range widened by
            :data:`RANGE_MARGIN_DEG`, then by as much as ``extent`` needs.
        name: The model's name.
    """
    extent = {} if extent is None else dict(extent)
    bodies = []
    for i, seg in enumerate(body.segments):
        centre, radii = _shape(body, i)
        bodies.append(
            OsimBody(
                BODY_NAMES[seg.name],
                float(seg.mass),
                _vec(seg.com),
                _vec(seg.inertia),
                centre,
                radii,
            )  # fmt: skip
        )
    pelvis_rot = []
    for cname, axis in zip(_PELVIS_RANGES, ((0, 0, 1), (1, 0, 0), (0, 1, 0)), strict=True):
        lo, hi = np.radians(_PELVIS_RANGES[cname])
        if cname in extent:
            lo, hi = min(lo, extent[cname][0]), max(hi, extent[cname][1])
        pelvis_rot.append(OsimCoordinate(cname, _vec(axis), "rotation", (float(lo), float(hi))))
    leg = (
        body.joints[body.joint_index("knee_r")].offset[1]
        + body.joints[body.joint_index("ankle_r")].offset[1]
    )
    standing = {"pelvis_ty": float(body.foot.ankle_height - leg)}
    pelvis_tr = []
    for cname, axis in zip(_PELVIS_TRANSLATION_RANGES, np.eye(3), strict=True):
        lo, hi = _PELVIS_TRANSLATION_RANGES[cname]
        if cname in extent:
            lo, hi = min(lo, extent[cname][0]), max(hi, extent[cname][1])
        pelvis_tr.append(
            OsimCoordinate(
                cname, _vec(axis), "translation", (float(lo), float(hi)), standing.get(cname, 0.0)
            )  # fmt: skip
        )
    joints = [
        OsimJoint(
            "ground_pelvis",
            "ground",
            "pelvis",
            (0.0, 0.0, 0.0),
            tuple(pelvis_rot),
            tuple(pelvis_tr),
        )  # fmt: skip
    ]
    for joint in body.joints:
        joints.append(
            OsimJoint(
                JOINT_NAMES[joint.name],
                BODY_NAMES[body.segments[joint.parent].name],
                BODY_NAMES[body.segments[joint.child].name],
                _vec(joint.offset),
                _rotations(joint, extent),
            )
        )
    return OsimModel(name, (0.0, -G, 0.0), tuple(bodies), tuple(joints))


def prediction_body(pred: Any) -> BodyModel:
    """The body model a prediction was evaluated with.

    :func:`walk3d.problem.settings.body_for` of ``pred.summary["settings"]`` (the defaults,
    the paper's subject, where absent).

    Raises:
        ValueError: the prediction's segment masses are not that body's.
    """
    recorded = pred.summary.get("settings") or {}
    gait, model = recorded.get("gait") or {}, recorded.get("model") or {}
    body = body_for(PredictionSettings(  # only what shapes the body: other settings may be old
        gait={k: gait[k] for k in ("mass", "height", "sex") if k in gait},
        model={k: model[k] for k in ("rollover_s", "rollover_ankle", "changes") if k in model},
    ))  # fmt: skip
    masses = np.array([s.mass for s in body.segments])
    if masses.shape != pred.segment_mass.shape or not np.allclose(
        masses, pred.segment_mass, rtol=1e-9, atol=0.0
    ):
        raise ValueError("the prediction's segment masses are not those of its body model")
    return body


def motion_extent(pred: Any) -> dict[str, tuple[float, float]]:
    """``{coordinate: (min, max)}`` of ``motion.mot``'s coordinates (rad, m)."""
    columns, data = motion_table(pred)
    return {c: (float(np.min(data[:, k])), float(np.max(data[:, k])))
            for k, c in enumerate(columns)}  # fmt: skip
