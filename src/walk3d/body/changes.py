"""What-if changes to the body and its joints: strength factors, added point masses, joint
limits and shank lengths (issue #43; docs/what-if.md).

A change names a joint, segment or DoF on both sides (``ankle``, ``thigh``,
``ankle_dorsiflexion``), on one side (``ankle_r``, ``foot_l``, ``ankle_dorsiflexion_r``) or a
midline one (``waist``, ``torso``). The half-cycle problem makes the left side the mirror of
the right half a cycle later, so a one-sided change needs the full-cycle problem
(:mod:`walk3d.problem.full_cycle`), which the prediction then uses.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import replace

import numpy as np

from walk3d.body.model import JOINT_NAMES, SEGMENT_NAMES, BodyModel, build_body

__all__ = ["DOF_KINDS", "JOINT_KINDS", "SEGMENT_KINDS", "STRENGTH_FACTORS", "apply_changes",
           "check_changes", "expand", "is_one_sided", "limited_dofs"]  # fmt: skip

JOINT_KINDS = tuple(dict.fromkeys(n.removesuffix("_r").removesuffix("_l") for n in JOINT_NAMES))
"""Joint names a strength change takes: waist, neck, shoulder, elbow, hip, knee, ankle."""
SEGMENT_KINDS = tuple(dict.fromkeys(n.removesuffix("_r").removesuffix("_l")
                                    for n in SEGMENT_NAMES))  # fmt: skip
"""Segment names an added mass takes: pelvis, torso, head, upper_arm, forearm, thigh, shank,
foot."""
_DOF_NAMES = build_body().dof_names
DOF_KINDS = tuple(dict.fromkeys(n.removesuffix("_r").removesuffix("_l") for n in _DOF_NAMES))
"""DoF names a joint limit takes (OpenSim's coordinate names without the side)."""

MAX_SHANK_CHANGE_M = 0.1
"""Largest shank length change, m: leg-length differences above about 2 cm are treated
clinically, and 10 cm is far beyond a shoe lift's range."""
STRENGTH_FACTORS = (0.01, 10.0)
"""Accepted strength factors: at 1 % a joint is all but paralysed, and ten times its strength is
far beyond training (tens of percent) or an assistive device; factors far outside (1e300, 1e-300)
overflow the criterion's moment-over-strength terms."""
MAX_ADDED_MASS_KG = 60.0
"""Largest added mass per segment, kg: a heavy load carriage (military packs reach 40–60 kg)."""


def expand(name: str, full: tuple[str, ...]) -> tuple[str, ...]:
    """The model names a change applies to: a midline or one-sided name itself, or both
    sides."""
    return (name,) if name in full else (f"{name}_r", f"{name}_l")


def is_one_sided(name: str) -> bool:
    """Whether a change's name is a side's own (``ankle_r``, ``foot_l``)."""
    return name.endswith(("_r", "_l"))


def _name_error(name: str, kinds: tuple[str, ...], full: tuple[str, ...], what: str) -> str | None:
    if name in kinds or (is_one_sided(name) and name in full):
        return None
    return f"unknown {what} {name!r}; known: {', '.join(kinds)}, sided ones also with _r or _l"


def _overlap(names: list[str]) -> bool:
    """Whether a part is named twice, or both without and with its side."""
    plain = {n for n in names if not is_one_sided(n)}
    return len(set(names)) < len(names) or any(n[:-2] in plain for n in names if is_one_sided(n))


def check_changes(
    strength: tuple[tuple[str, float], ...],
    added_mass: tuple[tuple[str, float], ...],
    limits: tuple[tuple[str, float, float], ...],
    shank_length: tuple[tuple[str, float], ...] = (),
) -> None:
    """Raise ValueError, one line, for the first bad change: a value that is not a finite
    number (a bool included), an unknown name, a factor outside :data:`STRENGTH_FACTORS`, a
    mass outside [0, :data:`MAX_ADDED_MASS_KG`], a limit beyond ±π rad (with a hint when it
    looks like degrees), an empty limit or one that excludes standing (angle 0), a shank change
    that is not a shank's or beyond ±:data:`MAX_SHANK_CHANGE_M`, a part named twice."""
    for what, items in (("strength factor", strength), ("added mass", added_mass),
                        ("limit", limits), ("length change", shank_length)):  # fmt: skip
        for name, *values in items:
            for v in values:
                if isinstance(v, bool) or not isinstance(v, numbers.Real) or not math.isfinite(v):
                    raise ValueError(f"the {what} of {name!r} must be a finite number, got {v!r}")
    for name, factor in strength:
        if msg := _name_error(name, JOINT_KINDS, JOINT_NAMES, "joint"):
            raise ValueError(msg)
        lo, hi = STRENGTH_FACTORS
        if not lo <= factor <= hi:
            raise ValueError(f"strength factor of {name!r} must be in [{lo:g}, {hi:g}], "
                             f"got {factor:g}")  # fmt: skip
    for name, kg in added_mass:
        if msg := _name_error(name, SEGMENT_KINDS, SEGMENT_NAMES, "segment"):
            raise ValueError(msg)
        if not 0 <= kg <= MAX_ADDED_MASS_KG:
            raise ValueError(f"added mass at {name!r} must be in [0, {MAX_ADDED_MASS_KG:g}] kg, "
                             f"got {kg:g}")  # fmt: skip
    for name, lo, hi in limits:
        if msg := _name_error(name, DOF_KINDS, _DOF_NAMES, "DoF"):
            raise ValueError(msg)
        if max(abs(lo), abs(hi)) > math.pi:
            hint = (f"; in degrees that is {np.radians(lo):.4g}:{np.radians(hi):.4g} rad"
                    if max(abs(lo), abs(hi)) <= 180 else "")  # fmt: skip
            raise ValueError(
                f"limit of {name!r} ({lo:g}:{hi:g} rad) is beyond ±π rad: limits are "
                f"in radians (the command line's --range takes degrees){hint}"
            )
        if not lo < hi:
            raise ValueError(f"limit of {name!r} is empty: {np.degrees(lo):.4g}:"
                             f"{np.degrees(hi):.4g} deg")  # fmt: skip
        if not lo <= 0 <= hi:
            raise ValueError(f"limit of {name!r} ({np.degrees(lo):.4g}:{np.degrees(hi):.4g} deg) "
                             "excludes standing (0 deg)")  # fmt: skip
    for name, dm in shank_length:
        if name not in ("shank", "shank_r", "shank_l"):
            raise ValueError(f"a leg length change names a shank (shank, shank_r or shank_l), "
                             f"got {name!r}")  # fmt: skip
        if not abs(dm) <= MAX_SHANK_CHANGE_M:
            raise ValueError(f"the length change of {name!r} must be within "
                             f"±{MAX_SHANK_CHANGE_M:g} m, got {dm:g}")  # fmt: skip
    groups = (("strength", strength), ("added mass", added_mass), ("limit", limits),
              ("leg length", shank_length))  # fmt: skip
    for what, items in groups:
        names = [item[0] for item in items]
        if _overlap(names):
            raise ValueError(f"a {what} change names the same part twice: {', '.join(names)}")


def apply_changes(
    body: BodyModel,
    strength: tuple[tuple[str, float], ...] = (),
    added_mass: tuple[tuple[str, float], ...] = (),
    shank_length: tuple[tuple[str, float], ...] = (),
) -> BodyModel:
    """``body`` with its joints' strengths (both directions, every DoF) times each factor, each
    added mass, kg, at its segment's centre of mass (a point mass: the inertia about the centre
    of mass is unchanged; ``foot`` puts that mass on each foot) and each shank's length changed
    by the metres given (:func:`_shank`). The body mass grows by the added masses."""
    if not strength and not added_mass and not shank_length:
        return body
    joints = list(body.joints)
    for name, factor in strength:
        for jn in expand(name, JOINT_NAMES):
            i = JOINT_NAMES.index(jn)
            j = joints[i]
            joints[i] = replace(j, strength_pos=_frozen(j.strength_pos * factor),
                                strength_neg=_frozen(j.strength_neg * factor))  # fmt: skip
    segments = list(body.segments)
    total = 0.0
    for name, kg in added_mass:
        for sn in expand(name, SEGMENT_NAMES):
            i = SEGMENT_NAMES.index(sn)
            segments[i] = replace(segments[i], mass=segments[i].mass + float(kg))
            total += float(kg)
    for name, dm in shank_length:
        for sn in expand(name, SEGMENT_NAMES):
            i, k = SEGMENT_NAMES.index(sn), JOINT_NAMES.index(sn.replace("shank", "ankle"))
            segments[i], joints[k] = _shank(segments[i], joints[k], float(dm))
    return replace(body, joints=tuple(joints), segments=tuple(segments), mass=body.mass + total)


def _shank(seg, ankle, dm: float):
    """The shank and its ankle joint with the knee-to-ankle length ``L`` changed by ``dm``: the
    ankle and the centre of mass move along the shank by ``dm`` and ``dm`` times the centre of
    mass's fraction of ``L``; mass and inertia stay (2 cm changes them by about 5 %)."""
    k = (seg.length + dm) / seg.length
    new_seg = replace(seg, com=_frozen(seg.com * k), length=seg.length + dm)
    return new_seg, replace(ankle, offset=_frozen(ankle.offset * k))


def limited_dofs(
    body: BodyModel, limits: tuple[tuple[str, float, float], ...]
) -> dict[int, tuple[float, float]]:
    """DoF index -> ``(min, max)``, rad, of each joint limit (both sides of a bilateral DoF
    named without its side)."""
    names = body.dof_names
    return {names.index(n): (lo, hi) for name, lo, hi in limits for n in expand(name, names)}


def _frozen(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a
