"""Helpers of the report tests, without a solve: the shipped atlas's male solution at 1.3 m/s
evaluated over the cycle (about a second) with the full summary ``walk3d predict`` writes (its
solver record made up: converged or not), and a fake campaign of such starts."""

from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from helpers import shared_data_dir

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "verify"))
from verify_support import evaluate_atlas  # noqa: E402, F401 - the shared atlas solution

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


def make_campaign(out: Path, source: Path, starts: dict[int, bool], requested: int) -> Path:
    """A campaign folder whose starts are copies of the result folder ``source``, converged or
    not as ``starts`` says, ranked with ``ranking.csv`` and ``best/`` as walk3d campaign does."""
    from walk3d.campaign import rank, store
    from walk3d.campaign.ranking import update_best, write_ranking
    from walk3d.campaign.task import record_from_summary
    from walk3d.problem.settings import PredictionSettings

    summary = json.loads((source / "summary.json").read_text(encoding="utf-8"))
    settings = PredictionSettings(**summary["settings"])
    store.open_campaign(out, settings, 0, requested, "ipopt")
    for seed, converged in starts.items():
        tmp = store.new_temporary(store.starts_dir(out), store.start_name(seed))
        shutil.copytree(source, tmp, dirs_exist_ok=True)
        s = summary | {"seed": seed, "converged": converged,
                       "status": "Solve_Succeeded" if converged else "Infeasible"}  # fmt: skip
        record = record_from_summary(s, settings.model.criterion, 10.0 + seed)
        record["criterion_value"] = (record["criterion_value"] or 0.0) + seed
        store.commit_start(tmp, seed, record)
    rows = rank(out)
    write_ranking(out, rows)
    update_best(out, rows)
    return out
