"""Helpers of the report tests, without a solve: the shipped atlas's male solution at 1.3 m/s
evaluated over the cycle (about a second) with the full summary ``walk3d predict`` writes (its
solver record made up: converged or not), and a fake campaign of such starts."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from helpers import shared_data_dir
from result_support import evaluate_atlas, make_campaign  # noqa: F401 - shared without a solve

DATA = shared_data_dir()
needs_data = pytest.mark.skipif(
    not (DATA / "falisse2019" / "cycle_right_leg_mean_sd.csv").is_file(),
    reason=f"measured data not found in {DATA} (../shared/data)",
)


def make_prediction(settings, ev, converged: bool, seed: int = 0):
    """A Prediction with ``walk3d predict``'s summary, its solver outcome made up."""
    from walk3d.pipeline import summarize
    from walk3d.results.evaluate import make_prediction as make

    outcome = SimpleNamespace(
        stages=[{"start": "atlas"}], converged=converged, attempts=1, wall_time_s=12.3,
        status="Solve_Succeeded" if converged else "Maximum_Iterations_Exceeded",
        iterations=42, compiled_derivatives=[], max_constraint_violation=1e-9,
        x=np.zeros(3), handover=settings.model.handover,
    )  # fmt: skip
    return make(ev.prediction_arrays, summarize(settings, seed, outcome, ev, "ipopt"))
