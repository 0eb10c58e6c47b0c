"""A result folder without a solve: the shipped atlas's male solution at 1.3 m/s evaluated
over the cycle (about a second) and saved with the summary walk3d predict writes, its
coefficients included (``walk3d audit`` evaluates them again)."""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np

SPEED = 1.3


def result_folder(folder: Path) -> Path:
    """``walk3d predict --out``'s files for the atlas's 1.3 m/s solution, in ``folder``."""
    import walk3d.solve.atlas as atlas_module
    from walk3d.pipeline import summarize
    from walk3d.problem.settings import PredictionSettings, body_for
    from walk3d.results.evaluate import evaluate_cycle, make_prediction
    from walk3d.results.prediction import save_prediction

    path = Path(atlas_module.__file__).parent / "atlas_data" / "male-natural.json"
    data = json.loads(path.read_text(encoding="utf-8"))
    entry = next(e for e in data["entries"] if abs(e["speed"] - SPEED) < 1e-9)
    settings = PredictionSettings(
        gait={"speed": SPEED, "period": entry["period"],
              "double_support": entry["double_support"]},
        model=data["settings"]["model"] | {"handover": False},  # as the atlas solved it
    )  # fmt: skip
    ev = evaluate_cycle(body_for(settings), settings, np.array(entry["x"]))
    stage = {"stage": "full problem", "start": "atlas", "atlas_speeds": [1.2, 1.3, 1.4],
             "iterations": 8, "status": "Solve_Succeeded", "objective": 1.0}  # fmt: skip
    outcome = SimpleNamespace(stages=[stage], converged=True, status="Solve_Succeeded",
                              iterations=8, attempts=1, wall_time_s=4.5, handover=False,
                              compiled_derivatives=(), max_constraint_violation=1e-9,
                              x=np.array(entry["x"]))  # fmt: skip
    summary = summarize(settings, 0, outcome, ev, "ipopt")
    return save_prediction(make_prediction(ev.prediction_arrays, summary), folder)
