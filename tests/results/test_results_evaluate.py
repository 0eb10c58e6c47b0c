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
    s = PredictionSettings()
    body = build_body()
    x = random_decision(11)
    return s, body, x, evaluate_cycle(body, s, x, n_samples=2161)


def test_ground_reaction_equals_momentum_rate_of_the_segments(cycle):
    s, body, _, ev = cycle
    a = ev.prediction_arrays
    t, com = a["time"], a["segment_com_position"]
    dt = t[1] - t[0]
    acc = (com[2:] - 2 * com[1:-1] + com[:-2]) / dt**2
    mass = a["segment_mass"]
    expected = np.einsum("s,nsk->nk", mass, acc) + np.array([0, mass.sum() * G, 0])
    total = a["grf_force"].sum(axis=1)[1:-1]
    ph = GaitPhases(s.gait.period, s.gait.double_support)
    tm = t[1:-1]
    away = (np.abs(tm - ph.heel_strike_r) > 5 * dt) & (np.abs(tm - ph.heel_strike_l) > 5 * dt)
    err = np.abs(total - expected)[away]
    assert np.max(err) < 1e-3 * body.mass * G


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
