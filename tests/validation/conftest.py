"""Fixtures for the validation tests: the shared lab data and a cheap synthetic prediction."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers import random_decision, shared_data_dir

from walk3d.body.model import build_body
from walk3d.problem.settings import PredictionSettings
from walk3d.results.evaluate import evaluate_cycle, make_prediction


@pytest.fixture(scope="session")
def falisse() -> Path:
    """The Falisse et al. 2019 folder; skips when the shared data is absent."""
    folder = shared_data_dir() / "falisse2019"
    if not (folder / "cycle_right_leg_mean_sd.csv").is_file():
        pytest.skip(f"measured data not found at {folder} (set WALK3D_SHARED_DATA)")
    return folder


@pytest.fixture(scope="session")
def subject01() -> Path:
    folder = shared_data_dir() / "opensim_subject01"
    if not (folder / "subject01_walk1_grf.mot").is_file():
        pytest.skip(f"measured data not found at {folder} (set WALK3D_SHARED_DATA)")
    return folder


@pytest.fixture(scope="session")
def winter() -> Path:
    path = shared_data_dir() / "winter" / "Winter_normal.csv"
    if not path.is_file():
        pytest.skip(f"measured data not found at {path} (set WALK3D_SHARED_DATA)")
    return path


@pytest.fixture(scope="session")
def synthetic_prediction():
    """A full cycle of a smooth random motion (no optimization), as a Prediction."""
    settings = PredictionSettings()
    body = build_body()
    x = random_decision(5)
    ev = evaluate_cycle(body, settings, x)
    summary = {"settings": settings.model_dump(), "objective": ev.criteria}
    return make_prediction(ev.prediction_arrays, summary)


@pytest.fixture(scope="module")
def pred_dir(synthetic_prediction, tmp_path_factory):
    """The synthetic prediction saved as a result folder, once per test module."""
    from walk3d.results.prediction import save_prediction

    return save_prediction(synthetic_prediction, tmp_path_factory.mktemp("pred") / "p")
