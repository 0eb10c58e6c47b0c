"""The stance foot's rockers and load (#41): heel rise in late single stance, and the leading
foot's load ramp at heel strike."""

import numpy as np
import pytest

from walk3d.contact.phases import GaitPhases, trailing_share
from walk3d.problem import descriptors, layout
from walk3d.problem.bounds import bounds
from walk3d.problem.schedule import schedule
from walk3d.problem.settings import PredictionSettings, body_for


def _slope_at_zero(ramp):
    h = 1e-6
    return (trailing_share(h, ramp) - trailing_share(0.0, ramp)) / h


@pytest.mark.parametrize("ramp", [0.0, 1.0, 2.0, 3.0])
def test_the_load_ramp_starts_with_its_slope_ends_at_zero_and_falls(ramp):
    x = np.linspace(0.0, 1.0, 201)
    e = trailing_share(x, ramp)
    assert e[0] == 1.0 and e[-1] == 0.0
    assert np.all(np.diff(e) <= 1e-12)  # the trailing foot only unloads
    assert float(_slope_at_zero(ramp)) == pytest.approx(-ramp, abs=1e-4)
    # at toe off the share leaves with zero slope (C¹ there)
    assert float((trailing_share(1.0, ramp) - trailing_share(1.0 - 1e-6, ramp)) / 1e-6) == (
        pytest.approx(0.0, abs=1e-4)
    )


def test_the_papers_share_starts_flat_so_the_slope_check_can_fail():
    assert float(_slope_at_zero(None)) == pytest.approx(0.0, abs=1e-4)
    assert float(_slope_at_zero(None)) != pytest.approx(-2.0, abs=1e-4)
    np.testing.assert_allclose(
        trailing_share(np.array([0.25, 0.5]), None), np.exp(-np.array([0.125, 1.0]))
    )


def test_the_ramp_reaches_the_nodes_on_both_grids_and_the_cycle():
    s = PredictionSettings(load_ramp=2.0)
    sch = schedule(s)
    ph = GaitPhases(s.gait.period, s.gait.double_support, 2.0)
    np.testing.assert_allclose(sch.decay, ph.trailing_decay(sch.times))
    x = (sch.times - sch.times[0]) / s.gait.double_support
    ds = sch.double_support
    np.testing.assert_allclose(sch.decay[ds], (1 - x[ds]) ** 2 * (1 + 0 * x[ds]))
    assert not np.allclose(sch.decay, schedule(PredictionSettings()).decay)  # control
    free = PredictionSettings(load_ramp=2.0, free=("period", "double_support"))
    grid = descriptors.free_grid(free.solver.nodes, ramp=2.0)
    np.testing.assert_allclose(schedule(free).decay, grid.decay)
    assert grid.decay[1] == pytest.approx(trailing_share(grid.a[1], 2.0))
    assert grid.decay[1] != pytest.approx(descriptors.free_grid(free.solver.nodes).decay[1])


def _root_foot_lower_bound(s):
    b = bounds(body_for(s), s, sch := schedule(s))
    n_x = layout.N_X
    y = b.lbz[n_x : n_x + sch.n * 3 * layout.N_COORD].reshape(sch.n, 3, layout.N_COORD)
    return sch, y[:, 0, layout.I_FOOT_R]


def test_heel_rise_frees_the_root_foot_toes_down_only_after_its_fraction_of_stance():
    s = PredictionSettings(heel_rise=0.6)
    sch, lo = _root_foot_lower_bound(s)
    _, lo0 = _root_foot_lower_bound(PredictionSettings())
    tau = sch.times - sch.times[0]
    late = sch.swing & (tau >= 0.6 * (s.gait.period / 2 + s.gait.double_support))
    assert late.any() and not late.all()
    assert np.all(lo[late] < -0.5)  # toes down to the toe rocker's limit (75°)
    np.testing.assert_array_equal(lo[~late], lo0[~late])
    flat = np.sin(s.model.foot_flat_tolerance / 2)
    assert np.all(lo0[sch.swing] == -flat)  # control: without it the foot stays flat


@pytest.mark.parametrize(
    ("field", "value", "words"),
    [("heel_rise", 0.1, "heel_rise"), ("heel_rise", 1.5, "heel_rise"),
     ("load_ramp", -1.0, "load_ramp"), ("load_ramp", 4.0, "load_ramp")],
)  # fmt: skip
def test_out_of_range_stance_settings_are_one_line_errors(field, value, words):
    with pytest.raises(ValueError, match=words) as info:
        PredictionSettings(**{field: value})
    assert "\n" not in str(info.value)
    PredictionSettings(**{field: 0.6 if field == "heel_rise" else 2.0})  # control: accepted
