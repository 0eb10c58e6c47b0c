"""Contact checks: nodes of zero weight inside the double-support intervals, whose rows hold as
a double-support node's (``settings.solver.contact_checks``); swing checks, the same in swing
and at toe off, with the swing foot above the floor (``settings.solver.swing_checks``)."""

import numpy as np
import pytest

from walk3d.problem import descriptors, layout
from walk3d.problem.bounds import bounds
from walk3d.problem.schedule import schedule
from walk3d.problem.settings import PredictionSettings, body_for

R = layout.G_ROWS


def _given(**extra) -> PredictionSettings:
    return PredictionSettings(speed=1.3, period=1.1, double_support=0.13, nodes=12, **extra)


def _free(**extra) -> PredictionSettings:
    return PredictionSettings(free=("period", "double_support"), nodes=12, period=1.1,
                              double_support=0.15, **extra)  # fmt: skip


@pytest.mark.parametrize("make", [_given, _free])
def test_checks_sit_inside_double_support_and_weigh_nothing(make):
    plain, checked = schedule(make()), schedule(make(contact_checks=2))
    assert not plain.checks.any()  # negative control: none unless asked
    check = checked.checks
    n_ds = int((plain.double_support & (plain.times - plain.times[0] > 1e-9)).sum())
    assert check.sum() >= 2 * n_ds and checked.n == plain.n + check.sum()
    np.testing.assert_array_equal(checked.times[~check], plain.times)
    tau = checked.times[check] - plain.times[0]
    td = make().gait.double_support
    assert (tau > 0).all() and (tau < td).all()
    assert checked.double_support[check].all() and not checked.swing[check].any()
    assert not np.isin(np.round(checked.times[check], 12), np.round(plain.times, 12)).any()
    w = checked.weights
    assert (w[check] == 0).all()
    half = make().gait.period / 2
    assert w.sum() == pytest.approx(half)
    w_plain = np.full(plain.n, plain.step) if plain.weights is None else plain.weights
    np.testing.assert_allclose(w[~check], w_plain)


def test_free_grid_checks_split_each_double_support_interval():
    grid = descriptors.free_grid(20, checks=1)
    assert grid.n == 20 + grid.n_ds and grid.n_checks == grid.n_ds
    np.testing.assert_allclose(grid.a[grid.check], (np.arange(grid.n_ds) + 0.5) / grid.n_ds)
    assert (grid.alpha[grid.check] == 0).all() and (grid.beta[grid.check] == 0).all()
    assert not descriptors.free_grid(20).check.any()


def test_a_check_bounds_contact_rows_and_fixes_its_slacks():
    s = _given(contact_checks=1)
    sch = schedule(s)
    b = bounds(body_for(s), s, sch)
    lay = layout.NlpLayout(sch.n, 0, 0)
    k_check = int(np.flatnonzero(sch.checks)[0])
    k_ds = 1  # a weighted double-support node
    glo = b.lbg[lay.g("node")].reshape(sch.n, layout.N_G)
    for rows in ("root_support", "other_support", "other_force"):
        np.testing.assert_array_equal(glo[k_check, R[rows]], glo[k_ds, R[rows]])
    assert np.isfinite(glo[k_check, R["root_support"]]).all()
    assert np.isneginf(glo[k_check, R["slack_pos"]]).all()  # unused: left out of the NLP
    assert (glo[k_ds, R["slack_pos"]] == 0).all()  # negative control: a node's are bounded
    t = lay.z("t")
    lo, hi = b.lbz[t].reshape(sch.n, -1), b.ubz[t].reshape(sch.n, -1)
    assert (lo[k_check] == 0).all() and (hi[k_check] == 0).all()
    assert np.isinf(hi[k_ds]).all()
    tol = s.solver.loop_check_tolerance
    ghi = b.ubg[lay.g("node")].reshape(sch.n, layout.N_G)
    np.testing.assert_allclose(ghi[k_check, R["loop_position"]], tol)
    assert (ghi[k_ds, R["loop_position"]] == 0).all()


def test_contact_checks_are_bounded():
    with pytest.raises(ValueError, match="contact checks"):
        _given(contact_checks=5)
    _given(contact_checks=4)


def test_contact_and_loop_checks_do_not_go_together():
    """Both would state the loop rows twice at the same instants (linearly dependent rows)."""
    with pytest.raises(ValueError, match="set loop checks to 0"):
        _given(contact_checks=1, loop_checks=1)
    _given(loop_checks=1)  # the control: each alone


@pytest.mark.parametrize("make", [_given, _free])
def test_swing_checks_sit_in_swing_from_toe_off_and_weigh_nothing(make):
    plain, checked = schedule(make()), schedule(make(swing_checks=1))
    check = checked.checks
    np.testing.assert_array_equal(checked.times[~check], plain.times)
    assert checked.swing[check].all() and not checked.double_support[check].any()
    tau = checked.times[check] - plain.times[0]
    g = make().gait
    assert (tau >= g.double_support - 1e-12).all() and (tau < g.period / 2).all()
    swing_nodes = int(plain.swing.sum())
    assert check.sum() >= swing_nodes  # one inside each swing interval
    assert (checked.weights[check] == 0).all()
    assert checked.weights.sum() == pytest.approx(g.period / 2)
    contact = schedule(make(contact_checks=1))  # the control: contact checks are not in swing
    assert not contact.swing[contact.checks].any()


def _floor_rows(s: PredictionSettings):
    sch = schedule(s)
    b = bounds(body_for(s), s, sch)
    glo = b.lbg[layout.NlpLayout(sch.n, 0, 0).g("node")].reshape(sch.n, layout.N_G)
    return sch, glo[:, R["other_points_y"]]


@pytest.mark.parametrize("make", [_given, _free])
def test_a_swing_check_keeps_the_swing_foot_above_the_floor_at_toe_off_too(make):
    s = make(swing_checks=1, swing_clearance=0.004)
    sch, floor = _floor_rows(s)
    assert (floor[sch.checks] == 0.0).all()  # the floor, not the clearance, near the contacts
    assert (floor[sch.swing & ~sch.checks] == 0.004).all()
    at_toe_off = np.isclose(sch.times - sch.times[0], s.gait.double_support, atol=1e-12)
    assert at_toe_off.any() and (floor[at_toe_off] == 0.0).all()
    sch0, floor0 = _floor_rows(make(swing_clearance=0.004))  # the control: no checks
    assert np.isneginf(floor0[sch0.double_support]).all()


def test_swing_checks_are_bounded():
    with pytest.raises(ValueError, match="swing checks"):
        _given(swing_checks=5)
    _given(swing_checks=4)
