"""Solvers for the prediction NLP: IPOPT (default) and CasADi's SQP method."""

from __future__ import annotations

from collections.abc import Callable

from walk3d.problem.settings import PredictionSettings
from walk3d.solve.revision import SOLVE_REVISION

SOLVERS = ("ipopt", "sqp")

__all__ = ["SOLVE_REVISION", "SOLVERS", "run_solver"]


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
