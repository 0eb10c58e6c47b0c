"""One node model for the solver and the reports: the NLP's node objective is
:func:`walk3d.model.node.objective` of :func:`walk3d.model.node.node_model` evaluated in NumPy,
with the slacks at the exact criterion integrand."""

import numpy as np
import pytest

from walk3d.model.criteria import signed_integrands
from walk3d.model.node import node_model, objective
from walk3d.model.settings import ModelSettings
from walk3d.model.subject import body_for
from walk3d.problem import nlp
from walk3d.problem.settings import PredictionSettings


@pytest.mark.parametrize("options", [
    {"criterion": "natural"},
    {"criterion": "tor=1,effort=1,effort3=0.5", "passive": True},
    {"criterion": "natural", "changes": {"strength": {"ankle": 0.5}}},
    {"criterion": "en=1,accel=0.5,head=1"},
])  # fmt: skip
def test_the_node_functions_objective_is_the_node_models(options):
    s = PredictionSettings(**options, handover=False)
    body = body_for(s)
    rng = np.random.default_rng(5)
    y = rng.uniform(-0.15, 0.15, nlp.N_Y)
    w0 = np.array([0.05, 1.0, 0.01, 0.02, 0.01, 0.03])
    p = np.array([0.6, -0.7, 2 * np.pi / 1.1, 0.0, 0.0, 0.0])
    st = nlp.state_at(body, [np.array([v]) for v in y], [np.array([v]) for v in w0], 0.07,
                      p[0], p[1], p[2])  # fmt: skip
    coords = [(np.array([y[i]]), np.array([p[2] * y[26 + i]]), np.array([p[2] ** 2 * y[52 + i]]))
              for i in range(26)]  # fmt: skip
    nm = node_model(body, s.model, coords, st)
    base = "tor" if s.model.criterion.startswith("tor") else "en"
    u_pos, u_neg = signed_integrands(body, base, nm.moments, nm.rates)
    t = np.maximum(np.ravel(u_pos), np.ravel(u_neg))  # the slacks at the exact integrand
    g, f = (np.array(v).ravel() for v in nlp.node_function(body, s.model)(y, w0, 0.07, p, t))
    k = nlp.criterion_row(s.model)
    scale = nlp.row_scale(s.model)
    row_base = t.sum() * (1.0 if k == 0 else nlp.POWER_SCALE_W / nlp.EN_SCALE)
    expect = float(np.squeeze(objective(s.model, row_base, nm, scale)))
    assert f[k] == pytest.approx(expect, rel=1e-10)
    # the slack rows t - u± bind on one side per DoF: the NLP's moments are the node model's
    rows = np.abs([g[nlp.G_ROWS["slack_pos"]], g[nlp.G_ROWS["slack_neg"]]])
    assert np.max(np.min(rows, axis=0)) < 1e-9
    # negative control: the objective of another criterion is not the node function's
    other = ModelSettings(criterion="tor=1,pelvis=5" if base == "tor" else "en=1,pelvis=5")
    assert float(np.squeeze(objective(other, row_base, nm, scale))) != pytest.approx(f[k])
