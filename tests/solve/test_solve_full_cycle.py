"""The full-cycle problem solved (issue #43), on the paper's subject with T and Td given,
seed 0: with no change it gives the half cycle back."""

import numpy as np
import pytest

from walk3d.api import settings as make_settings
from walk3d.problem.settings import body_for
from walk3d.results.evaluate import evaluate_cycle
from walk3d.solve import run_solver
from walk3d.solve.full_cycle import solve_full_cycle

pytestmark = pytest.mark.solve


def test_with_no_change_the_full_cycle_is_the_half_cycle():
    settings = make_settings(1.3806, 1.08, 0.16)
    half = run_solver(settings, 0)
    assert half.converged
    full = solve_full_cycle(settings, half)
    assert full.converged
    body = body_for(settings)
    a, b = evaluate_cycle(body, settings, half.x), evaluate_cycle(body, settings, full.x)
    ca, cb = (e.criteria["C_weighted"]["total"] for e in (a, b))
    assert cb == pytest.approx(ca, rel=0.005)
    diff = a.prediction_arrays["joint_angle"] - b.prediction_arrays["joint_angle"]
    assert np.degrees(np.abs(diff)).max() < 1.0
    assert full.record["iterations"] > 0  # solved, not handed back
