"""Which results are labelled as not a valid walking prediction: only a recorded ``true`` is
converged; a solve that did not converge, or a gait that does not walk, has a reason."""

from __future__ import annotations

import pytest

from walk3d.results.labels import did_not_converge, invalid_reason, is_converged
from walk3d.validation.score import FAILED, score

WALKING = {"gait_checks": {"looks_like_walking": True}}


@pytest.mark.parametrize("value", [False, "no", "yes", 1, None, [True]])
def test_only_true_is_converged(value):
    summary = {"converged": value, "status": "Maximum_Iterations_Exceeded", **WALKING}
    assert not is_converged(summary) and did_not_converge(summary)
    assert "did not converge (Maximum_Iterations_Exceeded)" in invalid_reason(summary)


def test_a_converged_walking_result_has_no_label():
    """Negative control of the labels above and below."""
    summary = {"converged": True, **WALKING}
    assert is_converged(summary) and not did_not_converge(summary)
    assert invalid_reason(summary) is None


def test_a_result_without_a_solve_is_not_labelled_as_failed():
    assert not is_converged({}) and not did_not_converge({}) and invalid_reason({}) is None


def test_a_converged_gait_that_does_not_walk_has_its_reason():
    summary = {"converged": True, "gait_checks": {"looks_like_walking": False}}
    assert "does not look like walking" in invalid_reason(summary)


def test_the_score_fails_a_summary_whose_converged_is_not_true(synthetic_comparison):
    """``{"converged": "no"}`` was scored as converged."""
    failed = score(synthetic_comparison, {"converged": "no", "status": "x", **WALKING})
    assert failed.total == FAILED and "did not converge" in failed.failed
    scored = score(synthetic_comparison, {"converged": True, **WALKING})  # negative control
    assert scored.failed is None


@pytest.fixture(scope="module")
def synthetic_comparison():
    import sys
    from pathlib import Path

    import numpy as np

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "verify"))
    from verify_support import atlas_prediction

    from walk3d.validation.compare import align_prediction, compare
    from walk3d.validation.reference import Reference

    pred, _ = atlas_prediction()
    percent, series = align_prediction(pred)
    return compare(pred, Reference("self", percent, series,
                                   {k: np.zeros_like(v) for k, v in series.items()}))  # fmt: skip
