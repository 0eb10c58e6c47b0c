"""The structured derivatives (per-node Jacobians and Hessians scattered into the NLP's) equal
CasADi's own derivatives of the same NLP, for every stage and with the optional rows."""

import casadi as ca
import numpy as np
import pytest

from walk3d.problem import derivatives, layout, nlp
from walk3d.problem.bounds import bounded_rows, bounds
from walk3d.problem.schedule import schedule
from walk3d.problem.settings import PredictionSettings, body_for


def _reference(prob):
    z, f, g = prob["x"], prob["f"], prob["g"]
    lf, lg = ca.MX.sym("lf"), ca.MX.sym("lg", g.numel())
    hess = ca.triu(ca.hessian(lf * f + ca.dot(lg, g), z)[0])
    return (
        ca.Function("j", [z], [ca.jacobian(g, z)]),
        ca.Function("gf", [z], [ca.gradient(f, z)]),
        ca.Function("h", [z, lf, lg], [hess]),
    )


def _dense(m) -> np.ndarray:
    return np.array(ca.densify(ca.DM(m)))


@pytest.mark.parametrize(
    ("dynamics", "balance", "extra"),
    [
        # the full stage with every optional row: loop checks, calibrated heel-strike map, and
        # a free double-support split
        pytest.param(
            True,
            True,
            {
                "criterion": "en",
                "loop_checks": 1,
                "transition_ratios": (0.2, 0.05, 0.1, 0.3),
                "split_terms": 2,
            },  # fmt: skip
            marks=pytest.mark.model,
        ),
        # a weighted criterion: every extra term in the objective row
        pytest.param(
            True,
            True,
            {
                "criterion": "tor=2,accel=0.5,jerk=0.3,head=0.3,impact=0.5,sag=0.2,shear=0.4,"
                "pose=0.5,pelvis=0.5,momentum=0.3,spin=0.7,arms=0.6",
                "heel_strike_nodes": 2,
                "contact_checks": 1,
                "swing_checks": 1,
                "cop_margin": 0.02,
            },
            marks=pytest.mark.model,
        ),
        (False, True, {}),
        (False, False, {}),
    ],
)
def test_structured_derivatives_equal_casadi(dynamics, balance, extra):
    _check_structured(dynamics, balance, extra)


@pytest.mark.model
def test_structured_derivatives_with_effort_and_passive_joints_equal_casadi():
    """The effort terms and the passive moments (#41) in the objective row and the slack rows;
    control: CasADi's Hessian of the NLP without passive joints is another one."""
    crit = "tor=1,effort=2,effort3=1,impact=0.5"
    # a random z gives moments of 10⁴ N·m and gradient entries of 10⁷: allow 10⁻¹⁵ of those
    prob = _check_structured(True, True, {"criterion": crit, "passive": True}, grad_atol=1e-15)
    s = PredictionSettings(nodes=6, criterion=crit)
    plain, _, _ = nlp.build_nlp(body_for(s), s)
    rng = np.random.default_rng(3)
    z0 = rng.uniform(-0.1, 0.1, prob["x"].numel())
    lam = rng.normal(size=prob["g"].numel())
    h_on, h_off = (_dense(_reference(q)[2](z0, 0.7, lam)) for q in (prob, plain))
    assert np.abs(h_on - h_off).max() > 1e-6 * np.abs(h_on).max()


def _check_structured(dynamics, balance, extra, grad_atol=0.0):
    """The checks of :func:`test_structured_derivatives_equal_casadi`; ``grad_atol``: round-off
    allowed in the gradient relative to its largest entry. Returns the NLP."""
    s = PredictionSettings(nodes=6, **extra)
    prob, _, _ = nlp.build_nlp(body_for(s), s, dynamics=dynamics, balance=balance)
    d = prob["derivatives"]
    jac, grad, hess = _reference(prob)
    rng = np.random.default_rng(3)
    z0 = rng.uniform(-0.1, 0.1, prob["x"].numel())
    z0[nlp.layout.N_X :] += rng.uniform(0.0, 0.3, z0.size - nlp.layout.N_X)
    lam = rng.normal(size=prob["g"].numel())
    g_val, j_val = d["jac_g"](z0, [])
    f_val, gf_val = d["grad_f"](z0, [])
    h_val = d["hess_lag"](z0, [], 0.7, lam)
    np.testing.assert_allclose(_dense(j_val), _dense(jac(z0)), rtol=0, atol=1e-11)
    gf_ref = _dense(grad(z0))
    np.testing.assert_allclose(_dense(gf_val), gf_ref, rtol=1e-13,
                               atol=1e-12 + grad_atol * np.abs(gf_ref).max())  # fmt: skip
    h_ref = _dense(hess(z0, 0.7, lam))
    assert np.abs(h_ref).max() > 1.0  # a Hessian that is not trivially zero
    np.testing.assert_allclose(_dense(h_val), h_ref, rtol=0, atol=1e-10 * np.abs(h_ref).max())
    # upper triangle only, as IPOPT's interface expects
    r, c = h_val.sparsity().get_triplet()
    assert all(i <= j for i, j in zip(r, c, strict=True))
    g_ref = ca.Function("g", [prob["x"]], [prob["g"]])(z0)
    np.testing.assert_allclose(np.array(g_val).ravel(), np.array(g_ref).ravel())
    return prob


@pytest.mark.model
@pytest.mark.parametrize(("dynamics", "criterion"), [(True, "en"), (False, "tor")])
def test_column_blocks_equal_the_node_derivatives(dynamics, criterion):
    """The blocks that are compiled to C (derivative_chunks, joined by assemble) give the
    node Jacobian and Hessian of node_derivatives, and the NLP built from them the same
    derivatives as CasADi's."""
    s = PredictionSettings(nodes=6, criterion=criterion)
    crit = 0 if criterion == "tor" else 1
    node = nlp.node_function(body_for(s), s.model, dynamics, with_hs=False, balance=True)
    jac, grad, hess = derivatives.node_derivatives(node, crit)
    blocks = derivatives.derivative_chunks(node, crit, chunks=5, prefix="t")
    assert [f.name() for f in blocks["hess"]] == [f"t_hess_{i}" for i in range(5)]
    jac_b = derivatives.assemble(blocks["jac"], "jac_b")
    hess_b = derivatives.assemble(blocks["hess"], "hess_b")
    rng = np.random.default_rng(5)
    v = rng.uniform(-0.1, 0.1, layout.N_V)
    p = np.array([30.0, -0.7, 5.8, 0.6, -0.3, 0.2])
    lam = rng.normal(size=node.size_out(0)[0])
    h_ref = _dense(hess(v, p, 0.7, lam))
    assert np.abs(h_ref).max() > 1.0
    np.testing.assert_allclose(_dense(hess_b(v, p, 0.7, lam)), h_ref, rtol=0,
                               atol=1e-12 * np.abs(h_ref).max())  # fmt: skip
    np.testing.assert_allclose(_dense(jac_b(v, p)), _dense(jac(v, p)), rtol=0, atol=1e-12)

    # the mapped Hessian block by block (map_blocks) is assemble(...).map(...) bit for bit
    vs = rng.uniform(-0.1, 0.1, (layout.N_V, 3))
    ps, lams = np.tile(p[:, None], (1, 3)), rng.normal(size=(lam.size, 3))
    sfs = np.array([[0.7, 0.2, 1.0]])
    np.testing.assert_array_equal(
        _dense(derivatives.map_blocks(blocks["hess"], 3, 2)(vs, ps, sfs, lams)),
        _dense(hess_b.map(3)(vs, ps, sfs, lams)),
    )

    for hess_arg in (hess_b, blocks["hess"]):  # assembled, or the blocks themselves
        prob, _, _ = nlp.build_nlp(body_for(s), s, dynamics=dynamics, balance=True,
                                   node_derivs=(jac_b, grad, hess_arg))  # fmt: skip
        d = prob["derivatives"]
        ref_jac, _, ref_hess = _reference(prob)
        z0 = rng.uniform(-0.1, 0.1, prob["x"].numel())
        lam_g = rng.normal(size=prob["g"].numel())
        h_nlp = _dense(ref_hess(z0, 0.7, lam_g))
        np.testing.assert_allclose(_dense(d["hess_lag"](z0, [], 0.7, lam_g)), h_nlp, rtol=0,
                                   atol=1e-10 * np.abs(h_nlp).max())  # fmt: skip
        np.testing.assert_allclose(_dense(d["jac_g"](z0, [])[1]), _dense(ref_jac(z0)), rtol=0,
                                   atol=1e-11)  # fmt: skip


@pytest.mark.model
def test_selected_rows_keep_their_values_and_derivatives():
    """select_rows: a stage sees only the bounded rows; the values, Jacobian rows and the
    Hessian (free rows' multipliers are zero) are those of the whole NLP."""
    s = PredictionSettings(nodes=6)
    body = body_for(s)
    prob, _, _ = nlp.build_nlp(body, s, dynamics=True, balance=True)
    b = bounds(body, s, schedule(s))
    rows = bounded_rows(b)
    free = np.setdiff1d(np.arange(b.lbg.size), rows)
    assert free.size > 0 and np.all(~np.isfinite(b.lbg[free]) & ~np.isfinite(b.ubg[free]))
    sub = derivatives.select_rows(prob, rows)
    assert sub["g"].numel() == rows.size and sub["x"] is prob["x"]
    rng = np.random.default_rng(4)
    z0 = rng.uniform(-0.1, 0.1, prob["x"].numel())
    z0[nlp.layout.N_X :] += rng.uniform(0.0, 0.3, z0.size - nlp.layout.N_X)
    full, part = prob["derivatives"], sub["derivatives"]
    g_all, j_all = full["jac_g"](z0, [])
    g_sub, j_sub = part["jac_g"](z0, [])
    np.testing.assert_array_equal(np.array(g_sub).ravel(), np.array(g_all).ravel()[rows])
    np.testing.assert_array_equal(_dense(j_sub), _dense(j_all)[rows])
    lam = rng.normal(size=rows.size)
    lam_all = np.zeros(b.lbg.size)
    lam_all[rows] = lam
    h_ref = _dense(full["hess_lag"](z0, [], 0.7, lam_all))
    assert np.abs(h_ref).max() > 1.0
    np.testing.assert_allclose(_dense(part["hess_lag"](z0, [], 0.7, lam)), h_ref, rtol=0,
                               atol=1e-14 * np.abs(h_ref).max())  # fmt: skip
    g_expr = ca.Function("g", [sub["x"]], [sub["g"]])(z0)
    np.testing.assert_array_equal(np.array(g_expr).ravel(), np.array(g_all).ravel()[rows])


@pytest.mark.model
def test_node0_derivatives_from_the_other_nodes_equal_its_own():
    """Node 0's derivatives built from the other nodes' plus its heel-strike rows
    (:func:`derivatives.with_rows`) equal those of node 0's own function; the other nodes'
    alone (the control) miss the heel-strike rows."""
    s = PredictionSettings()
    body = body_for(s)
    node = nlp.node_function(body, s.model, True, with_hs=False, balance=True)
    node0 = nlp.node_function(body, s.model, True, with_hs=True, balance=True)
    own = derivatives.node_derivatives(node0, 0)
    other = derivatives.node_derivatives(node, 0)
    built = derivatives.with_rows(other, node0, 0, nlp.G_ROWS["hs_wrench"])
    rng = np.random.default_rng(3)
    args = [0.1 * rng.normal(size=own[2].size_in(i)) for i in range(own[2].n_in())]
    for a, b, c in zip(own, built, other, strict=True):
        n_in = a.n_in()
        va, vb, vc = (_dense(f(*args[:2] if n_in == 2 else args)) for f in (a, b, c))
        assert np.abs(va).max() < 1e6  # a sane point
        assert np.allclose(va, vb, rtol=1e-10, atol=1e-10 * np.abs(va).max())
        if a is not own[1]:  # the gradient has no constraint rows
            assert not np.allclose(va, vc, rtol=1e-6, atol=1e-6 * np.abs(va).max())
