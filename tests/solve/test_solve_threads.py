"""Threads only spread the node evaluations: the solver takes the same steps for any count
(so a campaign start, one thread, and ``walk3d predict --seed``, every core, agree)."""

import numpy as np
import pytest

from walk3d.problem.settings import PredictionSettings
from walk3d.solve import ipopt

pytestmark = pytest.mark.solve

SETTINGS = PredictionSettings(nodes=6, max_iter=4, balance_max_iter=4)


def test_threads_give_identical_iterates():
    one = ipopt.build_solver(SETTINGS)
    two = ipopt.build_solver(SETTINGS.replace(**{"threads": 2}))
    z0 = ipopt.initial_guess(one, 3)
    np.testing.assert_array_equal(z0, ipopt.initial_guess(two, 3))
    za, ia, _ = ipopt._run(one.stage("balance"), one, z0, "balance", "balance")
    zb, ib, _ = ipopt._run(two.stage("balance"), two, z0, "balance", "balance")
    assert ia["iterations"] == ib["iterations"] == 4
    assert np.abs(za - z0).max() > 1e-6  # the solver moved
    np.testing.assert_array_equal(za, zb)
    # the full stage (joint moments, slacks) too
    start = ipopt.full_stage_start(one, za)
    fa, _, _ = ipopt._run(one.stage("full"), one, start, "full", "full")
    fb, _, _ = ipopt._run(two.stage("full"), two, start, "full", "full")
    np.testing.assert_array_equal(fa, fb)
