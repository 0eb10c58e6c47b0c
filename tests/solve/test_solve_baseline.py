"""The SLSQP baseline states the same problem as the IPOPT NLP (same rows, same values)."""

import casadi as ca
import numpy as np
import pytest

from walk3d.problem import layout, nlp
from walk3d.problem.settings import PredictionSettings
from walk3d.solve.baseline import _Dense, slsqp_solve
from walk3d.solve.ipopt import initial_guess


@pytest.mark.model
def test_dense_rows_have_the_bounds_of_each_stage():
    s = PredictionSettings(nodes=6, absolute="smooth")
    for dynamics in (False, True):
        dense = _Dense(s, dynamics=dynamics)
        g, _, _, _ = dense._eval(np.r_[initial_guess(dense.sv, 1)[: layout.N_X], np.zeros(6)])
        assert g.size == dense.lbg.size == dense.ubg.size


@pytest.mark.model
def test_dense_rows_equal_the_lifted_nlp_rows():
    s = PredictionSettings(nodes=6, absolute="smooth")
    dense = _Dense(s, dynamics=True)
    sv = dense.sv
    x = initial_guess(sv, 3)[: layout.N_X]
    w0 = np.array([0.02, 0.9, 0.01, 0.0, 0.01, 0.02])
    g_dense, _, _, _ = dense._eval(np.r_[x, w0])
    assert g_dense.size == dense.lbg.size  # every bounded row is computed, loop checks included
    # the lifted NLP at the consistent point (Y = A x, slacks unused in the smooth form)
    prob, sch, lift = nlp.build_nlp(sv.body, s)
    y = np.einsum("kij,j->ki", lift, x).ravel()
    z = np.r_[x, y, w0, np.zeros(sch.n * nlp.N_T)]
    g = np.array(ca.Function("g", [prob["x"]], [prob["g"]])(z)).ravel()
    n_lift, n_node = sch.n * nlp.N_Y, sch.n * nlp.N_G
    np.testing.assert_allclose(g[:n_lift], 0.0, atol=1e-12)
    expected = np.r_[g[n_lift : n_lift + n_node], g[n_lift + n_node + 6 :]]
    bounded = np.isfinite(dense.lbg) | np.isfinite(dense.ubg)  # (unbounded rows may differ)
    assert bounded[-6:].all()  # the toe-off loop check
    np.testing.assert_allclose(g_dense[bounded], expected[bounded], rtol=1e-9, atol=1e-12)


@pytest.mark.solve
def test_baseline_out_of_time_is_labelled_unconverged():
    out = slsqp_solve(PredictionSettings(nodes=6), 0, time_limit_s=0.5)
    assert not out.converged
    assert out.status == "time limit reached"
    assert out.stages[0]["stage"] == "kinematic" and out.solver == "slsqp-fd"


def test_the_smooth_form_of_a_reference_problem_is_not_revalidated():
    """A short subject's reference problem walks faster than the user-facing range (V / √s);
    switching its criterion form must keep it as it is (revalidating it would refuse it)."""
    from walk3d.problem import similarity
    from walk3d.solve.baseline import _smooth

    ref, _ = similarity.reference_problem(PredictionSettings(height=1.2, speed=3.5))
    assert ref.gait.speed > 4.0  # outside the range a user may give
    smooth = _smooth(ref)
    assert smooth.model.absolute == "smooth" and smooth.gait == ref.gait
    try:  # negative control: a validated copy refuses it
        ref.replace(absolute="smooth")
    except ValueError as exc:
        assert "speed" in str(exc)
    else:
        raise AssertionError("a validated copy accepted V > 4 m/s")
