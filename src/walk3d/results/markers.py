"""Virtual markers of the Plug-in Gait full-body set on walk3d's 13 segments.

:func:`marker_set` places each marker in its segment's frame (origin at the proximal joint
centre, axes along the global ones in upright standing: x forward, y up, z right) from the
subject's joint centres and segment lengths, so it scales with the subject. Right-side
markers are given; the left ones are their mirror images (z -> -z), except ``RBAK``.
Positions are those of marker centres on the skin (no marker radius, no wands).
:func:`marker_positions` follows them over a prediction (``pred``: a
:class:`walk3d.results.prediction.PredictedCycle`, not imported, as that module writes them).

Where walk3d has no anatomy (it is a stick model), a marker goes where a Plug-in Gait model
would rebuild walk3d's own joint centres and axes from it: HJC, THI and KNE lie in the thigh's
frontal plane, ASIS and PSIS at one height, HEE and TOE at one height above the sole, so that
marker-based segment frames coincide with walk3d's in upright standing. The rules
(``IAD``: inter-ASIS distance; ``d``: chest depth) are:

* pelvis: ``IAD`` = hip-centre distance / 0.72, after Bell et al. (1990), whose hip centre
  lies 36 % of ``IAD`` lateral, 30 % below and 19 % behind the mid-ASIS point; so ``ASIS`` at
  ``(0.19, 0.30, 0.5) IAD`` from the hip midpoint, ``PSIS`` at the same height, 0.7 ``IAD``
  behind the ASIS and 0.2 ``IAD`` lateral;
* thigh: ``KNE`` half the knee width (0.24 thigh lengths) lateral of the knee centre, ``THI``
  above it at two thirds of the thigh; shank: ``ANK`` half the ankle width (0.27 foot
  lengths) lateral of the ankle centre, ``TIB`` above it at two thirds of the shank;
* foot: ``TOE`` over the second metatarsal head (midway between walk3d's first and fifth
  metatarsal heads), ``HEE`` at the back of the heel, both 0.4 ankle heights above the sole;
* torso (``d`` = 0.6 shoulder-centre distance): ``C7`` 0.3 ``d`` behind the neck centre,
  ``CLAV`` (jugular notch) 0.3 ``d`` in front of it and half the shoulder drop lower, ``STRN``
  (xiphoid) and ``T10`` on the front and back at the xiphoid level, ``RBAK`` on the back
  midway between the spine and the right shoulder, midway between shoulder and xiphoid
  heights, ``SHO`` 0.15 upper-arm lengths above the shoulder centre;
* arm: ``ELB`` half the elbow width (0.25 upper-arm lengths) lateral of the elbow centre,
  ``UPA`` halfway up above it; forearm (palms facing the thighs): ``WRA`` (thumb side) and
  ``WRB`` (little-finger side) half the wrist width (0.2 forearm lengths) in front of and
  behind the wrist, ``FRM`` halfway up on the back of the forearm, ``FIN`` at the end of the
  hand (the third metacarpal head), 0.2 hand lengths out on its back;
* head (``h``: neck centre to vertex): ``FHD`` and ``BHD`` 0.64 ``h`` above the neck centre,
  0.35 ``h`` in front and behind, 0.25 ``h`` lateral.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from walk3d.body.anthropometry import scaled_de_leva
from walk3d.body.model import MIRROR_POINT, BodyModel
from walk3d.kinematics import quaternion

__all__ = ["MARKER_LABELS", "Marker", "marker_positions", "marker_set"]

MARKER_LABELS = (
    "LFHD", "RFHD", "LBHD", "RBHD", "C7", "T10", "CLAV", "STRN", "RBAK",
    "LSHO", "LUPA", "LELB", "LFRM", "LWRA", "LWRB", "LFIN",
    "RSHO", "RUPA", "RELB", "RFRM", "RWRA", "RWRB", "RFIN",
    "LASI", "RASI", "LPSI", "RPSI",
    "LTHI", "LKNE", "LTIB", "LANK", "LHEE", "LTOE",
    "RTHI", "RKNE", "RTIB", "RANK", "RHEE", "RTOE",
)  # fmt: skip
"""The markers, in Plug-in Gait's usual order."""


@dataclass(frozen=True)
class Marker:
    """A marker fixed to ``segment``, at ``position`` (3,) m in the segment frame."""

    label: str
    segment: str
    position: np.ndarray


def _right_side(body: BodyModel) -> dict[str, tuple[str, np.ndarray]]:
    """Right-side and middle markers (``label`` without side letter -> segment base, position)."""
    joints = {j.name: j for j in body.joints}
    seg = {s.name: s for s in body.segments}
    hip = joints["hip_r"].offset
    shoulder = joints["shoulder_r"].offset
    neck_y = float(joints["neck"].offset[1])
    iad = 2.0 * float(hip[2]) / 0.72
    thigh, shank = seg["thigh_r"].length, seg["shank_r"].length
    knee_w, ankle_w = 0.24 * thigh, 0.27 * body.foot.length
    sole = -body.foot.ankle_height
    metatarsal = 0.5 * (body.foot.met1 + body.foot.met5)
    marker_h = sole + 0.4 * body.foot.ankle_height
    d = 0.6 * 2.0 * float(shoulder[2])
    drop = neck_y - float(shoulder[1])
    de_leva = scaled_de_leva(body.mass, body.height, body.sex)
    xiphoid = de_leva["middle_trunk"].length  # above the torso origin (omphalion)
    upper_arm = seg["upper_arm_r"].length
    fa, hand = de_leva["forearm"].length, de_leva["hand"].length
    scale = seg["forearm_r"].length / (fa + hand)  # the segment carries the hand
    forearm, hand = fa * scale, hand * scale
    elbow_w, wrist_w = 0.25 * upper_arm, 0.2 * forearm
    h = seg["head"].length

    def at(*xyz: float) -> np.ndarray:
        return np.array(xyz, dtype=float)

    return {
        "FHD": ("head", at(0.35 * h, 0.64 * h, 0.25 * h)),
        "BHD": ("head", at(-0.35 * h, 0.64 * h, 0.25 * h)),
        "C7": ("torso", at(-0.3 * d, neck_y, 0.0)),
        "T10": ("torso", at(-0.5 * d, xiphoid, 0.0)),
        "CLAV": ("torso", at(0.3 * d, neck_y - 0.5 * drop, 0.0)),
        "STRN": ("torso", at(0.5 * d, xiphoid, 0.0)),
        "RBAK": ("torso", at(-0.5 * d, 0.5 * (shoulder[1] + xiphoid), 0.5 * shoulder[2])),
        "SHO": ("torso", shoulder + at(0.0, 0.15 * upper_arm, 0.0)),
        "UPA": ("upper_arm", at(0.0, -0.5 * upper_arm, 0.5 * elbow_w)),
        "ELB": ("upper_arm", at(0.0, -upper_arm, 0.5 * elbow_w)),
        "FRM": ("forearm", at(0.0, -0.5 * forearm, 0.5 * wrist_w)),
        "WRA": ("forearm", at(0.5 * wrist_w, -forearm, 0.0)),
        "WRB": ("forearm", at(-0.5 * wrist_w, -forearm, 0.0)),
        "FIN": ("forearm", at(0.0, -forearm - hand, 0.2 * hand)),
        "ASI": ("pelvis", at(0.19, 0.30, 0.5) * iad),
        "PSI": ("pelvis", at(0.19 - 0.7, 0.30, 0.2) * iad),
        "THI": ("thigh", at(0.0, -2.0 / 3.0 * thigh, 0.5 * knee_w)),
        "KNE": ("thigh", at(0.0, -thigh, 0.5 * knee_w)),
        "TIB": ("shank", at(0.0, -2.0 / 3.0 * shank, 0.5 * ankle_w)),
        "ANK": ("shank", at(0.0, -shank, 0.5 * ankle_w)),
        "HEE": ("foot", at(body.foot.heel[0], marker_h, body.foot.heel[2])),
        "TOE": ("foot", at(metatarsal[0], marker_h, metatarsal[2])),
    }


def marker_set(body: BodyModel) -> tuple[Marker, ...]:
    """The markers of :data:`MARKER_LABELS` on ``body`` (module doc for the rules)."""
    right = _right_side(body)
    out = []
    for label in MARKER_LABELS:
        if label in right:  # middle markers and RBAK
            base, pos = right[label]
            out.append(Marker(label, base, pos))
            continue
        side, name = label[0], label[1:]
        base, pos = right[name]
        segment = base if base in ("pelvis", "torso", "head") else f"{base}_{side.lower()}"
        out.append(Marker(label, segment, pos * (MIRROR_POINT if side == "L" else 1.0)))
    return tuple(out)


def marker_positions(
    pred: Any, body: BodyModel, markers: Sequence[Marker] | None = None
) -> np.ndarray:
    """``(N, M, 3)`` global positions (m) of ``markers`` (default :func:`marker_set`) at the
    prediction's samples, from each segment's centre of mass and orientation."""
    markers = marker_set(body) if markers is None else markers
    names = body.segment_names
    index = np.array([names.index(m.segment) for m in markers])
    local = np.array([m.position for m in markers])
    com = np.array([body.segments[i].com for i in index])
    rot = quaternion.to_matrix(pred.segment_orientation[:, index])  # (N, M, 3, 3)
    return pred.segment_com_position[:, index] + np.einsum("nmij,mj->nmi", rot, local - com)
