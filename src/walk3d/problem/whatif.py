"""The what-if changes of a prediction, as a settings group of :class:`ModelSettings`
(``settings.model.changes``; issue #43, docs/what-if.md). SI units: angles in rad, masses in
kg. :mod:`walk3d.body.changes` checks the names and values and applies them."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from pydantic import BaseModel, ConfigDict, field_validator, model_validator

from walk3d.body.changes import check_changes, is_one_sided

__all__ = ["Changes"]


def _pairs(v: Any) -> Any:
    """A mapping ``{name: value}`` as the tuple of its items; anything else unchanged."""
    if isinstance(v, Mapping):
        return tuple((k, *val) if isinstance(val, (tuple, list)) else (k, val)
                     for k, val in v.items())  # fmt: skip
    return v


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

    @field_validator("strength", "added_mass", "limits", mode="before")
    @classmethod
    def _items(cls, v: Any) -> Any:
        return _pairs(v)

    @model_validator(mode="after")
    def _valid(self) -> Changes:
        check_changes(self.strength, self.added_mass, self.limits)
        return self

    def __bool__(self) -> bool:
        return bool(self.strength or self.added_mass or self.limits)

    def both_sided(self) -> Changes:
        """These changes without the one-sided ones: what the half cycle can hold."""
        return Changes(**{k: tuple(i for i in getattr(self, k) if not is_one_sided(i[0]))
                          for k in ("strength", "added_mass", "limits")})  # fmt: skip

    @property
    def one_sided(self) -> bool:
        """Whether a change acts on one side only: the prediction then solves the full cycle
        (:mod:`walk3d.problem.full_cycle`)."""
        items = (*self.strength, *self.added_mass, *self.limits)
        return any(is_one_sided(item[0]) for item in items)


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
