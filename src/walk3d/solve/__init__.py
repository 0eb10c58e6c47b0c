"""Solvers for the prediction NLP: IPOPT (default) and CasADi's SQP method."""

from __future__ import annotations

from collections.abc import Callable

from walk3d.problem.settings import PredictionSettings

SOLVERS = ("ipopt", "sqp")

SOLVE_REVISION = 14
"""Increased whenever a change makes a start of the same settings and seed run other stages or
solve another problem; recorded in each summary.json. A campaign folder records it and refuses
to resume under another revision, so that its starts stay comparable (the history of the
revisions is in docs/solver.md)."""


def run_solver(
    settings: PredictionSettings,
    seed: int,
    solver: str = "ipopt",
    on_stage: Callable[[str], None] | None = None,
):
    """Solve with the named solver; returns a :class:`walk3d.solve.ipopt.SolveOutcome`."""
    if solver not in SOLVERS:
        raise ValueError(f"solver must be one of {SOLVERS}, got {solver!r}")
    from walk3d.solve import starts

    return starts.solve_start(settings, seed, method=solver, on_stage=on_stage)
