"""Helpers of the verify tests: a prediction without a solve (the shipped atlas's male solution
at 1.3 m/s evaluated over the cycle, about a second) and the OpenSim skip mark."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest

import walk3d.solve.atlas as atlas_module

SPEED = 1.3

needs_opensim = pytest.mark.skipif(
    importlib.util.find_spec("opensim") is None,
    reason="OpenSim's Python package is not installed (pip install 'walk3d[opensim]')",
)


def evaluate_atlas():
    """``(settings, body, evaluation)`` of the shipped male atlas solution at 1.3 m/s."""
    from walk3d.problem.settings import PredictionSettings, body_for
    from walk3d.results.evaluate import evaluate_cycle

    path = Path(atlas_module.__file__).parent / "atlas_data" / "male-natural.json"
    data = json.loads(path.read_text(encoding="utf-8"))
    entry = next(e for e in data["entries"] if abs(e["speed"] - SPEED) < 1e-9)
    settings = PredictionSettings(
        gait={"speed": SPEED, "period": entry["period"],
              "double_support": entry["double_support"]},
        model=data["settings"]["model"],
    )  # fmt: skip
    body = body_for(settings)
    return settings, body, evaluate_cycle(body, settings, np.array(entry["x"]))


def atlas_prediction():
    """``(prediction, body)`` of :func:`evaluate_atlas`, with only its settings as summary."""
    from walk3d.results.evaluate import make_prediction

    settings, body, ev = evaluate_atlas()
    return make_prediction(ev.prediction_arrays, {"settings": settings.model_dump()}), body
