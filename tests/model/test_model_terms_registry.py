"""A criterion term added from outside the package: one function and its registration, then
the solver's node function, the evaluated cycle, the reports' keys and the cache key all carry
it, with no other edit."""

import numpy as np
import pytest
from helpers import random_decision

import walk3d
from walk3d.body.model import build_body
from walk3d.model import terms
from walk3d.model.settings import node_fields
from walk3d.problem import nlp
from walk3d.problem.settings import ModelSettings, PredictionSettings
from walk3d.results.evaluate import evaluate_cycle
from walk3d.solve import solver

NAME = "trunk_test"


def trunk(node, ref):
    """The torso's angular velocity over ``ref`` (rad/s), squared, by global axis."""
    w = node.pose.omega[node.body.segment_index("torso")]
    return tuple((w[k] / ref) ** 2 for k in range(3))


@pytest.fixture
def registered():
    term = walk3d.register_term(walk3d.Term(NAME, trunk, 0.5, "the trunk's rate (rad/s)"))
    yield term
    terms.unregister(NAME)


def _node(body, criterion, seed=3):
    rng = np.random.default_rng(seed)
    y = rng.uniform(-0.15, 0.15, nlp.N_Y)
    w0 = np.array([0.05, 1.0, 0.01, 0.02, 0.01, 0.03])
    p = np.array([0.6, -0.7, 2 * np.pi / 1.1, 0.0, 0.0, 0.0])
    t = rng.uniform(0.0, 0.5, nlp.N_T)
    fn = nlp.node_function(body, ModelSettings(criterion=criterion, handover=False))
    g, f = (np.array(v).ravel() for v in fn(y, w0, 0.07, p, t))
    return g, f, (y, w0, p)


def test_a_registered_term_enters_the_node_objective_with_its_weight(registered):
    body = build_body()
    g0, f0, (y, w0, p) = _node(body, "natural")
    g1, f1, _ = _node(body, f"natural,{NAME}=2")
    st = nlp.state_at(body, [np.array([v]) for v in y], [np.array([v]) for v in w0], 0.07,
                      p[0], p[1], p[2])  # fmt: skip
    expect = 2 * float(np.sum([np.squeeze(v) for v in trunk(terms.Node(
        body, [], st.pose, st.total[0], None, []), 0.5)]))  # fmt: skip
    assert expect > 1e-3
    assert f1[0] - f0[0] == pytest.approx(expect, rel=1e-10)
    np.testing.assert_array_equal(g1, g0)  # the rows are the model's, the term is objective only
    # negative control: another weight gives another objective
    _, f3, _ = _node(body, f"natural,{NAME}=3")
    assert f3[0] - f0[0] != pytest.approx(expect, rel=1e-3)


def test_a_registered_term_is_evaluated_reported_and_weighted(registered):
    s = PredictionSettings(criterion=f"natural,{NAME}=2", period=1.1, double_support=0.13)
    plain = PredictionSettings(criterion="natural", period=1.1, double_support=0.13)
    body = build_body()
    x = random_decision(np.random.default_rng(0))
    c = evaluate_cycle(body, s, x).criteria
    c0 = evaluate_cycle(body, plain, x).criteria
    term = c[f"C_{NAME}"]
    assert term["total"] > 0 and term["total"] == pytest.approx(term["x"] + term["y"] + term["z"])
    assert c["C_weighted"]["parts"][NAME] == pytest.approx(2 * term["total"])
    assert c["C_weighted"]["total"] == pytest.approx(c0["C_weighted"]["total"] + 2 * term["total"])
    assert f"C_{NAME}" in terms.reported(c)
    assert terms.minimized(c, s.model.criterion) == c["C_weighted"]["total"]
    # reported where the term is not registered (a result read by another process)
    terms.unregister(NAME)
    assert f"C_{NAME}" in terms.reported(c)
    assert terms.preset_name(s.model.criterion) is None
    with pytest.raises(ValueError, match="unknown criterion term"):  # control: not a term now
        terms.parse(s.model.criterion)
    walk3d.register_term(registered)


def test_the_model_cache_key_follows_the_terms_formula(registered):
    body = build_body()
    model = ModelSettings(criterion=f"natural,{NAME}=1")
    key = solver.model_key(body, model)
    assert node_fields(model)["criterion_terms"]
    assert "criterion_terms" not in node_fields(ModelSettings(criterion="natural"))
    terms.register(walk3d.Term(NAME, trunk, 0.5), replace=True)  # control: the same formula
    assert solver.model_key(body, model) == key
    terms.register(walk3d.Term(NAME, lambda node, ref: trunk(node, 2 * ref), 0.5), replace=True)
    assert solver.model_key(body, model) != key


def test_registration_refuses_taken_and_bad_names(registered):
    with pytest.raises(ValueError, match="registered already"):
        terms.register(walk3d.Term(NAME, trunk, 1.0))
    for name in ("tor", "accel", "not a name"):
        with pytest.raises(ValueError, match="taken or not an identifier"):
            terms.register(walk3d.Term(name, trunk, 1.0))
    with pytest.raises(ValueError, match="needs a formula"):
        terms.register(walk3d.Term("coefficients_only", None, 1.0))
    with pytest.raises(ValueError, match="built in"):
        terms.unregister("accel")
    assert NAME in terms.names() and "accel" in terms.names()


def test_a_preset_with_changes_is_a_spec():
    natural = terms.parse("natural")
    changed = terms.parse("natural,pelvis=0,accel=1")
    assert "pelvis" not in changed and changed["accel"] == 1.0
    assert {k: v for k, v in changed.items() if k != "accel"} == {
        k: v for k, v in natural.items() if k not in ("pelvis", "accel")}  # fmt: skip
    with pytest.raises(ValueError, match="given twice"):
        terms.parse("natural,pelvis=1,pelvis=2")
    with pytest.raises(ValueError, match="unknown criterion term 'natural'"):
        terms.parse("accel=1,natural")  # a preset only comes first
