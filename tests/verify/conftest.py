"""A saved prediction without a solve: the shipped atlas's male solution at 1.3 m/s, written by
save_prediction."""

from __future__ import annotations

import pytest
from verify_support import atlas_prediction


@pytest.fixture(scope="session")
def saved_atlas_prediction(tmp_path_factory):
    """``(prediction, body, folder)``."""
    from walk3d.results.prediction import save_prediction

    pred, body = atlas_prediction()
    folder = save_prediction(pred, tmp_path_factory.mktemp("atlas") / "v_1.300")
    return pred, body, folder
