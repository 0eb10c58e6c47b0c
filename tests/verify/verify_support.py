"""Helpers of the verify tests: predictions without a solve (the shipped atlas's male solution
at 1.3 m/s, and a solved handover prediction kept in ``data/``, each evaluated over the cycle in
about a second) and the OpenSim skip mark."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest
from result_support import SPEED, evaluate_atlas  # noqa: F401 - the shared atlas solution

needs_opensim = pytest.mark.skipif(
    importlib.util.find_spec("opensim") is None,
    reason="OpenSim's Python package is not installed (pip install 'walk3d[opensim]')",
)


def atlas_prediction():
    """``(prediction, body)`` of :func:`evaluate_atlas`, with only its settings as summary."""
    from walk3d.results.evaluate import make_prediction

    settings, body, ev = evaluate_atlas()
    return make_prediction(ev.prediction_arrays, {"settings": settings.model_dump()}), body


HANDOVER_FILE = Path(__file__).parent / "data" / "handover_male_1.300.json"
"""The coefficients and settings of ``walk3d predict --speed 1.3 --period 1.1296
--double-support 0.131`` (converged, with the handover): the default ``walk3d predict --speed
1.3``'s cycle, whose predicted T and Td these are (walk3d.solve.landing)."""


def handover_prediction(handover: bool = True):
    """``(prediction, body)`` of :data:`HANDOVER_FILE` evaluated with or without its handover
    (without: the same coefficients with the root switched at heel strike, the control)."""
    from walk3d.problem.settings import PredictionSettings, body_for
    from walk3d.results.evaluate import evaluate_cycle, make_prediction

    data = json.loads(HANDOVER_FILE.read_text(encoding="utf-8"))
    settings = PredictionSettings(gait=data["gait"], model={**data["model"], "handover": handover})
    body = body_for(settings)
    ev = evaluate_cycle(body, settings, np.array(data["x"]))
    return make_prediction(ev.prediction_arrays, {"settings": settings.model_dump()}), body
