"""A criterion term: the object a built-in or a user's term is (:mod:`walk3d.model.terms`
registers them), and :class:`Node`, the one instant its formula reads."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

from walk3d.body.model import BodyModel
from walk3d.kinematics.forward import Pose

Parts = tuple[Any, Any, Any]
"""An integrand split into its x (frontal), y (transverse) and z (sagittal) parts, per s."""


@dataclass(frozen=True, eq=False)
class Node:
    """One instant of the gait as a term's formula sees it. Entries are NumPy arrays over time
    samples or CasADi ``SX`` scalars (one code for the NLP's nodes and the evaluated cycle)."""

    body: BodyModel
    coords: list[tuple[Any, Any, Any]]
    """The 26 coordinate triples (value, rate, acceleration) of :mod:`walk3d.model.coordinates`."""
    pose: Pose
    """Every segment's kinematics (:func:`walk3d.kinematics.forward.forward`)."""
    force: tuple[Any, Any, Any]
    """The total ground reaction force, N."""
    moments: list[Any] | None
    """The 24 active DoF moments, N·m (net less passive); None where no dynamics is solved."""
    axes: list[int]
    """Each DoF's axis label: 0 = x, 1 = y, 2 = z."""
    cache: dict[str, Any] = field(default_factory=dict, repr=False)
    """Quantities shared by several terms, made once per node (:meth:`shared`)."""

    @cached_property
    def zero(self) -> Any:
        """A zero of the node's type (a number, an array or an SX)."""
        return 0.0 * self.force[1]

    def shared(self, name: str, make: Callable[[Node], Any]) -> Any:
        """``make(self)``, computed once per node under ``name`` (the whole-body angular
        momentum serves two terms, for example)."""
        if name not in self.cache:
            self.cache[name] = make(self)
        return self.cache[name]


@dataclass(frozen=True)
class Term:
    """One criterion term: the cycle integral of a dimensionless integrand, in s, weighted in
    a criterion by its ``name``. A human-like gait scores about 1 per second on its ``scale``."""

    name: str
    """The name a criterion spec gives it a weight by (``tor=1,<name>=0.5``)."""
    formula: Callable[[Node, Any], Parts] | None
    """``formula(node, scale)``: the integrand at one node, split ``(x, y, z)``. None: a term on
    the Fourier coefficients, which the transcription adds exactly (``jerk``)."""
    scale: Any
    """The reference scale(s) the formula divides by (unit in ``doc``): about the RMS of the
    quantity in measured adult walking."""
    doc: str = ""
    """One line: what it charges, and the unit of its scale."""
    needs_moments: bool = False
    """Whether the formula reads :attr:`Node.moments` (left out where there is no dynamics)."""

    def integrand(self, node: Node) -> Parts:
        """The formula at ``node`` with this term's scale."""
        if self.formula is None:
            raise ValueError(f"criterion term {self.name!r} is on the coefficients, not a node")
        return self.formula(node, self.scale)
