"""A result folder without a solve: the shipped atlas's male solution at 1.3 m/s evaluated
over the cycle (about a second) and saved with the summary walk3d predict writes, its
coefficients included (``walk3d audit`` evaluates them again)."""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np

SPEED = 1.3


def _atlas_entry() -> tuple[dict, dict]:
    """The shipped male atlas file and its entry at :data:`SPEED`."""
    import walk3d.solve.atlas as atlas_module

    path = Path(atlas_module.__file__).parent / "atlas_data" / "male-natural.json"
    data = json.loads(path.read_text(encoding="utf-8"))
    return data, next(e for e in data["entries"] if abs(e["speed"] - SPEED) < 1e-9)


def atlas_x() -> np.ndarray:
    """The decision vector of the shipped male atlas solution at 1.3 m/s."""
    return np.array(_atlas_entry()[1]["x"], dtype=float)


def evaluate_atlas():
    """``(settings, body, evaluation)`` of the shipped male atlas solution at 1.3 m/s, with the
    free landing it was solved with."""
    from walk3d.problem.settings import PredictionSettings, body_for
    from walk3d.results.evaluate import evaluate_cycle

    data, entry = _atlas_entry()
    settings = PredictionSettings(
        gait={"speed": SPEED, "period": entry["period"],
              "double_support": entry["double_support"]},
        model=data["settings"]["model"] | {"handover": False},  # as the atlas solved it
    )  # fmt: skip
    body = body_for(settings)
    return settings, body, evaluate_cycle(body, settings, np.array(entry["x"]))


def bare_result_folder(folder: Path) -> Path:
    """The two files by which walk3d knows a result folder (:func:`walk3d.outputs.
    is_result_folder`) and nothing else: for the output checks, which never read them."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "summary.json").write_text('{"the": "result"}\n', encoding="utf-8")
    (folder / "manifest.json").write_text('{"files": {}}\n', encoding="utf-8")
    return folder


def result_folder(folder: Path) -> Path:
    """``walk3d predict --out``'s files for the atlas's 1.3 m/s solution, in ``folder``."""
    from walk3d.pipeline import summarize
    from walk3d.results.evaluate import make_prediction
    from walk3d.results.prediction import save_prediction

    settings, _, ev = evaluate_atlas()
    stage = {"stage": "full problem", "start": "atlas", "atlas_speeds": [1.2, 1.3, 1.4],
             "iterations": 8, "status": "Solve_Succeeded", "objective": 1.0}  # fmt: skip
    outcome = SimpleNamespace(stages=[stage], converged=True, status="Solve_Succeeded",
                              iterations=8, attempts=1, wall_time_s=4.5, handover=False,
                              compiled_derivatives=(), max_constraint_violation=1e-9,
                              x=np.array(_atlas_entry()[1]["x"]))  # fmt: skip
    summary = summarize(settings, 0, outcome, ev, "ipopt")
    return save_prediction(make_prediction(ev.prediction_arrays, summary), folder)


def make_campaign(out: Path, source: Path, starts: dict[int, bool], requested: int) -> Path:
    """A campaign folder whose starts are copies of the result folder ``source``, converged or
    not as ``starts`` says, ranked with ``ranking.csv`` and ``best/`` as walk3d campaign does."""
    import shutil

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
