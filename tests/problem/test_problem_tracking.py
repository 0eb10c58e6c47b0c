"""The track term in the NLP: the objective adds the node integrand with the objective's own
quadrature, and the structured derivatives add its exact gradient and Hessian."""

import casadi as ca
import numpy as np
import pytest

from walk3d.model.tracking import Tracking, integrand
from walk3d.problem import layout, nlp
from walk3d.problem.settings import PredictionSettings, body_for
from walk3d.problem.tracking import node_phases


def _settings(track: float | None):
    rng = np.random.default_rng(3)
    coef = np.zeros((24, 21))
    coef[:, :5] = rng.uniform(-0.2, 0.2, (24, 5))
    w = np.r_[np.ones(12), 2 * np.ones(12)]
    spec = Tracking(coefficients=tuple(map(tuple, coef)), weights=tuple(w))
    crit = "natural" if track is None else f"natural,track={track:g}"
    return PredictionSettings(criterion=crit, tracking=spec, nodes=6, period=1.1,
                              double_support=0.13)  # fmt: skip


@pytest.fixture(scope="module")
def problems():
    out = {}
    for key, w in (("plain", None), ("track", 7.0)):
        s = _settings(w)
        prob, sch, _ = nlp.build_nlp(body_for(s), s)
        out[key] = (s, prob, sch)
    return out


def _z(prob, seed=1):
    return np.random.default_rng(seed).uniform(-0.1, 0.1, prob["x"].numel())


def test_the_objective_adds_the_integrand_at_the_nodes(problems):
    s, prob, sch = problems["track"]
    _, plain, _ = problems["plain"]
    z = _z(prob)
    f = ca.Function("f", [prob["x"]], [prob["f"]])
    f0 = ca.Function("f0", [plain["x"]], [plain["f"]])
    added = float(f(z)) - float(f0(z))
    y = z[layout.N_X : layout.N_X + sch.n * layout.N_Y].reshape(sch.n, layout.N_Y)
    axes = [slot for j in body_for(s).joints for slot in j.dof_slots]
    target = s.model.tracking.target(node_phases(s, sch.times))
    parts = integrand(s.model.tracking, list(y[:, :24].T), target, axes)
    weights = 2.0 * (sch.step if sch.weights is None else sch.weights)
    expect = 7.0 * float(np.sum(weights * sum(parts)))
    assert added == pytest.approx(expect, rel=1e-10)
    # negative control: the phases of the nodes matter (the target half a cycle later)
    later = s.model.tracking.target(node_phases(s, sch.times + s.gait.period / 2))
    other = 7.0 * float(np.sum(weights * sum(integrand(s.model.tracking, list(y[:, :24].T),
                                                       later, axes))))  # fmt: skip
    assert other != pytest.approx(expect, rel=1e-3)


def test_the_structured_derivatives_add_the_exact_gradient_and_hessian(problems):
    s, prob, _ = problems["track"]
    _, plain, _ = problems["plain"]
    z = _z(prob)
    d, d0 = prob["derivatives"], plain["derivatives"]
    grad = np.array(d["grad_f"](z, [])[1]).ravel() - np.array(d0["grad_f"](z, [])[1]).ravel()
    zs = prob["x"]
    extra = prob["f"] - ca.substitute(plain["f"], plain["x"], zs)
    ref = ca.Function("g", [zs], [ca.gradient(extra, zs), ca.hessian(extra, zs)[0]])
    g_ref, h_ref = (np.array(v) for v in ref(z))
    np.testing.assert_allclose(grad, g_ref.ravel(), rtol=1e-9, atol=1e-9)
    lam_g = np.zeros(prob["g"].numel())
    h = d["hess_lag"](z, [], 1.0, lam_g) - d0["hess_lag"](z, [], 1.0, lam_g)
    h = np.array(ca.DM(h).full())
    np.testing.assert_allclose(h, np.triu(h_ref), rtol=1e-9, atol=1e-9)
    assert np.count_nonzero(np.diag(h)) > 0  # control: the term has curvature
