"""The period and double support as unknowns: the phase-following grid, the lifting as a
function of s, exact derivatives in s (against CasADi's and finite differences), the bounds, and
the given descriptors' problem left as it was."""

import casadi as ca
import numpy as np
import pytest

from walk3d.problem import descriptors, free_nlp, layout, nlp
from walk3d.problem.bounds import bounds
from walk3d.problem.schedule import lifting_maps, nlp_layout, schedule
from walk3d.problem.settings import PredictionSettings, body_for

FREE = ("period", "double_support")


def _free(**extra) -> PredictionSettings:
    return PredictionSettings(free=FREE, nodes=8, period=1.1, double_support=0.15, **extra)


def test_grid_follows_the_phases_and_integrates_the_half_cycle():
    grid = descriptors.free_grid(20)
    assert grid.n_ds == descriptors.ds_intervals(20) == 4  # 10 % of 2 x 20 intervals
    for t, td in [(1.08, 0.16), (0.95, 0.09), (1.4, 0.25)]:
        tau = np.array(grid.tau(t, td))
        assert tau[0] == 0.0 and tau[grid.n_ds] == pytest.approx(td)  # heel strike, toe off
        assert np.all(np.diff(tau) > 0) and tau[-1] < t / 2
        assert sum(grid.weights(t, td)) == pytest.approx(t / 2)
    # the trailing foot's share is a constant of the grid, and it unloads by toe off
    assert grid.decay[0] == 1.0 and grid.decay[grid.n_ds] < 1e-3 and grid.decay[-1] == 0.0
    assert grid.double_support.sum() == grid.n_ds + 1


@pytest.mark.model
def test_the_grid_does_not_depend_on_the_first_guess():
    """The problem, and so its optimum, is the same from any first guess of T and Td: only the
    objective's constant scale T0 / T differs."""
    a = free_nlp.build_free_nlp(body_for(_free()), _free())[1]
    other = _free().replace(period=0.95, double_support=0.2)
    b = free_nlp.build_free_nlp(body_for(other), other)[1]
    assert np.array_equal(a.double_support, b.double_support)
    assert np.array_equal(a.decay, b.decay)
    # negative control: another count of double-support intervals is another grid
    assert not np.array_equal(descriptors.free_grid(8).decay, descriptors.free_grid(8, 3).decay)
    with pytest.raises(ValueError, match="do not fit"):
        descriptors.free_grid(8, 7)


def test_lifting_of_s_equals_the_numeric_maps_at_the_first_guess():
    s = _free()
    sch = schedule(s)
    lift = lifting_maps(s, sch)
    fn = descriptors.lift_function(descriptors.free_grid(8))
    x = np.random.default_rng(0).normal(size=layout.N_X)
    want = np.einsum("kij,j->ki", lift, x).ravel()
    np.testing.assert_allclose(np.array(fn(x, [1.1, 0.15])).ravel(), want, atol=1e-12)
    # negative control: another Td moves the nodes, and the lifted values with them
    assert np.abs(np.array(fn(x, [1.1, 0.17])).ravel() - want).max() > 1e-2


def _reference(prob):
    z, f, g = prob["x"], prob["f"], prob["g"]
    lf, lg = ca.MX.sym("lf"), ca.MX.sym("lg", g.numel())
    return (
        ca.Function("j", [z], [ca.jacobian(g, z)]),
        ca.Function("gf", [z], [ca.gradient(f, z)]),
        ca.Function("h", [z, lf, lg], [ca.triu(ca.hessian(lf * f + ca.dot(lg, g), z)[0])]),
    )


def _dense(m) -> np.ndarray:
    return np.array(ca.densify(ca.DM(m)))


def _point(prob, seed=3):
    rng = np.random.default_rng(seed)
    z = rng.uniform(-0.1, 0.1, prob["x"].numel())
    z[layout.N_X :] += rng.uniform(0.0, 0.3, z.size - layout.N_X)
    z[-2:] = [1.12, 0.14]
    return z, rng.normal(size=prob["g"].numel())


@pytest.mark.model
@pytest.mark.parametrize(
    ("dynamics", "balance", "criterion", "checks", "split"),
    [
        (True, True, "tor=1,jerk=0.5,impact=2,arms=1", 0, 2),  # with a free split
        (True, True, "en", 1, 0),  # and a what-if joint limit: range rows
        (False, True, "tor", 0, 0),
    ],
)
def test_structured_derivatives_in_s_equal_casadi(dynamics, balance, criterion, checks, split):
    limits = {"changes": {"limits": (("knee_flexion", -0.1, 0.1),)}} if checks else {}
    s = _free(criterion=criterion, contact_checks=checks, split_terms=split, **limits)
    prob, _, _ = free_nlp.build_free_nlp(body_for(s), s, dynamics=dynamics, balance=balance)
    d = prob["derivatives"]
    jac, grad, hess = _reference(prob)
    z0, lam = _point(prob)
    _, j_val = d["jac_g"](z0, [])
    _, gf_val = d["grad_f"](z0, [])
    h_val = d["hess_lag"](z0, [], 0.7, lam)
    j_ref = _dense(jac(z0))
    assert np.abs(j_ref[:, -2:]).max() > 1.0  # the rows do depend on T and Td
    np.testing.assert_allclose(_dense(j_val), j_ref, rtol=0, atol=1e-10)
    np.testing.assert_allclose(_dense(gf_val), _dense(grad(z0)), rtol=0, atol=1e-11)
    h_ref = _dense(hess(z0, 0.7, lam))
    assert np.abs(h_ref[:, -2:]).max() > 1.0
    np.testing.assert_allclose(_dense(h_val), h_ref, rtol=0, atol=1e-10 * np.abs(h_ref).max())


def test_derivatives_in_s_match_finite_differences():
    """Central differences of g, f and the Lagrangian's gradient in T and Td against the
    structured derivatives; the negative control drops the s columns and fails."""
    s = _free(criterion="natural")
    prob, _, _ = free_nlp.build_free_nlp(body_for(s), s)
    d = prob["derivatives"]
    z0, lam = _point(prob, seed=5)
    fg = ca.Function("fg", [prob["x"]], [prob["f"], prob["g"]])
    _, j_val = d["jac_g"](z0, [])
    _, gf_val = d["grad_f"](z0, [])
    h_val = _dense(d["hess_lag"](z0, [], 1.0, lam))
    h_full = np.triu(h_val) + np.triu(h_val, 1).T

    def lag_grad(z):
        _, gf = d["grad_f"](z, [])
        _, jg = d["jac_g"](z, [])
        return _dense(gf).ravel() + _dense(jg).T @ lam

    for i in (z0.size - 2, z0.size - 1):
        e = np.zeros(z0.size)
        e[i] = 1e-6
        fp, gp = fg(z0 + e)
        fm, gm = fg(z0 - e)
        dg = (np.array(gp) - np.array(gm)).ravel() / 2e-6
        scale = np.abs(dg).max()
        assert scale > 1.0
        assert np.abs(dg - _dense(j_val)[:, i]).max() < 1e-6 * scale
        assert float(fp - fm) / 2e-6 == pytest.approx(_dense(gf_val)[i, 0], rel=1e-6)
        dh = (lag_grad(z0 + e) - lag_grad(z0 - e)) / 2e-6
        assert np.abs(dh - h_full[:, i]).max() < 1e-5 * np.abs(dh).max()
        # negative control: without its s column the Jacobian misses these differences
        assert np.abs(dg).max() > 1e3 * np.abs(dg - _dense(j_val)[:, i]).max()


def test_bounds_pin_s_before_the_last_stage_and_free_it_in_human_ranges():
    s = _free()
    body, sch = body_for(s), schedule(s)
    lay = nlp_layout(body, s, sch)
    assert lay.n_s == 2 and lay.n_z == layout.NlpLayout(8).n_z + 2
    pinned = bounds(body, s, sch)
    free = bounds(body, s, sch, free=True)
    assert pinned.lbz[-2:].tolist() == pinned.ubz[-2:].tolist() == [1.1, 0.15]
    assert free.lbz[-2] == descriptors.PERIOD_RANGE_S[0] and free.ubz[-2] == 1.7
    assert free.lbg[-2:].tolist() == [0.0, 0.0] and np.isinf(free.ubg[-2:]).all()
    # a given period stays given
    one = PredictionSettings(free=("double_support",), nodes=8, period=1.1, double_support=0.15)
    b = bounds(body, one, schedule(one), free=True)
    assert b.lbz[-2] == b.ubz[-2] == 1.1 and b.lbz[-1] < 0.15 < b.ubz[-1]


@pytest.mark.model
def test_given_descriptors_keep_the_paper_problem():
    """Without a predicted descriptor the NLP is the regular-grid one: no s, the same rows and
    the same values as the values recorded before s existed (C_tor objective and g at a fixed
    point, to 1e-9)."""
    s = PredictionSettings(nodes=6, handover=False)  # the problem the values were recorded on
    prob, sch, _ = nlp.build_nlp(body_for(s), s)
    assert sch.weights is None and nlp_layout(body_for(s), s, sch).n_s == 0
    rng = np.random.default_rng(11)
    z0 = rng.uniform(-0.1, 0.1, prob["x"].numel())
    z0[layout.N_X :] += rng.uniform(0.0, 0.3, z0.size - layout.N_X)
    f, g = ca.Function("fg", [prob["x"]], [prob["f"], prob["g"]])(z0)
    assert float(f) == pytest.approx(F_GIVEN, rel=1e-9, abs=1e-9)
    assert float(np.linalg.norm(np.array(g))) == pytest.approx(G_NORM_GIVEN, rel=1e-9)


@pytest.mark.model
@pytest.mark.parametrize("grid", ["phase", "regular"], ids=["phase", "control: regular"])
def test_given_descriptors_on_the_phase_grid_are_the_pinned_free_problem(grid):
    """With ``grid = 'phase'`` a given T and Td is the problem of a predicted T and Td with s
    at those values: the same objective and rows at any point (the free one adds s and its two
    fraction rows). The regular grid places its nodes elsewhere, so the control differs."""
    given = PredictionSettings(nodes=8, period=1.1, double_support=0.15, grid=grid,
                               criterion="natural")  # fmt: skip
    free = given.replace(free=FREE, grid="regular")
    pg, sch, _ = nlp.build_nlp(body_for(given), given)
    pf, _, _ = free_nlp.build_free_nlp(body_for(free), free)
    same = pf["g"].numel() == pg["g"].numel() + 2  # the regular grid adds a toe-off loop check
    assert pf["x"].numel() == pg["x"].numel() + 2 and same == (grid == "phase")
    rng = np.random.default_rng(4)
    z = rng.uniform(-0.1, 0.1, pg["x"].numel())
    z[layout.N_X :] += rng.uniform(0.0, 0.3, z.size - layout.N_X)
    fg, gg = ca.Function("fg", [pg["x"]], [pg["f"], pg["g"]])(z)
    ff, gf = ca.Function("ff", [pf["x"]], [pf["f"], pf["g"]])(np.concatenate([z, [1.1, 0.15]]))
    rows = min(gg.numel(), gf.numel() - 2)
    gap = max(abs(float(fg - ff)), float(np.abs(np.array(gg[:rows] - gf[:rows])).max()))
    if grid == "phase":
        assert sch.times[0] + 0.15 == pytest.approx(sch.times[descriptors.ds_intervals(8)])
        assert gap < 1e-9
    else:
        assert gap > 1e-3


F_GIVEN = 3.682754201591211
G_NORM_GIVEN = 119.93297581479742
"""Computed at commit 0f8e4a5, before the descriptors could be unknowns."""


def test_first_guess_follows_published_cadence_and_given_values_stay():
    t, td = descriptors.first_guess(1.38, 1.77)
    assert 120 / t == pytest.approx(float(descriptors.published_cadence(1.38, 1.77)))
    assert 105 < 120 / t < 120 and 0.08 < td / t < 0.1
    assert descriptors.auto_descriptors(1.2, 1.7, 1.1, 0.13) == (1.1, 0.13, ())
    t2, td2, free = descriptors.auto_descriptors(1.2, 1.7, 1.1, None)
    assert free == ("double_support",) and t2 == 1.1 and 0.05 < td2 / t2 < 0.22
    t3, td3, free = descriptors.auto_descriptors(1.2, 1.7, None, 0.2)
    assert free == ("period",) and td3 == 0.2 and 0.05 <= 0.2 / t3 <= 0.22
    with pytest.raises(ValueError, match="fits no predicted period"):
        descriptors.auto_descriptors(1.2, 1.7, None, 0.5)


def test_settings_with_free_descriptors_refuse_rows_at_fixed_times():
    with pytest.raises(ValueError, match="loop_checks"):
        free_nlp.check_supported(_free(loop_checks=1))
    free_nlp.check_supported(_free())  # negative control


def test_a_joint_limit_gives_the_free_nlp_the_bounds_range_rows():
    """What-if joint limits (``--range``) with a predicted T or Td: the free NLP has the range
    rows its bounds have (they were missing: IPOPT's rows and bounds then disagreed), linear in
    the coefficients; without limits (the control) there are none."""
    from walk3d.problem.bounds import bounds
    from walk3d.problem.schedule import range_rows

    for limits in ((("knee_flexion", -0.1, 0.1),), ()):
        s = _free(changes={"limits": limits})
        body = body_for(s)
        prob, sch, _ = free_nlp.build_free_nlp(body, s, dynamics=False)
        b = bounds(body, s, sch, dynamics=False, free=True)
        assert prob["g"].numel() == b.lbg.size
        n_range = range_rows(body, s)[0].shape[0]
        assert (n_range > 0) == bool(limits)
