"""A prediction without a solve (tests/verify/verify_support.py's atlas solution at 1.3 m/s),
saved as a result folder, for the animation tests."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "verify"))


@pytest.fixture(scope="session")
def atlas_result(tmp_path_factory):
    """``(prediction, body, folder)``."""
    from verify_support import atlas_prediction

    from walk3d.results.prediction import save_prediction

    pred, body = atlas_prediction()
    folder = save_prediction(pred, tmp_path_factory.mktemp("anim") / "v_1.300", body=body)
    return pred, body, folder
