"""The NLP's per-node CasADi function is the same physics as the NumPy path."""

import numpy as np
import pytest

from walk3d import G
from walk3d.body.model import build_body
from walk3d.kinematics.forward import stack_v
from walk3d.model.criteria import node_terms, signed_integrands
from walk3d.model.state import dof_moment_terms, strength_weights
from walk3d.problem import layout, nlp
from walk3d.problem.bounds import bounds
from walk3d.problem.schedule import loop_check_times, range_rows
from walk3d.problem.settings import PredictionSettings


@pytest.fixture(scope="module")
def setup():
    s = PredictionSettings(nodes=8, handover=False)  # the paper's root switch; handover below
    body = build_body()
    return s, body, nlp.node_function(body, s.model)


def _random_node(seed):
    rng = np.random.default_rng(seed)
    y = rng.uniform(-0.1, 0.1, nlp.N_Y)
    w0 = np.array([0.05, 1.0, 0.01, 0.02, 0.01, 0.03])
    t = rng.uniform(0.0, 0.5, nlp.N_T)
    # [decay, anchor_x, ω, h, ḣ/ω, ḧ/ω²]
    return y, w0, 0.07, np.array([0.6, -0.7, 2 * np.pi / 1.3, 0.7, -0.4, 0.3]), t


def test_symbolic_node_function_matches_numpy_evaluation(setup):
    s, body, fn = setup
    y, w0, hw, p, t = _random_node(1)
    g, f = (np.array(v).ravel() for v in fn(y, w0, hw, p, t))
    # ω comes from the node parameters (here T = 1.3 s, not the settings' 1.08 s)
    st = nlp.state_at(body, [np.array([v]) for v in y], [np.array([v]) for v in w0], hw,
                      p[0], p[1], p[2])  # fmt: skip
    g_np, f_np, starts = nlp.node_outputs(body, s.model, st, *dof_moment_terms(body, st)[:2])
    g_np = [float(np.squeeze(v)) for v in g_np]
    np.testing.assert_allclose(g[: len(g_np)], g_np, rtol=1e-10, atol=1e-12)
    assert len(g) == nlp.N_G
    # slack rows: t - u± with u± the signed criterion terms; the objective is the slack sum
    u_pos, u_neg = signed_integrands(body, "tor", *dof_moment_terms(body, st)[:2])
    u_pos = np.array([float(np.squeeze(v)) for v in u_pos])
    u_neg = np.array([float(np.squeeze(v)) for v in u_neg])
    np.testing.assert_allclose(g[nlp.G_ROWS["slack_pos"]], t - u_pos, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(g[nlp.G_ROWS["slack_neg"]], t - u_neg, rtol=1e-10, atol=1e-12)
    assert f[0] == pytest.approx(t.sum(), rel=1e-12)
    # the smallest feasible slack is the exact C_tor integrand |M| / M_max(direction)
    exact = [
        float(np.squeeze(v))
        for v in node_terms(*dof_moment_terms(body, st)[:2], *strength_weights(body), None)[0]
    ]
    np.testing.assert_allclose(np.maximum(u_pos, u_neg), exact, rtol=1e-10, atol=1e-12)
    # the split: the trailing foot carries decay * W0, the root the rest of the total
    wf = body.mass * G
    fl = stack_v(st.feet["l"][0])[0]
    np.testing.assert_allclose(fl, p[0] * w0[:3] * wf, rtol=1e-12)
    tot = stack_v(st.total[0])[0]
    np.testing.assert_allclose(stack_v(st.feet["r"][0])[0] + fl, tot, rtol=1e-12)


def test_bounds_and_variables_have_matching_sizes(setup):
    s, body, _ = setup
    prob, sch, lift = nlp.build_nlp(body, s)
    b = bounds(body, s, sch)
    assert prob["x"].shape[0] == b.lbz.size == layout.N_X + sch.n * (nlp.N_Y + nlp.N_T) + 6
    assert prob["g"].shape[0] == b.lbg.size
    assert np.all(b.lbz <= b.ubz) and np.all(b.lbg <= b.ubg)
    # double support comes first, then swing; the loop is enforced only in double support
    assert sch.double_support[0] and not sch.double_support[-1]
    rows = nlp.G_ROWS["loop_position"]
    n_lift = sch.n * nlp.N_Y
    g_node = b.lbg[n_lift : n_lift + sch.n * nlp.N_G].reshape(sch.n, nlp.N_G)
    assert np.all(g_node[sch.double_support, rows] == 0)
    assert np.all(np.isinf(g_node[sch.swing, rows]))
    # the loop is also checked between consecutive double-support nodes and at toe-off
    # (8 nodes: the last double-support node is well before it), within a tolerance
    t_loop = loop_check_times(s, sch)
    assert t_loop.size == s.solver.loop_checks * (sch.double_support.sum() - 1) + 1
    assert t_loop[-1] == pytest.approx(sch.times[0] + s.gait.double_support)
    assert b.lbg.size - (n_lift + sch.n * nlp.N_G + 6) - len(range_rows(body, s)[1]) == (
        6 * t_loop.size
    )
    assert np.all(b.ubg[-6:] == s.solver.loop_check_tolerance) and np.all(b.lbg[-6:] < 0)


def test_handover_node_function_matches_numpy_and_moves_the_loads(setup):
    """With ``model.handover`` the node function reads the share from ``p[3:6]`` (rates scaled
    by ω) and its ground reaction is the NumPy path's with that share; the same node without
    the handover has another reaction (the control), and the loop rows stay the root chain's."""
    s, body, fn = setup
    model = s.model.model_copy(update={"handover": True})
    fn_h = nlp.node_function(body, model)
    y, w0, hw, p, t = _random_node(4)
    g_h = np.array(fn_h(y, w0, hw, p, t)[0]).ravel()
    g = np.array(fn(y, w0, hw, p, t)[0]).ravel()
    st = nlp.state_at(body, [np.array([v]) for v in y], [np.array([v]) for v in w0], hw,
                      p[0], p[1], p[2], handover=(p[3], p[4], p[5]))  # fmt: skip
    mr = dof_moment_terms(body, st)[:2]
    g_np = np.array([float(np.squeeze(v)) for v in nlp.node_outputs(body, model, st, *mr)[0]])
    np.testing.assert_allclose(g_h[: g_np.size], g_np, rtol=1e-9, atol=1e-11)
    force = nlp.G_ROWS["root_force"]
    assert np.abs(g_h[force] - g[force]).max() > 1e-3
    for name in ("loop_position", "loop_orientation", "loop_velocity", "loop_omega"):
        np.testing.assert_allclose(g_h[nlp.G_ROWS[name]], g[nlp.G_ROWS[name]], atol=1e-12)


def test_loop_function_matches_the_node_rows(setup):
    s, body, fn = setup
    y, w0, hw, p, t = _random_node(2)
    g = np.array(fn(y, w0, hw, p, t)[0]).ravel()
    loop = np.array(nlp.loop_function(body, s.model)(y[: layout.N_COORD], hw, p[1])).ravel()
    rows = np.r_[nlp.G_ROWS["loop_position"], nlp.G_ROWS["loop_orientation"]]
    np.testing.assert_allclose(loop, g[rows], rtol=1e-10, atol=1e-12)


@pytest.mark.parametrize("decay", [0.0, 0.6, 1.0])
def test_balance_split_shares_the_reaction_as_the_full_stage(setup, decay):
    """With ``balance_split`` the balance node (no joint moments) bounds the same per-foot
    loads as the full node: force, friction, centre-of-pressure and heel-strike rows agree, and
    so do their bounds, so a balance optimum starts the full stage inside them. Without it
    (the default) the support rows hold the total under both feet and differ."""
    s, body, full = setup
    y, w0, hw, p, t = _random_node(3)
    p = np.array([decay, *p[1:]])
    R = nlp.G_ROWS
    rows = np.r_[R["root_force"], R["other_force"], R["hs_wrench"], R["root_support"],
                 R["other_support"]]  # fmt: skip
    split = PredictionSettings(nodes=8, balance_split=True, handover=False)  # as `setup`

    def balance_rows(settings):
        fn = nlp.node_function(body, settings.model, dynamics=False, balance=True)
        return np.array(fn(y, w0, hw, p, t)[0]).ravel()[rows]

    g_full = np.array(full(y, w0, hw, p, t)[0]).ravel()[rows]
    np.testing.assert_allclose(balance_rows(split), g_full, rtol=1e-9, atol=1e-12)
    assert np.abs(g_full[-12:]).max() > 1e-3  # the support rows compared are not all zero
    if decay > 0:
        assert np.abs(balance_rows(s) - g_full).max() > 1e-3
    sch = nlp.schedule(s)
    b_full, b_split = bounds(body, s, sch), bounds(body, split, sch, dynamics=False)
    n_lift = sch.n * nlp.N_Y

    def node_bounds(b):
        lo, hi = (v[n_lift : n_lift + sch.n * nlp.N_G].reshape(sch.n, nlp.N_G)[:, rows]
                  for v in (b.lbg, b.ubg))  # fmt: skip
        return lo, hi

    for a, b in zip(node_bounds(b_split), node_bounds(b_full), strict=True):
        np.testing.assert_array_equal(a, b)
