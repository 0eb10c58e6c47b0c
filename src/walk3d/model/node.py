"""The node model: everything the solver and the reports need at one instant, written once.

:func:`node_model` takes the gait state at a node (:func:`walk3d.model.state.evaluate`) and
returns the moments the criterion sees (net less each enabled element,
:mod:`walk3d.model.element`), the criterion terms' integrands and the what-if overload. The
NLP's node function adds its constraint rows and slacks to it;
:func:`walk3d.results.evaluate.evaluate_cycle` stacks it over the cycle.
:func:`objective` is the weighted criterion's integrand, for both.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from walk3d.body.model import BodyModel
from walk3d.model import terms, whatif
from walk3d.model.settings import ModelSettings, elements
from walk3d.model.state import GaitState, dof_moment_terms
from walk3d.model.term import Parts

__all__ = ["NodeModel", "active", "node_model", "objective"]


def active(body: BodyModel, model: ModelSettings, st: GaitState, values: list[Any]) -> GaitState:
    """``st`` with the moments the criterion sees: each element whose setting is on
    (:func:`walk3d.model.settings.elements`) applied in turn, in the settings' field order."""
    for element in elements(model):
        st = element.apply(body, model, st, values)
    return st


@dataclass(frozen=True)
class NodeModel:
    """The node model's outputs at one instant (numbers, arrays over samples, or SX)."""

    state: GaitState
    """The gait state with the net joint moments (what the results report)."""
    active: GaitState
    """The same with the moments the criterion sees (:func:`active`)."""
    moments: list[Any]
    """The 24 active DoF moments about their axes, N·m."""
    rates: list[Any]
    """The 24 DoF angular rates, rad/s."""
    axes: list[int]
    """Each DoF's axis label: 0 = x, 1 = y, 2 = z."""
    terms: dict[str, Parts]
    """Integrand per criterion term (:mod:`walk3d.model.terms`), split (x, y, z), per s."""
    overload: Parts | None
    """The weakened joints' overload (:func:`walk3d.model.whatif.overload`); None when no
    joint is weakened."""


def node_model(
    body: BodyModel,
    model: ModelSettings,
    coords: list[tuple[Any, Any, Any]],
    st: GaitState,
    wanted: tuple[str, ...] | None = None,
) -> NodeModel:
    """The node model at the state ``st`` of the 26 coordinate triples ``coords``: ``wanted``
    terms (default every node term of :func:`walk3d.model.terms.node_names`)."""
    values = [c[0] for c in coords[:24]]
    act = active(body, model, st, values)
    moments, rates, axes = dof_moment_terms(body, act)
    parts = terms.integrands(body, coords, act.pose, act.total[0], moments, wanted)
    weak = whatif.weakened_dofs(body, model.changes)
    cap = whatif.overload(body, model.changes, moments, values, axes) if weak else None
    return NodeModel(st, act, moments, rates, axes, parts, cap)


def objective(model: ModelSettings, base: Any, node: NodeModel | None, scale: float = 1.0) -> Any:
    """The weighted criterion's integrand: ``w_base base + (Σ_j w_j term_j + overload) scale``;
    ``base`` is the paper criterion's integrand (C_tor's or C_en's), ``scale`` what the
    objective holds per unit of the weighted terms. ``base`` alone for a plain criterion
    with no weakened joint, or without a node model (no dynamics)."""
    weights = terms.parse(model.criterion)
    w_base = weights[terms.base(model.criterion)]
    extra = terms.extras(model.criterion)
    if node is None or not (extra or w_base != 1.0 or node.overload is not None):
        return base
    cap = sum(node.overload) if node.overload is not None else 0.0
    return w_base * base + (terms.weighted(extra, node.terms) + cap) * scale
