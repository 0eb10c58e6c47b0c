"""The smooth landing (``ModelSettings.handover``, on by default) when T and Td are predicted.

The criterion's weights were chosen against measured periods, and the atlas was solved, with
the paper's free landing: the chain's root passes to the leading foot at heel strike and the
velocities jump there. With the handover in the problem while T and Td are still unknowns, the
period comes out 7–11 % short and the solve does not converge from the atlas (docs/opensim.md).
So T and Td are predicted with the free landing, and the motion is then solved again with the
handover at those T and Td, warm from the first optimum. With T and Td given, the handover
problem is solved directly. If the second solve does not converge, the cycle keeps the free
landing (converged, its velocities jumping at heel strike), and the outcome says so.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import TYPE_CHECKING

from walk3d.problem import layout
from walk3d.problem.settings import PredictionSettings

if TYPE_CHECKING:  # the solvers load only when a solve runs, not with walk3d.pipeline
    from walk3d.solve.ipopt import SolveOutcome

__all__ = ["LANDING", "LANDING_MAX_ITER", "landing_of", "solve_with_landing"]

LANDING = "landing"
"""The ``start`` of the handover stage's record in ``SolveOutcome.stages``."""

LANDING_MAX_ITER = 150
"""Iteration limit of the handover solve at the predicted T and Td: over the atlas's speeds the
converged ones took 25–64 iterations, and one that had not converged by 400 did not
(``benchmarks/landing.py``)."""


def solve_with_landing(
    settings: PredictionSettings,
    first: Callable[[PredictionSettings], SolveOutcome],
    method: str = "ipopt",
    on_stage: Callable[[str], None] | None = None,
) -> SolveOutcome:
    """Solve ``settings`` with ``first`` (a solve of given settings: from the atlas, standing
    or a warm start); with the handover and predicted descriptors, ``first`` solves the free
    landing and the handover follows at its T and Td (module docstring)."""
    if not (settings.model.handover and settings.gait.free):
        return first(settings)
    from walk3d.solve import ipopt, starts

    free = first(settings.replace(handover=False))
    if not free.converged:
        return free
    given = settings.replace(free=(), **free.descriptors)
    smooth = starts.solve_warm(given, free.z[: layout.N_X], method, on_stage,
                               origin="the free landing's optimum",
                               max_iter=LANDING_MAX_ITER)  # fmt: skip
    smooth.stages[-1]["start"] = LANDING
    # the handover stage is not another start: free's attempts and T, Td stand
    both = replace(ipopt.merged(free, smooth, method), attempts=free.attempts,
                   descriptors=free.descriptors)  # fmt: skip
    both.stages[-1]["attempt"] = free.stages[-1].get("attempt", 0)
    if smooth.converged:
        return both
    if on_stage:
        on_stage("the handover did not converge: the cycle keeps the free landing")
    kept = {"x": free.x, "z": free.z, "status": free.status, "handover": False,
            "max_constraint_violation": free.max_constraint_violation}  # fmt: skip
    return replace(both, converged=True, **kept)


def landing_of(outcome: SolveOutcome) -> str:
    """How the cycle lands, for the summary: ``handover``, ``free``, or ``free`` with the reason
    when the handover stage ran and did not converge."""
    if outcome.handover:
        return "handover"
    if any(r.get("start") == LANDING for r in outcome.stages):
        return "free: the handover at the predicted T and Td did not converge"
    return "free"
