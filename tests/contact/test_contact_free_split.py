"""The double-support split left to the optimizer (walk3d.contact.free_split): the free terms
vanish at heel strike, at toe off and in single stance; the feet still sum to the total
reaction; the node function and the evaluated cycle carry the same split."""

import numpy as np
import pytest

from walk3d import G
from walk3d.body.model import build_body
from walk3d.contact import free_split
from walk3d.contact.phases import GaitPhases
from walk3d.kinematics.forward import stack_v
from walk3d.problem import layout, nlp
from walk3d.problem.settings import PredictionSettings, body_for

W0 = np.array([0.05, 1.0, 0.01, 0.02, 0.01, 0.03])
C = np.array([[0.3, -0.8, 0.02, 0.01, -0.02, 0.05], [-0.1, 0.4, 0.0, 0.0, 0.01, -0.02]])


def test_the_free_terms_vanish_at_both_ends_of_double_support():
    """h = 1 (heel strike) and h = 0 (toe off, single stance): the paper's ``decay · W0``;
    inside, the terms move the load (the control), and without coefficients nothing does."""
    for h in (0.0, 1.0):
        np.testing.assert_allclose(free_split.trailing_load(W0, 0.4, h, C.ravel()), 0.4 * W0)
    inside = np.array(free_split.trailing_load(W0, 0.4, 0.5, C.ravel()))
    basis = 0.25 * np.array([1.0, 0.5])
    np.testing.assert_allclose(inside, 0.4 * W0 + basis @ C, rtol=1e-14)
    assert np.abs(inside - 0.4 * W0).max() > 0.05
    np.testing.assert_allclose(free_split.trailing_load(W0, 0.4, 0.5, []), 0.4 * W0)


def test_the_subjects_coefficients_scale_as_the_loads():
    c = free_split.subject_split(C, 0.9)
    np.testing.assert_allclose(c[:, :3], C[:, :3])
    np.testing.assert_allclose(c[:, 3:], 0.9 * C[:, 3:])


@pytest.fixture(scope="module")
def node_functions():
    body = build_body()
    plain = PredictionSettings(nodes=8)
    split = PredictionSettings(nodes=8, split_terms=2)
    return body, nlp.node_function(body, plain.model), nlp.node_function(body, split.model), split


def _node(seed: int, h: float):
    rng = np.random.default_rng(seed)
    y = rng.uniform(-0.1, 0.1, nlp.N_Y)
    p = np.array([0.6, -0.7, 2 * np.pi / 1.3, h, -0.4, 0.3])  # [decay, anchor_x, ω, h, ...]
    return y, 0.07, p, rng.uniform(0.0, 0.5, nlp.N_T)


def test_the_node_function_carries_the_split_and_keeps_the_total(node_functions):
    """With two free terms the trailing foot carries :func:`trailing_load` (the NumPy path),
    the root foot the rest: the total (Newton–Euler, from the motion alone) is the paper's
    split's. Control: the root foot's force differs from the paper's split's."""
    body, plain, split, s = node_functions
    y, hw, p, t = _node(5, 0.5)
    w = np.r_[W0, C.ravel()]
    g_split = np.array(split(y, w, hw, p, t)[0]).ravel()
    g_plain = np.array(plain(y, W0, hw, p, t)[0]).ravel()
    st = nlp.state_at(body, [np.array([v]) for v in y], [np.array([v]) for v in w], hw,
                      p[0], p[1], p[2], handover=(p[3], p[4], p[5]), share=p[3])  # fmt: skip
    wf = body.mass * G
    want = np.array(free_split.trailing_load(W0, p[0], p[3], C.ravel()))[:3] * wf
    np.testing.assert_allclose(stack_v(st.feet["l"][0])[0], want, rtol=1e-12)
    total = stack_v(st.total[0])[0]
    np.testing.assert_allclose(stack_v(st.feet["r"][0])[0] + want, total, rtol=1e-12)
    rows = nlp.G_ROWS
    mr = nlp.dof_moment_terms(body, st)[:2]
    g_np = np.array([float(np.squeeze(v)) for v in nlp.node_outputs(body, s.model, st, *mr)[0]])
    np.testing.assert_allclose(g_split[: g_np.size], g_np, rtol=1e-9, atol=1e-11)
    loops = np.r_[rows["loop_position"], rows["loop_velocity"]]
    np.testing.assert_allclose(g_split[loops], g_plain[loops], atol=1e-12)
    force = rows["root_force"]
    assert np.abs(g_split[force] - g_plain[force]).max() > 1e-3


def test_the_evaluated_cycle_carries_the_split_in_double_support_only():
    """``evaluate_cycle(split=C)``: the trailing foot's force moves by ``h (1 − h) Σ h^j C_j``
    (mirrored under the left root) in double support, and not at all in single stance (the
    control); the total stays."""
    from result_support import atlas_x, evaluate_atlas

    from walk3d.results.evaluate import evaluate_cycle

    settings, body, plain = evaluate_atlas()
    split = evaluate_cycle(body, settings, atlas_x(), split=C)
    ph = GaitPhases(settings.gait.period, settings.gait.double_support)
    t = np.linspace(0.0, settings.gait.period, 101)
    h = ph.handover(t)[0]
    right = ph.root_is_right(t)
    f0, f1 = plain.prediction_arrays["grf_force"], split.prediction_arrays["grf_force"]
    scale = np.abs(f0).max()
    np.testing.assert_allclose(f1.sum(axis=1), f0.sum(axis=1), atol=1e-9 * scale)
    moved = np.abs(f1 - f0).max(axis=(1, 2))
    assert moved[h == 0].max() < 1e-9 * scale and moved[(h > 0.1) & (h < 0.9)].min() > 1.0
    basis = np.column_stack([h * (1 - h), h * h * (1 - h)])
    mirror = np.where(right[:, None], 1.0, np.array(free_split.MIRROR[:3]))
    want = basis @ C[:, :3] * body.mass * G * mirror
    trailing = np.where(right, 1, 0)  # the left foot (1) trails under the right root
    got = f1[np.arange(t.size), trailing] - f0[np.arange(t.size), trailing]
    np.testing.assert_allclose(got, want, atol=1e-9 * scale)


def test_a_free_split_is_for_the_half_cycle_and_a_few_terms():
    with pytest.raises(ValueError, match="split_terms must be in"):
        PredictionSettings(split_terms=9)
    with pytest.raises(ValueError, match="split_terms is for the half cycle"):
        PredictionSettings(split_terms=2, full_cycle=True)
    assert PredictionSettings(split_terms=2).model.split_terms == 2
    assert body_for(PredictionSettings(split_terms=2)).mass > 0
    assert layout.NlpLayout(4, n_split=12).n_w0 == 18


@pytest.mark.solve
def test_a_prediction_with_a_free_split_walks_and_is_evaluated_again_alike(tmp_path):
    """``walk3d.predict(split_terms=2)`` from the atlas: converges on a gait that walks, costs
    less than the paper's split (9.2, docs/criteria.md), records its coefficients, and the
    audit's evaluation of the folder gives the saved ground reactions; evaluated without them
    (the control), the double support's reactions differ."""
    import walk3d
    from walk3d.results.evaluate import evaluate_cycle
    from walk3d.tracking import _evaluated

    pred = walk3d.predict(split_terms=2, out=tmp_path / "o")
    s = pred.summary
    assert s["converged"] and s["gait_checks"]["looks_like_walking"]
    assert s["objective"]["C_weighted"]["total"] < 9.0
    split = np.array(s["coefficients"]["split"])
    assert split.shape == (2, 6) and np.abs(split).max() > 0.01
    again, settings = _evaluated(tmp_path / "o")
    saved = walk3d.load_result(tmp_path / "o").grf_force
    np.testing.assert_allclose(again.prediction_arrays["grf_force"], saved, atol=1e-6)
    x = np.array(s["coefficients"]["x"])
    without = evaluate_cycle(body_for(settings), settings, x).prediction_arrays["grf_force"]
    assert np.abs(without - saved).max() > 1.0
