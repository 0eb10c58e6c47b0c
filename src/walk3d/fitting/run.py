"""``walk3d fit-criterion``: the CMA-ES loop over stored generations (:mod:`.search`)."""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from walk3d.fitting.evaluate import MODES, split_candidate
from walk3d.fitting.search import (
    SIGMA0,
    Evaluations,
    FitMismatch,
    Parameter,
    candidate_of,
    values_of,
)
from walk3d.fitting.trials import FitTrial
from walk3d.io.atomic import atomic_write_text
from walk3d.io.checks import read_json_object
from walk3d.io.criterion import write_criterion
from walk3d.io.tables import write_csv_table
from walk3d.model import terms

__all__ = ["FitResult", "fit_criterion"]

FIT_MARK = "fit.json"
"""The file every fit folder holds."""


@dataclass
class FitResult:
    """The start and the best criterion, their mean scores and per-trial records."""

    start: str
    best: str
    start_score: float
    best_score: float
    generations: int
    per_trial: dict[str, dict[str, float]] = field(default_factory=dict)
    """``{"start" | "best": {"<trial>/<mode>": score}}``, held-out trials included."""
    held_out: tuple[str, ...] = ()
    files: dict[str, Path] = field(default_factory=dict)


def _identity(trials, params, base, modes, seed, popsize, held_out) -> dict:
    return {"trials": [t.model_dump(mode="json") for t in trials],
            "parameters": [_stored(p) for p in params], "base": terms.canonical(base),
            "modes": list(modes), "seed": seed, "popsize": popsize,
            "held_out": sorted(held_out)}  # fmt: skip


def _stored(p: Parameter) -> dict:
    """A parameter as ``fit.json`` holds it (a weight without its kind, as before options)."""
    return {k: v for k, v in p.__dict__.items() if not (k == "kind" and v == "weight")}


def _open(out: Path, identity: dict) -> None:
    mark = out / FIT_MARK
    identity = json.loads(json.dumps(identity))  # as stored: tuples as lists
    if mark.exists():
        stored = read_json_object(mark)
        stored.pop("walk3d", None)
        if stored != identity:
            diff = [k for k in identity if stored.get(k) != identity[k]]
            raise FitMismatch(f"{out} holds a fit with other {', '.join(diff) or 'settings'}; "
                              "choose another --out")  # fmt: skip
        return
    if out.exists() and any(out.iterdir()):
        raise FitMismatch(f"{out} is a folder of other files; choose another --out")
    (out / "evaluations").mkdir(parents=True, exist_ok=True)
    (out / "generations").mkdir(exist_ok=True)
    atomic_write_text(mark, json.dumps(identity, indent=1, sort_keys=True) + "\n")


def _mean(records: dict, criterion: str, trials: Sequence[FitTrial], modes) -> float:
    return float(np.mean([records[(criterion, t.name, m)]["score"] for t in trials for m in modes]))


def fit_criterion(
    trials: Sequence[FitTrial],
    params: Sequence[Parameter],
    out: str | Path,
    *,
    base: str = terms.DEFAULT_PRESET,
    generations: int = 6,
    popsize: int = 8,
    seed: int = 0,
    modes: Sequence[str] = ("given",),
    held_out: Sequence[str] = (),
    workers: int | None = None,
    scheduler: str | None = None,
    on_progress: Callable[[int, int, str], None] | None = None,
) -> FitResult:
    """Fit ``params`` (weights of ``base``) to the trials not ``held_out`` (module doc of
    :mod:`.search`); score the held-out ones with the start and the best. ``modes``: ``given``
    and/or ``predicted`` T and Td. Resumes a fit folder of the same identity. ValueError (one
    line) for bad arguments, before any solve."""
    import cma

    from walk3d.campaign.runner import dask_client

    names = [t.name for t in trials]
    unknown = sorted(set(held_out) - set(names))
    if unknown:
        raise ValueError(f"--hold-out {unknown[0]!r} is not a trial ({', '.join(names)})")
    fit_on = [t for t in trials if t.name not in held_out]
    kept = [t for t in trials if t.name in held_out]
    if not fit_on:
        raise ValueError("every trial is held out: nothing to fit on")
    if not params:
        raise ValueError("no --parameter to fit")
    if len({p.name for p in params}) != len(params):
        raise ValueError("a --parameter is given twice")
    if not set(modes) <= set(MODES) or not modes:
        raise ValueError(f"--descriptors must be among {', '.join(MODES)}")
    if generations < 1 or popsize < 2:
        raise ValueError("--generations must be ≥ 1 and --popsize ≥ 2")
    out = Path(out)
    _open(out, _identity(trials, params, base, modes, seed, popsize, held_out))

    u0 = [p.to_unit(p.start) for p in params]
    start = candidate_of(base, params, u0)
    total = (2 * len(trials) + generations * popsize * len(fit_on)) * len(modes)
    done = [0]

    def advance(record: dict) -> None:
        done[0] += 1
        if on_progress:
            on_progress(done[0], total, f"{record['trial']}/{record['mode']} "
                                        f"score {record['score']:.3f}")  # fmt: skip

    # one parameter: no bounds (cma's bound transform fails in one dimension at the second
    # tell); the unit values are clipped to [0, 1] where they become weights or options
    bounds = {"bounds": [0, 1]} if len(params) > 1 else {}
    es = cma.CMAEvolutionStrategy(u0, SIGMA0, {"seed": seed + 1, "popsize": popsize,
                                               "verbose": -9, **bounds})  # fmt: skip
    rows: list[dict] = []
    with dask_client(workers, scheduler, popsize * len(fit_on) * len(modes)) as client:
        ev = Evaluations(client, out / "evaluations", seed, advance)
        jobs = [(start, t, m) for t in trials for m in modes]
        records = ev.run(jobs)
        scores = {start: _mean(records, start, fit_on, modes)}
        for g in range(generations):
            gen_file = out / "generations" / f"g{g:03d}.json"
            asked = [list(map(float, x)) for x in es.ask()]
            stored = read_json_object(gen_file) if gen_file.exists() else None
            x = stored["x"] if stored and len(stored.get("x", [])) == popsize else asked
            crits = [candidate_of(base, params, u) for u in x]
            atomic_write_text(gen_file, json.dumps({"x": x, "criteria": crits}, indent=1) + "\n")
            records |= ev.run([(c, t, m) for c in crits for t in fit_on for m in modes])
            f = [_mean(records, c, fit_on, modes) for c in crits]
            es.tell([np.asarray(u) for u in x], f)
            atomic_write_text(gen_file, json.dumps({"x": x, "criteria": crits, "scores": f},
                                                   indent=1) + "\n")  # fmt: skip
            for i, (u, c, s) in enumerate(zip(x, crits, f, strict=True)):
                scores[c] = s
                rows.append(
                    {
                        "generation": g,
                        "candidate": i,
                        "score": s,
                        "criterion": c,
                        **values_of(params, u),
                    }
                )
        best = min(scores, key=scores.get)
        records |= ev.run([(best, t, m) for t in trials for m in modes])

    per = {label: {f"{t.name}/{m}": records[(c, t.name, m)]["score"]
                   for t in trials for m in modes}
           for label, c in (("start", start), ("best", best))}  # fmt: skip
    result = FitResult(start, best, scores[start], scores[best], generations, per,
                       tuple(t.name for t in kept))  # fmt: skip
    result.files = _write_outputs(out, result, params, rows, fit_on)
    return result


def _write_outputs(out: Path, result: FitResult, params, rows, fit_on) -> dict[str, Path]:
    criterion, options = split_candidate(result.best)
    weights = terms.parse(criterion)
    notes = [f"walk3d fit-criterion: fitted {', '.join(p.name for p in params)} on "
             f"{', '.join(t.name for t in fit_on)}",
             f"mean score {result.best_score:.4f} (start {result.start_score:.4f}; lower is "
             "better, 1 = at the bar)"]  # fmt: skip
    if result.held_out:
        notes.append(f"held out: {', '.join(result.held_out)}")
    files = {"criterion": write_criterion(out / "criterion.toml", weights, notes, options)}
    if rows:
        files["table"] = write_csv_table(out / "fit.csv", tuple(rows[0]), rows)
    summary = {"start": result.start, "best": result.best, "start_score": result.start_score,
               "best_score": result.best_score, "generations": result.generations,
               "per_trial": result.per_trial, "held_out": list(result.held_out)}  # fmt: skip
    atomic_write_text(out / "result.json", json.dumps(summary, indent=1, sort_keys=True) + "\n")
    files["result"] = out / "result.json"
    return files
