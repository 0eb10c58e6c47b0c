"""The immutable 13-segment, 12-joint, 24-DoF body model (paper section 2.1).

Every segment frame has its origin at the segment's proximal joint centre (the pelvis: midway
between the hip joint centres) and is aligned with the global frame in upright standing
(x forward, y up, z right). Joint ``j`` connects ``segments[joints[j].parent]`` to
``segments[j + 1]``: the pelvis is segment 0 and the root of the tree.

Orders (used across the whole package):

* segments: pelvis, torso, head, upper_arm_r, forearm_r, upper_arm_l, forearm_l,
  thigh_r, shank_r, foot_r, thigh_l, shank_l, foot_l;
* joints: waist, neck, shoulder_r, elbow_r, shoulder_l, elbow_l, hip_r, knee_r, ankle_r,
  hip_l, knee_l, ankle_l;
* DoF: the joints' DoF in joint order (see :data:`DOF_NAMES`).

Left-side geometry and axes are the mirror images (z -> -z) of the right side; axial vectors
mirror as ``(x, y, z) -> (-x, -y, z)``, so equal DoF values on both sides give mirror-image
postures.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import numpy as np

from walk3d.body.anthropometry import load_parameters, lump, scaled_de_leva
from walk3d.body.rollover import RollOver, arc_rollover

SEGMENT_NAMES = (
    "pelvis", "torso", "head", "upper_arm_r", "forearm_r", "upper_arm_l", "forearm_l",
    "thigh_r", "shank_r", "foot_r", "thigh_l", "shank_l", "foot_l",
)  # fmt: skip
JOINT_NAMES = (
    "waist", "neck", "shoulder_r", "elbow_r", "shoulder_l", "elbow_l",
    "hip_r", "knee_r", "ankle_r", "hip_l", "knee_l", "ankle_l",
)  # fmt: skip
_JOINT_PARENT = {
    "waist": "pelvis", "neck": "torso", "shoulder_r": "torso", "elbow_r": "upper_arm_r",
    "shoulder_l": "torso", "elbow_l": "upper_arm_l", "hip_r": "pelvis", "knee_r": "thigh_r",
    "ankle_r": "shank_r", "hip_l": "pelvis", "knee_l": "thigh_l", "ankle_l": "shank_l",
}  # fmt: skip
MIRROR_AXIAL = np.array([-1.0, -1.0, 1.0])
MIRROR_POINT = np.array([1.0, 1.0, -1.0])


def _ro(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


@dataclass(frozen=True)
class Segment:
    name: str
    mass: float
    com: np.ndarray
    """Centre of mass in the segment frame, m."""
    inertia: np.ndarray
    """Principal moments of inertia about the centre of mass along the frame axes, kg m²."""
    length: float


@dataclass(frozen=True)
class Joint:
    """A joint between ``parent`` and ``child`` segment indices.

    ``kind`` is ``ball`` (3 DoF, quaternion vector part along ``axes``), ``hinge`` (1 DoF about
    ``axis``) or ``universal`` (``axis`` fixed in the parent, then ``axis2`` fixed in the child).
    ``axes`` (3, 3) holds, as rows, the joint's x (frontal), y (transverse) and z (sagittal) axes
    in the parent frame, with the mirror signs on the left side; joint moments are reported on
    them. ``dof_slots`` says which of those rows each DoF acts about.
    """

    name: str
    kind: str
    parent: int
    child: int
    offset: np.ndarray
    """Joint centre in the parent frame, m."""
    axes: np.ndarray
    axis: np.ndarray | None
    axis2: np.ndarray | None
    dof_names: tuple[str, ...]
    dof_slots: tuple[int, ...]
    range: np.ndarray
    """(n_dof, 2) angle limits, rad."""
    strength_pos: np.ndarray
    strength_neg: np.ndarray
    """Maximum isometric moments, N m, for positive / negative moments about each DoF axis."""
    side: str | None

    @property
    def n_dof(self) -> int:
        return len(self.dof_names)


@dataclass(frozen=True)
class FootGeometry:
    """Right-foot landmarks in the foot frame (origin at the ankle joint centre), m."""

    heel: np.ndarray
    toe: np.ndarray
    met1: np.ndarray
    met5: np.ndarray
    ankle_height: float
    length: float

    def points(self, side: str) -> np.ndarray:
        """(4, 3) heel, toe, met1, met5 for ``side`` ('r' or 'l')."""
        p = np.stack([self.heel, self.toe, self.met1, self.met5])
        return p if side == "r" else p * MIRROR_POINT


@dataclass(frozen=True)
class BodyModel:
    mass: float
    height: float
    sex: str
    segments: tuple[Segment, ...]
    joints: tuple[Joint, ...]
    foot: FootGeometry
    rollover: RollOver
    foot_axis: np.ndarray
    """Stance-foot rotation axis (right side, global), unit."""
    torso_range: np.ndarray
    """(3, 2) limits of the torso's global orientation about x, y, z, rad."""

    @property
    def segment_names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.segments)

    @property
    def dof_names(self) -> tuple[str, ...]:
        return tuple(n for j in self.joints for n in j.dof_names)

    def segment_index(self, name: str) -> int:
        return self.segment_names.index(name)

    def joint_index(self, name: str) -> int:
        return JOINT_NAMES.index(name)

    def path_to_pelvis(self, segment: int) -> list[int]:
        """Joint indices from ``segment`` up to the pelvis (nearest first)."""
        path = []
        while segment != 0:
            j = segment - 1
            path.append(j)
            segment = self.joints[j].parent
        return path


def _segments(mass: float, height: float, sex: str, geo: dict) -> tuple[list[Segment], dict]:
    d = scaled_de_leva(mass, height, sex)
    lt, mt, ut = d["lower_trunk"], d["middle_trunk"], d["upper_trunk"]
    pelvis_com = (0.0, lt.length * (1 - lt.com_fraction), 0.0)
    torso = lump(
        [
            (mt.mass, (0.0, mt.length * (1 - mt.com_fraction), 0.0), mt.inertia_xyz),
            (ut.mass, (0.0, mt.length + ut.length * (1 - ut.com_fraction), 0.0), ut.inertia_xyz),
        ]
    )
    h = d["head"]
    fa, hand = d["forearm"], d["hand"]
    forearm = lump(
        [
            (fa.mass, (0.0, -fa.length * fa.com_fraction, 0.0), fa.inertia_xyz),
            (hand.mass, (0.0, -fa.length - hand.length * hand.com_fraction, 0.0),
             hand.inertia_xyz),
        ]
    )  # fmt: skip
    foot = d["foot"]
    fg = geo["foot"]
    ankle_h = geo["ankle_height"] * height
    foot_com = ((foot.com_fraction - fg["ankle"]) * foot.length, -0.5 * ankle_h, 0.0)

    def limb(s):
        return (s.mass, (0.0, -s.length * s.com_fraction, 0.0), s.inertia_xyz)

    rows = {
        "pelvis": ((lt.mass, pelvis_com, lt.inertia_xyz), lt.length),
        "torso": (torso, mt.length + ut.length),
        "head": ((h.mass, (0.0, h.length * (1 - h.com_fraction), 0.0), h.inertia_xyz), h.length),
        "upper_arm": (limb(d["upper_arm"]), d["upper_arm"].length),
        "forearm": (forearm, fa.length + hand.length),
        "thigh": (limb(d["thigh"]), d["thigh"].length),
        "shank": (limb(d["shank"]), d["shank"].length),
        "foot": ((foot.mass, foot_com, foot.inertia_xyz), foot.length),
    }
    segs = []
    for name in SEGMENT_NAMES:
        base, side = (name[:-2], name[-1]) if name[-2:] in ("_r", "_l") else (name, None)
        (sm, com, inertia), length = rows[base]
        com = np.array(com) * (MIRROR_POINT if side == "l" else 1.0)
        segs.append(Segment(name, float(sm), _ro(com), _ro(inertia), float(length)))
    lengths = {k: v.length for k, v in d.items()}
    lengths["ankle_height"] = ankle_h
    return segs, lengths


def _joint_offsets(height: float, geo: dict, L: dict) -> dict[str, np.ndarray]:
    hip_w = geo["hip_width"] * height
    sh_w = geo["shoulder_width"] * height
    neck_y = L["middle_trunk"] + L["upper_trunk"]
    return {
        "waist": np.array([0.0, L["lower_trunk"], 0.0]),
        "neck": np.array([0.0, neck_y, 0.0]),
        "shoulder": np.array([0.0, neck_y - geo["shoulder_drop"] * height, sh_w / 2]),
        "elbow": np.array([0.0, -L["upper_arm"], 0.0]),
        "hip": np.array([0.0, 0.0, hip_w / 2]),
        "knee": np.array([0.0, -L["thigh"], 0.0]),
        "ankle": np.array([0.0, -L["shank"], 0.0]),
    }


def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def _joints(mass: float, height: float, params: dict, L: dict) -> list[Joint]:
    offsets = _joint_offsets(height, params["geometry"], L)
    k_strength = mass / params["strength"]["reference_mass_kg"]
    joints = []
    for j, name in enumerate(JOINT_NAMES):
        base, side = (name[:-2], name[-1]) if name[-2:] in ("_r", "_l") else (name, None)
        p = params["joints"][base]
        mirror = side == "l"
        ax_sign = MIRROR_AXIAL if mirror else np.ones(3)
        axis = _unit(p["axis"]) * ax_sign if "axis" in p else None
        axis2 = _unit(p["axis2"]) * ax_sign if "axis2" in p else None
        if p["type"] == "ball":
            slots = (0, 1, 2)
        elif p["type"] == "hinge":
            slots = (2,)
        else:
            slots = (2, 0)
        suffix = f"_{side}" if side else ""
        joints.append(
            Joint(
                name=name,
                kind=p["type"],
                parent=SEGMENT_NAMES.index(_JOINT_PARENT[name]),
                child=j + 1,
                offset=_ro(offsets[base] * (MIRROR_POINT if mirror else 1.0)),
                axes=_ro(np.diag(ax_sign)),
                axis=None if axis is None else _ro(axis),
                axis2=None if axis2 is None else _ro(axis2),
                dof_names=tuple(f"{n}{suffix}" for n in p["dofs"]),
                dof_slots=slots,
                range=_ro(np.radians(np.array(p["range_deg"], dtype=float))),
                strength_pos=_ro(np.array(p["strength_pos_Nm"], dtype=float) * k_strength),
                strength_neg=_ro(np.array(p["strength_neg_Nm"], dtype=float) * k_strength),
                side=side,
            )
        )
    return joints


def _foot(height: float, params: dict, L: dict) -> FootGeometry:
    fg = params["geometry"]["foot"]
    lf = L["foot"]
    ha = L["ankle_height"]

    def pt(frac: float, lateral: float = 0.0) -> np.ndarray:
        return _ro([(frac - fg["ankle"]) * lf, -ha, lateral * lf])

    return FootGeometry(
        heel=pt(0.0),
        toe=pt(1.0, fg["toe_lateral"]),
        met1=pt(fg["met1"], fg["met1_lateral"]),
        met5=pt(fg["met5"], fg["met5_lateral"]),
        ankle_height=ha,
        length=lf,
    )


@cache
def build_body(mass: float = 68.8, height: float = 1.77, sex: str = "male") -> BodyModel:
    """Build the body model of a subject (defaults: the paper's subject, 68.8 kg, 1.77 m, male).

    Raises ``ValueError`` for non-physical inputs.
    """
    if not (np.isfinite(mass) and 20.0 <= mass <= 250.0):
        raise ValueError(f"body mass must be between 20 and 250 kg, got {mass}")
    if not (np.isfinite(height) and 1.0 <= height <= 2.4):
        raise ValueError(f"height must be between 1.0 and 2.4 m, got {height}")
    params = load_parameters()
    segs, L = _segments(mass, height, sex, params["geometry"])
    joints = _joints(mass, height, params, L)
    foot = _foot(height, params, L)
    ro = params["geometry"]["rollover"]
    rollover = arc_rollover(
        radius=ro["radius"] * foot.length,
        centre_forward=ro["centre_forward"] * foot.length,
        ankle_height=foot.ankle_height,
    )
    return BodyModel(
        mass=float(mass),
        height=float(height),
        sex=sex,
        segments=tuple(segs),
        joints=tuple(joints),
        foot=foot,
        rollover=rollover,
        foot_axis=_ro([0.0, 0.0, 1.0]),
        torso_range=_ro(np.radians(np.array(params["torso_orientation"]["range_deg"], float))),
    )
