"""The default prediction, solved with the handover (the root passed between the feet over double
support), passes every bar of ``walk3d verify`` over the whole cycle; the same coefficients with
the root switched at heel strike do not (skipped without OpenSim)."""

from __future__ import annotations

import pytest
from verify_support import handover_prediction, needs_opensim

from walk3d.results.prediction import save_prediction
from walk3d.verify.compare import BARS
from walk3d.verify.run import verify_folder

pytestmark = needs_opensim


@pytest.fixture(scope="module")
def checked(tmp_path_factory):
    """``{handover: Verification}`` for the stored solution with and without its handover."""
    out = {}
    for handover in (True, False):
        pred, _ = handover_prediction(handover)
        folder = save_prediction(pred, tmp_path_factory.mktemp("handover") / f"h{int(handover)}")
        out[handover] = verify_folder(folder)
    return out


def test_the_handover_prediction_meets_every_bar_over_the_whole_cycle(checked):
    v = checked[True]
    assert v.passes(BARS)
    for row in v.whole.moments:  # r >= 0.99, RMSE <= 2 % of peak: met by far
        assert row.r > 0.9999 and row.rmse_pct_peak < 0.2, row
    assert max(r.peak_pct_bw for r in v.whole.residuals) < 0.5
    assert max(v.drift_m.values()) < 1e-3


def test_the_same_motion_with_the_root_switched_at_heel_strike_fails_the_residual_bar(checked):
    v = checked[False]
    assert not v.passes(BARS)
    assert max(r.peak_pct_bw for r in v.whole.residuals) > 10.0
