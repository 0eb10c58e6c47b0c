"""The smooth landing (``ModelSettings.handover``, on by default) when T and Td are predicted.

The criterion's weights were chosen against measured periods, and the atlas was solved, with
the paper's free landing: the chain's root passes to the leading foot at heel strike and the
velocities jump there. With the handover in the problem while T and Td are still unknowns, the
period comes out 7–11 % short and the solve does not converge from the atlas (docs/opensim.md).
So T and Td are those of the free landing's optimum, and the motion is the handover's at them.

Two ways to get them (``settings.solver.descriptors_from``):

* ``atlas`` (default, a start from the atlas): T and Td blended from the atlas entries that
  bracket the speed (each entry is the free landing's optimum at its speed), then one solve of
  the handover at them from the entries' handover optima (``Atlas.x_handover``). The blend's
  T and Td differ from a free-landing solve at that speed by the interpolation error
  (docs/descriptors.md);
* ``solve``, and whenever the atlas has no handover entry for the speed or that solve fails:
  the free landing solved with T and Td free, then the handover at its T and Td, warm from it.
  If that second solve does not converge, the cycle keeps the free landing (converged, its
  velocities jumping at heel strike), and the outcome says so.

With T and Td given, the handover problem is solved directly.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import TYPE_CHECKING

from walk3d.problem import layout
from walk3d.problem.settings import PredictionSettings

if TYPE_CHECKING:  # the solvers load only when a solve runs, not with walk3d.pipeline
    from walk3d.solve.ipopt import SolveOutcome

__all__ = ["ATLAS_DESCRIPTORS", "LANDING", "LANDING_MAX_ITER", "landing_of",
           "solve_with_landing"]  # fmt: skip

LANDING = "landing"
"""The ``start`` of the handover stage's record in ``SolveOutcome.stages``."""

LANDING_MAX_ITER = 150
"""Iteration limit of the handover solve at the predicted T and Td: over the atlas's speeds the
converged ones took 25–64 iterations, and one that had not converged by 400 did not
(``benchmarks/landing.py``)."""


ATLAS_DESCRIPTORS = "atlas"
"""``descriptors_from`` in the stage record of a solve whose T and Td came from the atlas."""


def _from_atlas(
    settings: PredictionSettings, seed: int, method: str, on_stage: Callable[[str], None] | None
) -> SolveOutcome | None:
    """The handover solved once at the atlas's T and Td (module docstring), or None when the
    atlas has no handover entry for the speed."""
    import numpy as np

    from walk3d.problem import descriptors, similarity
    from walk3d.solve import atlas, starts

    if set(settings.gait.free) != set(descriptors.NAMES):  # the atlas predicts both at once
        return None
    ref, scale = similarity.reference_problem(settings)
    found, _ = atlas.candidates(ref, tries=1)
    if not found or found[0].landing != "handover":
        return None
    start, k = found[0], float(np.sqrt(scale))
    blended = {"period": start.period * k, "double_support": start.double_support * k}
    given = settings.replace(free=(), **blended)
    if on_stage:
        on_stage("T and Td from the atlas (" + ", ".join(f"{n} {v:.3f} s" for n, v in
                                                           blended.items()) + ")")  # fmt: skip
    outcome = starts.solve_from_atlas(given, seed, method, on_stage)
    if outcome is None:
        return None
    outcome.stages[-1]["descriptors_from"] = ATLAS_DESCRIPTORS
    found_s = {n: getattr(given.gait, n) for n in settings.gait.free}
    return replace(outcome, descriptors=found_s)


def solve_with_landing(
    settings: PredictionSettings,
    first: Callable[[PredictionSettings], SolveOutcome],
    method: str = "ipopt",
    on_stage: Callable[[str], None] | None = None,
    seed: int | None = None,
) -> SolveOutcome:
    """Solve ``settings`` with ``first`` (a solve of given settings: from the atlas, standing
    or a warm start); with the handover and predicted descriptors, T and Td come from the atlas
    (when ``seed`` is given: ``first`` starts from the atlas) or from ``first`` solving the
    free landing, and the handover is solved at them (module docstring)."""
    if not (settings.model.handover and settings.gait.free):
        return first(settings)
    from walk3d.solve import ipopt, starts

    one = None
    if (seed is not None and settings.solver.start == "atlas"
            and settings.solver.descriptors_from == "atlas"):  # fmt: skip
        one = _from_atlas(settings, seed, method, on_stage)
        if one is not None and one.converged:
            return one
        if one is not None and on_stage:
            on_stage("the solve at the atlas's T and Td did not converge: solving the free "
                     "landing")  # fmt: skip
    free = first(settings.replace(handover=False))
    if one is not None:
        free = ipopt.merged(one, free, method)
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
