"""The work of one start, run inside a (long-lived) Dask worker process.

A task receives only plain data (the settings as a dict, the seed, the solver name and the
``starts`` folder) and calls :func:`walk3d.pipeline.predict`, whose compiled model is cached per
process, so each worker builds the model once and reuses it for every start it runs. The task
writes its own result folder (see :mod:`walk3d.campaign.store`), so a finished start is on disk
even if the client dies; with a remote ``--scheduler`` the workers must therefore see the
campaign folder (shared file system).

Test hooks: the environment variables ``WALK3D_CAMPAIGN_FAIL_SEEDS`` and
``WALK3D_CAMPAIGN_CRASH_SEEDS`` (comma-separated seeds) make the task raise, or kill its
worker process, for those seeds. They are read in the worker, which inherits the environment
of the process that started the local cluster.
"""

from __future__ import annotations

import os
import shutil
import time
import traceback
from pathlib import Path
from typing import Any

from distributed.diagnostics.plugin import WorkerPlugin

from walk3d.campaign import store
from walk3d.io.atomic import temporary_sibling
from walk3d.io.errors import OutputWriteError
from walk3d.model import terms
from walk3d.problem.settings import flat_settings

__all__ = ["ENVIRONMENT", "NUMERICS", "IgnoreInterrupt", "error_record", "failure_kind",
           "record_from_summary", "run_start"]  # fmt: skip

FAIL_ENV = "WALK3D_CAMPAIGN_FAIL_SEEDS"
CRASH_ENV = "WALK3D_CAMPAIGN_CRASH_SEEDS"
CRITERIA = ("C_tor", "C_en")
ENVIRONMENT = "environment"
"""Failure kind of a start stopped by its surroundings (disk, memory, a lost worker): it is
retried when the campaign resumes."""
NUMERICS = "numerics"
"""Failure kind of a start whose solve did not converge or raised in the model or solver: it
stays recorded, as rerunning it gives the same answer."""


def failure_kind(exc: BaseException) -> str:
    """:data:`ENVIRONMENT` for OS, memory and dead-worker errors, else :data:`NUMERICS`."""
    if isinstance(exc, (OSError, MemoryError)) or type(exc).__name__ == "KilledWorker":
        return ENVIRONMENT
    return NUMERICS


class IgnoreInterrupt(WorkerPlugin):
    """Dask worker plugin: the worker processes ignore SIGINT, so that a terminal's Ctrl-C,
    sent to the whole process group, is handled by the campaign's main process alone (it stops
    the cluster) instead of printing a traceback from every worker."""

    name = "walk3d-ignore-sigint"

    def setup(self, worker: object) -> None:
        import signal
        import threading

        if threading.current_thread() is threading.main_thread():
            signal.signal(signal.SIGINT, signal.SIG_IGN)


class RegisterTerms(WorkerPlugin):
    """Dask worker plugin: registers the campaign process's user criterion terms
    (:func:`walk3d.model.terms.user_terms`) in each worker, which solves with them."""

    name = "walk3d-terms"

    def __init__(self, user_terms: tuple[terms.Term, ...]) -> None:
        self.user_terms = user_terms

    def setup(self, worker: object) -> None:
        for term in self.user_terms:
            terms.register(term, replace=True)


def _env_seeds(name: str) -> set[int]:
    return {int(s) for s in os.environ.get(name, "").replace(" ", "").split(",") if s}


def _test_hooks(seed: int) -> None:
    if seed in _env_seeds(CRASH_ENV):
        os._exit(70)
    if seed in _env_seeds(FAIL_ENV):
        raise RuntimeError(f"injected failure for seed {seed} ({FAIL_ENV})")


def one_line(exc: BaseException, limit: int = 300) -> str:
    """``Type: message`` of an exception on one line, at most ``limit`` characters."""
    text = " ".join(f"{type(exc).__name__}: {exc}".split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _split(value: Any) -> dict[str, float | None]:
    value = value if isinstance(value, dict) else {}
    return {k: value.get(k) for k in ("total", "x", "y", "z")}


def record_from_summary(summary: dict, criterion: str, task_time_s: float) -> dict:
    """The campaign record of a finished prediction (from its ``summary.json`` dict)."""
    objective = summary.get("objective") or {}
    value = terms.minimized(objective, criterion)
    walked = (summary.get("descriptors") or {}).get("predicted") and summary["descriptors"]
    if walked and isinstance(value, (int, float)):  # per metre: starts differ in their period
        value = value / walked["stride_length"]
    record = {
        "seed": int(summary["seed"]),
        "status": str(summary.get("status")),
        "converged": bool(summary.get("converged")),
        "failure": "" if summary.get("converged") else NUMERICS,
        "criterion": criterion,
        "criterion_value": value,
        "iterations": summary.get("iterations"),
        "wall_time_s": summary.get("wall_time_s"),
        "task_time_s": round(task_time_s, 3),
        "max_constraint_violation": summary.get("max_constraint_violation"),
        "solver": summary.get("method", (summary.get("inputs") or {}).get("solver")),
        "looks_like_walking": (summary.get("gait_checks") or {}).get("looks_like_walking"),
    }
    for key in CRITERIA:
        record[key] = _split(objective.get(key))
    return store.clean_json(record)


def error_record(
    seed: int, criterion: str, message: str, task_time_s: float | None, failure: str = NUMERICS
) -> dict:
    """The record of a start that raised or whose worker died (never converged)."""
    return {
        "seed": seed,
        "status": f"error: {message}",
        "converged": False,
        "failure": failure,
        "criterion": criterion,
        "criterion_value": None,
        "iterations": None,
        "wall_time_s": None,
        "task_time_s": None if task_time_s is None else round(task_time_s, 3),
        "max_constraint_violation": None,
        "solver": None,
        **{key: _split(None) for key in CRITERIA},
    }


def write_error(
    starts_dir: str | Path,
    seed: int,
    criterion: str,
    exc: BaseException,
    task_time_s: float | None = None,
    tb: str | None = None,
) -> dict:
    """Write a record-only folder for a start that failed with ``exc``; returns the record.

    A dead worker (Dask's ``KilledWorker``) gets a short fixed message. Raises ``OSError``
    when even the record cannot be written (the start then stays pending).
    """
    if type(exc).__name__ == "KilledWorker":
        message = "KilledWorker: the worker process died while running this start"
    else:
        message = one_line(exc)
    tmp = store.new_temporary(Path(starts_dir), store.start_name(seed))
    if tb:
        (tmp / "traceback.txt").write_text(tb, encoding="utf-8")
    record = error_record(seed, criterion, message, task_time_s, failure_kind(exc))
    return store.commit_start(tmp, seed, record)


def run_start(settings_dict: dict, seed: int, solver: str, starts_dir: str) -> dict | None:
    """Run one start and store it under ``starts_dir``; returns its record, or None when its
    result could not be written (a full disk: the start stays pending, for a rerun).

    Never raises for a failing prediction: an exception becomes an ``error: ...`` record.
    A start already stored (e.g. a retried task) is not run again.
    """
    root = Path(starts_dir)
    existing = store.read_record(root / store.start_name(seed))
    if existing is not None:
        return existing
    criterion = str(flat_settings(settings_dict).get("criterion", "tor"))
    t0 = time.perf_counter()
    tmp = temporary_sibling(root, store.start_name(seed))  # predict builds it atomically
    try:
        from walk3d import pipeline as predict_module
        from walk3d.problem.settings import PredictionSettings

        _test_hooks(seed)
        settings = PredictionSettings(**settings_dict)
        pred = predict_module.predict(settings, seed, solver, out_dir=tmp)
        record = record_from_summary(pred.summary, criterion, time.perf_counter() - t0)
    except OutputWriteError:  # not a failed start: its folder did not fit
        shutil.rmtree(tmp, ignore_errors=True)
        return None
    except Exception as exc:
        shutil.rmtree(tmp, ignore_errors=True)
        return write_error(root, seed, criterion, exc, time.perf_counter() - t0,
                           traceback.format_exc())  # fmt: skip
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return store.commit_start(tmp, seed, record)
