"""Report fixtures without a solve (tests/report/report_support.py): the atlas solution saved
as a result folder with walk3d predict's summary."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from report_support import evaluate_atlas, make_prediction


@pytest.fixture(scope="session")
def evaluated():
    """``(settings, body, evaluation)`` of the atlas solution."""
    return evaluate_atlas()


@pytest.fixture(scope="session")
def result_folder(evaluated, tmp_path_factory):
    """A converged-looking result folder (no report, no video)."""
    from walk3d.results.prediction import save_prediction

    settings, body, ev = evaluated
    pred = make_prediction(settings, ev, converged=True)
    return save_prediction(pred, tmp_path_factory.mktemp("report") / "v_1.300", body=body)


@pytest.fixture()
def fresh_folder(result_folder, tmp_path):
    """A private copy of :func:`result_folder` that a test may change."""
    return Path(shutil.copytree(result_folder, tmp_path / result_folder.name))
