"""Full-cycle evaluation of any decision vector obeys Newton's law and the gait's structure."""

import numpy as np
import pytest
from helpers import random_decision

from walk3d import G
from walk3d.body.model import build_body
from walk3d.contact.phases import GaitPhases
from walk3d.problem.settings import PredictionSettings
from walk3d.results.evaluate import evaluate_cycle


@pytest.fixture(scope="module")
def cycle():
    s = PredictionSettings(handover=False)  # random coefficients: the paper's root switch
    body = build_body()
    x = random_decision(11)
    return s, body, x, evaluate_cycle(body, s, x, n_samples=2161)


def _momentum_residual(a: dict) -> tuple[np.ndarray, np.ndarray]:
    """``(t, total ground reaction − (Σ m a + M g))`` at the inner samples of the prediction
    arrays ``a``, s and N (segment accelerations by central differences)."""
    t, com = a["time"], a["segment_com_position"]
    dt = t[1] - t[0]
    acc = (com[2:] - 2 * com[1:-1] + com[:-2]) / dt**2
    mass = a["segment_mass"]
    expected = np.einsum("s,nsk->nk", mass, acc) + np.array([0, mass.sum() * G, 0])
    return t[1:-1], a["grf_force"].sum(axis=1)[1:-1] - expected


def test_ground_reaction_equals_momentum_rate_of_the_segments(cycle):
    s, body, _, ev = cycle
    tm, residual = _momentum_residual(ev.prediction_arrays)
    dt = tm[1] - tm[0]
    ph = GaitPhases(s.gait.period, s.gait.double_support)
    away = (np.abs(tm - ph.heel_strike_r) > 5 * dt) & (np.abs(tm - ph.heel_strike_l) > 5 * dt)
    err = np.abs(residual)[away]
    assert np.max(err) < 1e-3 * body.mass * G


def _momentum_error(settings, x, n: int = 2161) -> np.ndarray:
    """|total ground reaction − (Σ m a + M g)| at the inner samples, N."""
    from walk3d.problem.settings import body_for

    a = evaluate_cycle(body_for(settings), settings, x, n_samples=n).prediction_arrays
    return np.linalg.norm(_momentum_residual(a)[1], axis=1)


def test_with_the_handover_the_ground_reaction_is_the_momentum_rate_at_heel_strike_too():
    """The default 1.3 m/s cycle (converged with the handover): Newton's law holds at every
    sample, heel strikes included; the same coefficients with the root switched at heel strike
    break it there (the velocity jump's impulse is missing from the ground reactions)."""
    import json
    from pathlib import Path

    data = json.loads((Path(__file__).parents[1] / "verify" / "data" /
                       "handover_male_1.300.json").read_text(encoding="utf-8"))  # fmt: skip
    x = np.array(data["x"])
    smooth = PredictionSettings(gait=data["gait"], model={**data["model"], "handover": True})
    weight = smooth.gait.mass * G
    assert _momentum_error(smooth, x).max() < 1e-3 * weight
    free = smooth.replace(handover=False)
    assert _momentum_error(free, x).max() > 0.5 * weight  # the control


def test_feet_are_loaded_only_in_stance_and_split_exactly(cycle):
    s, _, _, ev = cycle
    a = ev.prediction_arrays
    ph = GaitPhases(s.gait.period, s.gait.double_support)
    for k, side in enumerate(("r", "l")):
        swing = ~ph.in_stance(a["time"], side)
        assert np.all(a["grf_force"][swing, k] == 0.0)
        assert np.all(np.isnan(a["grf_cop"][swing, k]))
    # COP lies on the floor wherever a foot is loaded
    loaded = ~np.isnan(a["grf_cop"][..., 1])
    assert np.all(a["grf_cop"][..., 1][loaded] == 0.0)


def test_criteria_are_reported_with_axis_split_and_smoothing_is_small(cycle):
    _, _, _, ev = cycle
    for key in ("C_tor", "C_en"):
        c = ev.criteria[key]
        assert c["total"] == pytest.approx(c["x"] + c["y"] + c["z"])
        assert c["total"] > 0
        smooth = ev.criteria_smoothed[key]["total"]
        assert smooth >= c["total"] and (smooth - c["total"]) / c["total"] < 0.01
