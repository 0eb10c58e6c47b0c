"""A model element: an option that acts at every node, turned on by its setting.

A :class:`~walk3d.model.settings.ModelSettings` field names its element in its
:class:`~walk3d.model.settings.Role` (``element="module:NAME"``); while the field is not at its
off value, :func:`walk3d.model.node.active` applies it. The solver, the evaluated cycle and the
cache keys then follow without an edit (docs/extending.md).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from walk3d.body.model import BodyModel
from walk3d.model.state import GaitState


@dataclass(frozen=True)
class Element:
    """``apply(body, model, state, values)`` returns the gait state whose joint moments the
    criterion sees (``values``: the 24 joint coordinates; ``model``: the model settings)."""

    name: str
    apply: Callable[[BodyModel, Any, GaitState, list[Any]], GaitState]
