"""The what-if changes of a prediction, as a settings group of :class:`ModelSettings`
(``settings.model.changes``; issue #43, docs/what-if.md). SI units: angles in rad, masses in
kg. :mod:`walk3d.body.changes` checks the names and values and applies them."""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping
from typing import Any

import numpy as np
from pydantic import BaseModel, ConfigDict, field_validator, model_validator

from walk3d import mathops as mo
from walk3d.body.changes import check_changes, expand, is_one_sided
from walk3d.body.model import JOINT_NAMES, BodyModel
from walk3d.model import effort

__all__ = ["Changes", "overload", "weakened_dofs"]


def _pairs(v: Any) -> Any:
    """A mapping ``{name: value}`` as the tuple of its items; anything else unchanged."""
    if isinstance(v, Mapping):
        return tuple((k, *val) if isinstance(val, (tuple, list)) else (k, val)
                     for k, val in v.items())  # fmt: skip
    return v


_VALUES = {"strength": (1, "a factor", "(joint, factor)"),
           "added_mass": (1, "a mass in kg", "(segment, kg)"),
           "limits": (2, "(low, high) in rad", "(dof, low, high)"),
           "shank_length": (1, "a length change in m", "(shank, m)")}  # fmt: skip
"""How many values each item of a :class:`Changes` field holds after its name, what they are
and the item's form (for messages)."""


class Changes(BaseModel):
    """Strength factors, added masses and joint limits; none by default (normal walking)."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    strength: tuple[tuple[str, float], ...] = ()
    """``(joint, factor)``: the joint's strengths in both directions times ``factor``; they
    normalize C_tor and the effort terms, so a weak joint costs more per N·m."""
    added_mass: tuple[tuple[str, float], ...] = ()
    """``(segment, kg)``: a point mass at the segment's centre of mass (a backpack: torso)."""
    limits: tuple[tuple[str, float, float], ...] = ()
    """``(dof, min, max)``, rad: bounds on the joint angle over the whole cycle (an orthosis)."""
    shank_length: tuple[tuple[str, float], ...] = ()
    """``(shank, m)``: the shank's length changed (``shank_r``, −0.02: the right leg 2 cm
    shorter, ``--leg-length-difference``)."""

    @field_validator("strength", "added_mass", "limits", "shank_length", mode="before")
    @classmethod
    def _items(cls, v: Any, info: Any) -> Any:
        """Refuse, in one line, an item that is not a name and its values (pydantic's own
        message counts tuple items) or holds a bool or text, which pydantic would read as
        1.0 or as the number it writes."""
        v = _pairs(v)
        field = info.field_name
        count, what, form = _VALUES[field]
        if not isinstance(v, (tuple, list)):  # a set or generator would skip the checks below
            raise ValueError(f"{field} must be a mapping or a list of {form} items, "
                             f"got a {type(v).__name__}")  # fmt: skip
        for item in v:
            if not (isinstance(item, (tuple, list)) and item and isinstance(item[0], str)):
                raise ValueError(f"each {field} item is {form}, got {item!r:.60}")
            values = tuple(item[1:])
            if len(values) != count:
                raise ValueError(f"{field} of {item[0]} must be {what}, got {values!r:.60}")
            if any(isinstance(x, (bool, np.bool_)) for x in values):
                raise ValueError(f"{field} of {item[0]} must be {what}, not a bool: "
                                 f"{values!r:.60}")  # fmt: skip
            if not all(isinstance(x, numbers.Real) for x in values):  # "1_0" would read as 10
                raise ValueError(f"{field} of {item[0]} must be {what}, got {values!r:.60}")
        return v

    @model_validator(mode="after")
    def _valid(self) -> Changes:
        check_changes(self.strength, self.added_mass, self.limits, self.shank_length)
        return self

    def __bool__(self) -> bool:
        return any(getattr(self, k) for k in KINDS)

    def both_sided(self) -> Changes:
        """These changes without the one-sided ones: what the half cycle can hold."""
        return Changes(**{k: tuple(i for i in getattr(self, k) if not is_one_sided(i[0]))
                          for k in KINDS})  # fmt: skip

    def half_cycle(self) -> Changes:
        """The changes of the half cycle that starts the full cycle: those to both sides, and
        each one-sided joint limit on both sides (the two sides' intersection where both have
        one), so that the mirrored start keeps the limits; the other one-sided changes are left
        out (a start outside a brace cost 81 iterations against 45 inside, docs/what-if.md)."""
        base = self.both_sided()
        sided: dict[str, tuple[float, float]] = {}
        for name, lo, hi in self.limits:
            if is_one_sided(name):
                lo0, hi0 = sided.get(name[:-2], (-math.inf, math.inf))
                sided[name[:-2]] = (max(lo, lo0), min(hi, hi0))
        limits = base.limits + tuple((n, lo, hi) for n, (lo, hi) in sided.items())
        return Changes(**{k: getattr(base, k) for k in KINDS} | {"limits": limits})

    @property
    def one_sided(self) -> bool:
        """Whether a change acts on one side only: the prediction then solves the full cycle
        (:mod:`walk3d.problem.full_cycle`)."""
        items = [item for k in KINDS for item in getattr(self, k)]
        return any(is_one_sided(item[0]) for item in items)


KINDS = ("strength", "added_mass", "limits", "shank_length")
"""The fields of :class:`Changes`, each a tuple of items named first by a part."""
BRACE_HEEL_RISE = 0.3
"""Fraction of stance after which the root foot's heel may rise when the ankle's dorsiflexion
is limited and ``heel_rise`` is not set: with the ankle braced the shank cannot roll over a
flat foot (a ±5° brace did not converge with the foot flat all through single stance; with the
heel free from 30 % of stance it did, docs/what-if.md)."""


def heel_rise(model: Any) -> float | None:
    """The heel-rise fraction the bounds use: ``model.heel_rise``, else
    :data:`BRACE_HEEL_RISE` with a limit on the root (right) foot's ``ankle_dorsiflexion``,
    else None (flat)."""
    if model.heel_rise is not None:
        return model.heel_rise
    roots = ("ankle_dorsiflexion", "ankle_dorsiflexion_r")  # the root foot's ankle
    braced = any(name in roots for name, _, _ in model.changes.limits)
    return BRACE_HEEL_RISE if braced else None


STEP_ASYMMETRY_COST = 4.0
"""``k`` of the full cycle's criterion factor ``1 + k SLA²``, SLA = (right step − left step) /
stride: a step-to-step transition cost growing with step length⁴ (Donelan, Kram & Kuo 2002)
gives k = 3–6, and split-belt walkers' metabolic power about k = 4 (Finley et al. 2013;
docs/criteria.md)."""

OVERLOAD_WEIGHT = 10.0
"""Weight, per s, of :func:`overload`'s squared excess: a moment 10 % over a weakened joint's
strength all through the cycle costs 0.1, about 1 % of a normal gait's criterion, one 100 %
over costs 10."""
OVERLOAD_EPS = 0.01
"""Width of the smooth ``max(0, v)``, ``(v + sqrt(v² + ε²)) / 2``, in units of the strength."""


def weakened_dofs(body: BodyModel, changes: Changes) -> list[int]:
    """DoF indices of the joints a strength factor below 1 weakens."""
    joints = {jn for name, f in changes.strength if f < 1 for jn in expand(name, JOINT_NAMES)}
    out, i = [], 0
    for joint in body.joints:
        if joint.name in joints:
            out += range(i, i + joint.n_dof)
        i += joint.n_dof
    return out


def overload(
    body: BodyModel, changes: Changes, moments: list[Any], values: list[Any], axes: list[int]
) -> tuple[Any, Any, Any]:
    """The weakened joints' moments over their strengths, per s, split by DoF axis ``(x, y,
    z)``: ``W Σ max(0, u_i − 1)²`` (smoothly), ``u_i = |M_i| / M_max,i(θ_i)`` with the weakened,
    angle-dependent strength (:func:`walk3d.model.effort.ratio`), so that a weak muscle
    cannot hold much more than it can (C_tor, linear in ``u``, only makes its moments dearer).
    Zeros with no weakened joint. ``moments``: the 24 active DoF moments, N·m; ``values``: the
    24 coordinate values; ``axes``: each DoF's axis label."""
    parts = [0.0 * moments[0]] * 3
    for i in weakened_dofs(body, changes):
        v = effort.ratio(body, i, moments[i], values[i]) - 1.0
        parts[axes[i]] = (
            parts[axes[i]] + OVERLOAD_WEIGHT * (0.5 * (v + mo.sqrt(v * v + OVERLOAD_EPS**2))) ** 2
        )
    return parts[0], parts[1], parts[2]
