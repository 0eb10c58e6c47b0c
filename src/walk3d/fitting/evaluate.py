"""One evaluation of a fit: predict one trial with one criterion and score it.

Runs inside a Dask worker (:mod:`walk3d.fitting.search`) and receives only plain data. It
writes its record, ``evaluations/<key>.json``, atomically before returning, so a finished
evaluation survives the client; a record already there is returned without solving.
"""

from __future__ import annotations

import hashlib
import time
import traceback
from pathlib import Path
from typing import Literal

from walk3d.campaign.store import clean_json, write_json
from walk3d.fitting.trials import FitTrial
from walk3d.io.checks import read_json_object
from walk3d.problem.settings import PredictionSettings
from walk3d.validation.score import FAILED

__all__ = [
    "MODES",
    "evaluate",
    "evaluation_key",
    "split_candidate",
    "trial_descriptors",
    "trial_settings",
]

MODES = ("given", "predicted")
"""How a trial's T and Td reach the prediction: the measured ones given, or predicted."""
Mode = Literal["given", "predicted"]


def split_candidate(candidate: str) -> tuple[str, dict[str, float]]:
    """The criterion and the model options of a candidate, ``criterion`` or
    ``criterion|name=value,...`` (:func:`walk3d.fitting.search.candidate_of`)."""
    criterion, _, tail = candidate.partition("|")
    options = dict(item.split("=", 1) for item in tail.split(",")) if tail else {}
    return criterion, {k: float(v) for k, v in options.items()}


def evaluation_key(criterion: str, trial: str, mode: str) -> str:
    """File stem of one evaluation: a digest of the candidate (the canonical criterion, and its
    model options if any), the trial, the mode."""
    digest = hashlib.sha256(criterion.encode()).hexdigest()[:12]
    return f"{digest}-{trial}-{mode}"


def trial_descriptors(trial: FitTrial) -> tuple[float, float, float]:
    """``(V, T, Td)`` of a trial (m/s, s, s): its table's, else read from its IK and GRF."""
    if trial.ik is None or trial.grf is None:
        return float(trial.speed), float(trial.period), float(trial.double_support)  # type: ignore[arg-type]
    from walk3d.trials.descriptors import descriptors_from_trial

    d = descriptors_from_trial(trial.ik, trial.grf, speed=trial.speed)
    return d.speed, d.period, d.double_support


def trial_settings(
    trial: FitTrial,
    criterion: str,
    mode: Mode,
    descriptors: tuple[float, float, float] | None = None,
) -> PredictionSettings:
    """The prediction of ``trial`` under ``criterion`` (a candidate: the canonical criterion
    and its model options, :func:`split_candidate`), with the measured T and Td (``given``) or
    both predicted; one thread, as the workers run side by side. ``descriptors``: the trial's
    :func:`trial_descriptors`, when already read."""
    from walk3d.problem.descriptors import auto_descriptors

    speed, period, td = descriptors or trial_descriptors(trial)
    given = (period, td) if mode == "given" else (None, None)
    t, d, free = auto_descriptors(speed, trial.height, *given)
    weights, options = split_candidate(criterion)
    return PredictionSettings(speed=speed, period=t, double_support=d, free=free,
                              mass=trial.mass, height=trial.height, sex=trial.sex,
                              criterion=weights, threads=1, **options)  # fmt: skip


def evaluate(
    trial_data: dict,
    criterion: str,
    mode: Mode,
    records_dir: str,
    *,
    seed: int = 0,
    solver: str = "ipopt",
    result_dir: str | None = None,
) -> dict:
    """Predict and score one trial (``trial_data``: a :class:`FitTrial` dump); its record.
    ``result_dir``: also write the prediction's result folder there. Never raises for a failing
    prediction: the record then has ``score`` :data:`FAILED` and the reason."""
    trial = FitTrial(**trial_data)
    path = Path(records_dir) / f"{evaluation_key(criterion, trial.name, mode)}.json"
    if path.exists() and result_dir is None:
        try:
            return read_json_object(path)
        except Exception:  # a damaged record is evaluated again
            path.unlink(missing_ok=True)
    record = {"criterion": criterion, "trial": trial.name, "mode": mode, "seed": seed}
    t0 = time.perf_counter()
    try:
        from walk3d.pipeline import predict
        from walk3d.validation.compare import compare
        from walk3d.validation.run import load_references
        from walk3d.validation.score import score

        measured = trial_descriptors(trial)
        settings = trial_settings(trial, criterion, mode, measured)
        pred = predict(settings, seed, solver, out_dir=result_dir)
        reference = load_references(trial.reference, trial.mass, speed=trial.reference_speed)[0]
        result = score(compare(pred, reference, trial.name), pred.summary, measured[2])
        record |= {"score": result.total, "parts": result.parts,
                   "figures": result.figures, "failed": result.failed,
                   "converged": bool(pred.summary.get("converged")),
                   "iterations": pred.summary.get("iterations"),
                   "descriptors": pred.summary.get("descriptors")}  # fmt: skip
    except Exception as exc:
        line = " ".join(f"{type(exc).__name__}: {exc}".split())[:300]
        record |= {"score": FAILED, "failed": line, "traceback": traceback.format_exc()[-2000:]}
    finally:
        from walk3d.solve.solver import forget_solvers

        forget_solvers()  # each criterion builds its own solver, hundreds of MB
    record["wall_time_s"] = time.perf_counter() - t0
    write_json(path, record)  # non-finite figures as null
    return clean_json(record)
