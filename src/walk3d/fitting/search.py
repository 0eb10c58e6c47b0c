"""Fit criterion weights to measured trials with CMA-ES, resumable, on Dask workers.

Why CMA-ES (the ``cma`` package): the score of a weighting is a whole prediction per trial,
noisy in the sense that a solve may land on another local optimum, and has no derivative;
CMA-ES is the standard for such black boxes of 3–10 parameters, is invariant to the
parameters' scale, and evaluates a generation's candidates side by side, which the workers
need. A weight is searched on a log scale, in ``[low, high]`` mapped to ``[0, 1]``; a model
option (:data:`OPTION_RANGES`) on a linear one. A candidate is the canonical criterion, plus
``|name=value,...`` when it sets model options (:func:`candidate_of`).

A fit folder ``DIR`` holds:

* ``fit.json``: what is fitted (trials, parameters, base criterion, modes, seed, population),
  written once; a resume with other settings is refused (:class:`FitMismatch`);
* ``evaluations/<key>.json``: one record per (criterion, trial, mode)
  (:mod:`walk3d.fitting.evaluate`), reused by any later generation or resume;
* ``generations/g<NNN>.json``: the candidates a generation asked for and their scores; a
  resume tells CMA-ES the stored generations again, in order, and goes on from there;
* at the end ``criterion.toml`` (the best weights, and the model options in ``[model]``, for
  ``walk3d predict --criterion``),
  ``fit.csv`` (every candidate) and ``result.json`` (start and best, per trial, held out too).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from walk3d.decimals import decimal
from walk3d.fitting.evaluate import evaluate, evaluation_key
from walk3d.fitting.trials import FitTrial
from walk3d.io.checks import read_json_object
from walk3d.model import terms

__all__ = [
    "OPTION_RANGES",
    "SIGMA0",
    "FitMismatch",
    "Parameter",
    "candidate_of",
    "criterion_of",
    "parameter",
    "values_of",
    "weights_of",
]

SIGMA0 = 0.25
"""CMA-ES's first step in the unit box: a quarter of each weight's log range."""
SPAN = 10.0
"""Default range of a weight: the preset's weight divided and multiplied by this."""
EMPTY_START = 1.0
"""Start of a weight the base criterion does not hold (its range: ``/SPAN`` to ``*SPAN``)."""


OPTION_RANGES = {"heel_rise": (0.3, 1.0, 0.6), "load_ramp": (0.0, 3.0, 1.0)}
"""``(low, high, start)`` of each model option a fit can choose
(:data:`walk3d.io.criterion.MODEL_OPTIONS`): the settings' own ranges; the starts are the
measured heel-off at 0.6 of stance and a ramp of slope 1, halfway between the paper's flat
start (0) and a linear one (2)."""


class FitMismatch(ValueError):
    """The folder holds a fit of other trials, parameters or settings."""


@dataclass(frozen=True)
class Parameter:
    """One fitted value: a criterion term's weight, searched log-uniformly in ``[low, high]``,
    or a model option's (``kind`` ``option``), searched uniformly."""

    name: str
    low: float
    high: float
    start: float
    kind: str = "weight"

    def to_unit(self, value: float) -> float:
        if self.kind == "option":
            return (value - self.low) / (self.high - self.low)
        return math.log(value / self.low) / math.log(self.high / self.low)

    def from_unit(self, u: float) -> float:
        u = float(np.clip(u, 0.0, 1.0))
        if self.kind == "option":
            return self.low + (self.high - self.low) * u
        return self.low * (self.high / self.low) ** u


def parameter(text: str, base: str) -> Parameter:
    """``term`` or ``term=low:high`` (weights) as a Parameter that starts at the ``base``
    criterion's weight. ValueError (one line) for an unknown term, a base of the paper's or a
    range that is not ``0 < low < start < high``."""
    name, eq, span = text.strip().partition("=")
    name = name.strip()
    if name in OPTION_RANGES:
        return _option(text, name, eq, span)
    if name in terms.BASES:
        raise ValueError(
            f"--parameter {name}: the base criterion's weight is the scale, not fitted"
        )
    if name not in terms.names():
        raise ValueError(
            f"--parameter {name!r} is not a criterion term ({', '.join(terms.names())}) or a "
            f"model option ({', '.join(OPTION_RANGES)})"
        )
    start = terms.parse(base).get(name) or EMPTY_START
    low, high = _span(text, span, "impact=0.5:20") if eq else (start / SPAN, start * SPAN)
    if not (0 < low < high < math.inf) or not (low <= start <= high):
        raise ValueError(f"--parameter {text!r}: need 0 < low <= start ({start:g}) <= high")
    return Parameter(name, low, high, start)


def _span(text: str, span: str, example: str) -> tuple[float, float]:
    """``low:high`` of a ``--parameter`` as plain decimals (``float`` would read 1_0 as 10);
    ValueError (one line) for anything else."""
    bounds = [decimal(v) for v in span.split(":")] if span.strip() else []
    if len(bounds) != 2 or any(math.isnan(b) for b in bounds):
        raise ValueError(f"--parameter {text!r}: the range is low:high, e.g. {example}")
    return bounds[0], bounds[1]


def _option(text: str, name: str, eq: str, span: str) -> Parameter:
    """``option`` or ``option=low:high`` within its :data:`OPTION_RANGES`."""
    low, high, start = OPTION_RANGES[name]
    if eq:
        bounds = _span(text, span, f"{name}=0.4:0.8")
        if not (low <= bounds[0] < bounds[1] <= high):
            raise ValueError(f"--parameter {text!r}: need {low:g} <= low < high <= {high:g}")
        low, high = bounds
        start = min(max(start, low), high)
    return Parameter(name, low, high, start, "option")


def values_of(params: Sequence[Parameter], u: Sequence[float]) -> dict[str, float]:
    """The weights and options at the unit-box point ``u``, rounded to 4 significant digits."""
    return {p.name: float(f"{p.from_unit(x):.4g}") for p, x in zip(params, u, strict=True)}


def weights_of(params: Sequence[Parameter], u: Sequence[float]) -> dict[str, float]:
    """The weights (not the model options) at ``u`` (:func:`values_of`)."""
    values = values_of(params, u)
    return {p.name: values[p.name] for p in params if p.kind == "weight"}


def criterion_of(base: str, params: Sequence[Parameter], u: Sequence[float]) -> str:
    """The canonical criterion: ``base`` with the weights at ``u`` in place."""
    weights = terms.parse(base) | weights_of(params, u)
    return terms.canonical(",".join(f"{k}={v:.17g}" for k, v in weights.items()))


def candidate_of(base: str, params: Sequence[Parameter], u: Sequence[float]) -> str:
    """The candidate at ``u``: :func:`criterion_of`, then ``|name=value,...`` for the model
    options (in name order), if any are fitted."""
    values = values_of(params, u)
    options = sorted((p.name, values[p.name]) for p in params if p.kind == "option")
    tail = ",".join(f"{k}={v:.17g}" for k, v in options)
    return criterion_of(base, params, u) + (f"|{tail}" if tail else "")


@dataclass
class Evaluations:
    """Runs evaluations on a Dask client, reusing stored records."""

    client: object
    records_dir: Path
    seed: int
    on_done: Callable[[dict], None] | None = None

    def run(self, jobs: list[tuple[str, FitTrial, str]]) -> dict[tuple[str, str, str], dict]:
        """Records of ``(criterion, trial, mode)`` jobs; stored ones are read, not solved."""
        from distributed import as_completed

        out: dict[tuple[str, str, str], dict] = {}
        futures = {}
        for criterion, trial, mode in jobs:
            key = (criterion, trial.name, mode)
            path = self.records_dir / f"{evaluation_key(*key)}.json"
            if key in out or key in futures.values():
                continue
            try:
                out[key] = read_json_object(path)
                continue
            except Exception:
                pass
            fut = self.client.submit(evaluate, trial.model_dump(mode="json"), criterion, mode,
                                     str(self.records_dir.resolve()), seed=self.seed,
                                     pure=False)  # fmt: skip
            futures[fut] = key
        for fut in as_completed(futures):
            out[futures[fut]] = record = fut.result()
            if self.on_done:
                self.on_done(record)
            fut.release()
        return out
