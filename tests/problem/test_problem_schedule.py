"""The node grid: regular by default, with extra nodes after heel strike when asked."""

import numpy as np
import pytest

from walk3d.problem.schedule import loop_check_times, schedule
from walk3d.problem.settings import PredictionSettings


def test_regular_grid_has_no_weights_and_the_half_cycle():
    s = PredictionSettings(nodes=20)
    sch = schedule(s)
    assert sch.weights is None and sch.n == 20
    assert sch.step * sch.n == pytest.approx(s.gait.period / 2)


def test_heel_strike_nodes_split_the_first_interval_and_weights_integrate():
    s = PredictionSettings(nodes=20, heel_strike_nodes=3)
    sch = schedule(s)
    assert sch.n == 23
    tau = sch.times - sch.times[0]
    assert np.all(np.diff(tau) > 0)
    np.testing.assert_allclose(tau[1:4], sch.step * np.array([0.25, 0.5, 0.75]))
    assert sch.weights.sum() == pytest.approx(s.gait.period / 2)
    # the midpoint rule integrates a smooth periodic function over the half cycle closely
    w = 2 * np.pi / (s.gait.period / 2)
    f = 1.0 + 0.5 * np.cos(w * tau) ** 2
    exact = (1.0 + 0.25) * s.gait.period / 2
    assert float(sch.weights @ f) == pytest.approx(exact, rel=2e-3)
    assert float(sch.weights @ f) != pytest.approx(exact * 1.01, rel=2e-3)
    # the extra nodes are in double support, weighted by their short intervals
    assert sch.double_support[:4].all()
    assert sch.weights[2] == pytest.approx(sch.step / 4)


def test_loop_checks_fall_between_neighbouring_nodes_on_an_irregular_grid():
    s = PredictionSettings(nodes=20, heel_strike_nodes=1, loop_checks=1)
    sch = schedule(s)
    t = loop_check_times(s, sch)
    assert t[0] == pytest.approx(0.5 * (sch.times[0] + sch.times[1]))
    assert not np.any(np.isclose(t[:, None], sch.times[None, :]))
