"""The weakened joints' overload term (#43): a strength factor below 1 caps the joint's moments
at its weakened, angle-dependent strength, in the node function's criterion row and in the
evaluated criteria."""

import casadi as ca
import numpy as np
import pytest
from helpers import random_decision

from walk3d.body.changes import apply_changes
from walk3d.body.model import build_body
from walk3d.model import effort, whatif
from walk3d.model.whatif import Changes, overload, weakened_dofs
from walk3d.problem import nlp
from walk3d.problem.settings import ModelSettings, PredictionSettings, body_for
from walk3d.results.evaluate import evaluate_cycle

WEAK = Changes(strength={"ankle_r": 0.5})


def _weak_body():
    return apply_changes(build_body(), WEAK.strength)


def _axes(body):
    return [slot for j in body.joints for slot in j.dof_slots]


def test_the_weakened_dofs_are_the_weak_joints_alone():
    body = build_body()
    names = [body.dof_names[i] for i in weakened_dofs(body, WEAK)]
    assert names == ["ankle_dorsiflexion_r", "subtalar_inversion_r"]
    both = weakened_dofs(body, Changes(strength={"knee": 0.4}))
    assert [body.dof_names[i] for i in both] == ["knee_flexion_r", "knee_flexion_l"]
    assert weakened_dofs(body, Changes(strength={"ankle_r": 1.5})) == []  # stronger: no cap
    assert weakened_dofs(body, Changes()) == []


def test_overload_is_the_squared_excess_over_the_weakened_strength():
    body = _weak_body()
    i_r, i_l = (body.dof_names.index(f"ankle_dorsiflexion_{s}") for s in "rl")
    theta = 0.1
    values = [np.array([0.0, 0.0])] * 24
    values[i_r] = values[i_l] = np.full(2, np.sin(theta / 2))
    sn = effort.strengths(body, i_r, theta)[1]  # plantarflexor strength, weakened, at θ
    assert sn == pytest.approx(0.5 * effort.strengths(build_body(), i_r, theta)[1])
    moments = [np.zeros(2) for _ in range(24)]
    moments[i_r] = np.array([-2.0 * sn, -0.5 * sn])  # twice and half the strength
    moments[i_l] = np.array([-2.0 * sn, -2.0 * sn])  # the other ankle: not weakened
    parts = overload(body, WEAK, moments, values, _axes(body))
    total = sum(parts)
    assert total[0] == pytest.approx(whatif.OVERLOAD_WEIGHT * 1.0, rel=1e-4)
    assert 0 < total[1] < 1e-4 * whatif.OVERLOAD_WEIGHT  # below the strength: almost free
    assert parts[0][0] < 1e-7 and parts[1][0] == 0.0  # sagittal: the ankle's z axis
    # negative control: with the left ankle weakened too, its excess counts
    both = Changes(strength={"ankle": 0.5})
    body2 = apply_changes(build_body(), both.strength)
    assert sum(overload(body2, both, moments, values, _axes(body2)))[0] == pytest.approx(
        2 * whatif.OVERLOAD_WEIGHT, rel=1e-4
    )


def test_overload_derivative_equals_finite_differences():
    body = _weak_body()
    m, q = ca.SX.sym("m", 24), ca.SX.sym("q", 24)
    f = sum(overload(body, WEAK, [m[i] for i in range(24)], [q[i] for i in range(24)],
                     _axes(body)))  # fmt: skip
    fn = ca.Function("f", [m, q], [f, ca.gradient(f, m), ca.gradient(f, q)])
    rng = np.random.default_rng(0)
    m0, q0 = rng.normal(0, 60, 24), rng.uniform(-0.2, 0.2, 24)
    _, gm, gq = (np.array(v).ravel() for v in fn(m0, q0))
    assert np.abs(gm).max() > 0  # the excess is active at this point
    h = 1e-6
    for i in weakened_dofs(body, WEAK):
        for g, k in ((gm, 0), (gq, 1)):
            dp, dm = [m0.copy(), q0.copy()], [m0.copy(), q0.copy()]
            dp[k][i] += h
            dm[k][i] -= h
            fd = (float(fn(*dp)[0]) - float(fn(*dm)[0])) / (2 * h)
            assert g[i] == pytest.approx(fd, rel=1e-5, abs=1e-8)
    assert np.all(gm[[i for i in range(24) if i not in weakened_dofs(body, WEAK)]] == 0)


def test_the_node_criterion_row_adds_the_overload():
    rng = np.random.default_rng(4)
    y = rng.uniform(-0.15, 0.15, nlp.N_Y)
    w0 = np.array([0.05, 1.0, 0.01, 0.02, 0.01, 0.03])
    p = np.array([0.6, -0.7, 2 * np.pi / 1.1, 0.0, 0.0, 0.0])
    t = rng.uniform(0.0, 0.5, nlp.N_T)
    plain, weak = ModelSettings(handover=False), ModelSettings(handover=False, changes=WEAK)
    body = _weak_body()
    f_plain = np.array(nlp.node_function(body, plain)(y, w0, 0.07, p, t)[1]).ravel()
    f_weak = np.array(nlp.node_function(body, weak)(y, w0, 0.07, p, t)[1]).ravel()
    st = nlp.state_at(body, [np.array([v]) for v in y], [np.array([v]) for v in w0], 0.07,
                      p[0], p[1], p[2])  # fmt: skip
    moments, _, axes = nlp.dof_moment_terms(body, st)
    ref = float(np.sum(overload(body, WEAK, moments, [np.array([v]) for v in y[:24]], axes)))
    assert ref > 1e-3  # a random state overloads the weak ankle: the check can fail
    assert f_weak[0] - f_plain[0] == pytest.approx(ref, rel=1e-10)


def test_the_evaluated_criteria_report_the_overload_and_count_it():
    s = PredictionSettings(changes={"strength": {"ankle_r": 0.3}})
    x = random_decision(11)
    ev = evaluate_cycle(body_for(s), s, x)
    c = ev.criteria
    assert c["C_overload"]["total"] > 0
    parts = c["C_weighted"]["parts"]
    assert parts["overload"] == c["C_overload"]["total"]
    assert c["C_weighted"]["total"] == pytest.approx(sum(parts.values()))
    plain = evaluate_cycle(body_for(PredictionSettings()), PredictionSettings(), x).criteria
    assert "C_overload" not in plain and "overload" not in plain["C_weighted"]["parts"]
