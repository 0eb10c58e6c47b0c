"""The fit's score: each part is its error over the issue's bar, a failed gait scores FAILED."""

import numpy as np
import pytest

from walk3d.validation.compare import Comparison, Row, rmse
from walk3d.validation.quantities import quantity
from walk3d.validation.reference import Reference
from walk3d.validation.score import (
    CAP,
    FAILED,
    SCORED,
    check_scored,
    knee_loading_peak,
    missing_scored,
    score,
    score_json,
)

P = np.linspace(0.0, 100.0, 101)
MEASURED = {
    "angle:knee_flexion": 30 * np.sin(np.pi * P / 100) ** 2 + 5,
    "angle:hip_flexion": 25 * np.cos(2 * np.pi * P / 100),
    "grf:grf_vertical": 9.81 * np.clip(np.sin(np.pi * P / 60), 0, None),
    "moment:knee_flexion": np.sin(2 * np.pi * P / 100),
}
CHECKS = {"looks_like_walking": True, "pelvis_rotation_range_deg": 8.0, "step_width_m": 0.1,
          "roughness_worst": 0.05}  # fmt: skip
SUMMARY = {"converged": True, "gait_checks": CHECKS,
           "descriptors": {"double_support": 0.12, "predicted": []}}  # fmt: skip


def comparison(predicted: dict) -> Comparison:
    ref = Reference("measured", P, dict(MEASURED), {})
    rows = []
    for key, m in MEASURED.items():
        p = predicted[key]
        rows.append(Row(quantity(key), rmse(p, m), float(np.corrcoef(p, m)[0, 1]), "ok",
                        np.nan, None))  # fmt: skip
    return Comparison("p", ref, P, predicted, tuple(rows))


def test_the_measurement_itself_scores_zero():
    s = score(comparison(dict(MEASURED)), SUMMARY)
    assert s.total == pytest.approx(0.0, abs=1e-12)
    assert set(s.parts) >= {"angle:knee_flexion", "knee_loading_peak", "moment:knee_flexion:r",
                            "step_width_m"}  # fmt: skip


def test_each_part_is_its_error_over_its_bar():
    pred = dict(MEASURED) | {"angle:knee_flexion": MEASURED["angle:knee_flexion"] + 3.5}
    s = score(comparison(pred), SUMMARY)
    assert s.parts["angle:knee_flexion"] == pytest.approx(3.5 / 7.0)
    assert s.parts["knee_loading_peak"] == pytest.approx(3.5 / 8.0)
    assert s.figures["knee_loading_peak_deg"] == pytest.approx(
        knee_loading_peak(pred["angle:knee_flexion"])
    )
    assert s.total == pytest.approx(np.mean(list(s.parts.values())))
    wild = dict(MEASURED) | {"grf:grf_vertical": MEASURED["grf:grf_vertical"] + 100.0}
    assert score(comparison(wild), SUMMARY).parts["grf:grf_vertical"] == CAP


def test_guards_count_only_beyond_their_limits():
    wide = SUMMARY | {
        "gait_checks": CHECKS | {"step_width_m": 0.2, "pelvis_rotation_range_deg": 11.9}
    }
    s = score(comparison(dict(MEASURED)), wide)
    assert s.parts["step_width_m"] == pytest.approx(1.0)
    assert s.parts["pelvis_rotation_range_deg"] == 0.0


def test_predicted_double_support_is_scored_against_the_measured():
    pred = SUMMARY | {"descriptors": {"double_support": 0.138, "predicted": ["double_support"]}}
    s = score(comparison(dict(MEASURED)), pred, measured_td=0.12)
    assert s.parts["double_support"] == pytest.approx(0.018 / (0.15 * 0.12))
    assert "double_support" not in score(comparison(dict(MEASURED)), SUMMARY, 0.12).parts


@pytest.mark.parametrize("summary, why", [
    (SUMMARY | {"converged": False, "status": "Maximum_Iterations_Exceeded"}, "converge"),
    (SUMMARY | {"gait_checks": CHECKS | {"looks_like_walking": False}}, "walking"),
])  # fmt: skip
def test_a_gait_that_failed_scores_failed(summary, why):
    s = score(comparison(dict(MEASURED)), summary)
    assert s.total == FAILED and why in s.failed


def test_a_reference_without_a_scored_quantity_makes_the_score_partial():
    s = score(comparison(dict(MEASURED)), SUMMARY)
    assert s.missing == ("angle:ankle_dorsiflexion", "grf:grf_fore_aft",
                         "moment:ankle_dorsiflexion", "moment:hip_flexion")  # fmt: skip
    assert s.partial and score_json(s)["partial"] is True
    assert score_json(s)["missing"] == list(s.missing)
    # negative control: a reference with every scored quantity gives a full score
    full = Reference("measured", P, dict.fromkeys(SCORED, P), {})
    assert missing_scored(full) == ()
    failed = score(Comparison("p", full, P, {}, ()), SUMMARY | {"converged": False})
    assert not failed.partial and not score_json(failed)["partial"]


def test_a_reference_with_no_scored_quantity_is_refused():
    with pytest.raises(ValueError, match="only_pct holds none of the scored quantities"):
        check_scored(Reference("only_pct", P, {"angle:pelvis_tilt": P}, {}))
    check_scored(Reference("one", P, {"grf:grf_vertical": P}, {}))  # one is enough
