"""Decision-vector layout, gait phases, criteria algebra and settings validation."""

import numpy as np
import pytest

from walk3d.contact.phases import GaitPhases
from walk3d.kinematics import fourier
from walk3d.model.criteria import node_terms, split_by_axis
from walk3d.problem import layout
from walk3d.problem.settings import PredictionSettings, first_error

T = 1.08


def test_layout_has_the_papers_165_coefficients_plus_step_width():
    assert layout.N_SERIES == 15 and layout.N_COEF == 11
    assert layout.N_X == 166 and layout.I_HALF_STEP == 165
    assert len(layout.COORD_SOURCE) == layout.N_COORD == 26


def test_left_coordinates_are_right_shifted_by_half_a_cycle():
    rng = np.random.default_rng(0)
    x = rng.normal(size=layout.N_X)
    t = np.linspace(0, T, 7)
    a0, a1, _ = layout.coordinate_maps(t, T)
    a0s, a1s, _ = layout.coordinate_maps(t + T / 2, T)
    # hip_r (coordinate 12) at t + T/2 equals hip_l (coordinate 18) at t; same for rates
    np.testing.assert_allclose(a0s[:, 12] @ x, a0[:, 18] @ x, atol=1e-12)
    np.testing.assert_allclose(a1s[:, 24] @ x, a1[:, 25] @ x, atol=1e-12)
    # the coordinate map is the Fourier basis of the series' coefficients
    b0 = fourier.basis(t, T)[0]
    np.testing.assert_allclose(a0[:, 15] @ x, b0 @ layout.coefficients(x)[11], atol=1e-12)


def test_midline_symmetry_mask_makes_waist_mirror_every_half_cycle():
    rng = np.random.default_rng(1)
    x = rng.normal(size=layout.N_X)
    x[layout.fixed_zero_mask()] = 0.0
    t = np.linspace(0, T, 9)
    a0, _, _ = layout.coordinate_maps(t, T)
    a0s, _, _ = layout.coordinate_maps(t + T / 2, T)
    # frontal/transverse waist elements flip sign, sagittal waist and neck repeat
    np.testing.assert_allclose(a0s[:, 0] @ x, -(a0[:, 0] @ x), atol=1e-12)
    np.testing.assert_allclose(a0s[:, 1] @ x, -(a0[:, 1] @ x), atol=1e-12)
    np.testing.assert_allclose(a0s[:, 2] @ x, a0[:, 2] @ x, atol=1e-12)
    np.testing.assert_allclose(a0s[:, 3] @ x, a0[:, 3] @ x, atol=1e-12)
    assert layout.fixed_zero_mask().sum() == 2 * 5 + 2 * 6


def test_phases_match_the_papers_timeline():
    ph = GaitPhases(1.08, 0.16)
    assert ph.heel_strike_r / 1.08 == pytest.approx(0.352, abs=1e-3)  # paper: 36 %
    assert ph.heel_strike_l / 1.08 == pytest.approx(0.852, abs=1e-3)  # paper: 86 %
    t = np.array([0.1, 0.45, 0.6, 1.0])
    np.testing.assert_array_equal(ph.in_stance(t, "r"), [False, True, True, True])
    np.testing.assert_array_equal(ph.in_stance(t, "l"), [True, True, False, True])
    np.testing.assert_array_equal(ph.root_is_right(t), [False, True, True, False])
    # the trailing foot is fully loaded at heel strike and unloaded (exp(-8)) at its toe off
    assert ph.trailing_decay(np.array([ph.heel_strike_r]))[0] == 1.0
    assert ph.trailing_decay(np.array([ph.toe_off_l]))[0] == pytest.approx(np.exp(-8))
    assert ph.trailing_decay(np.array([0.7]))[0] == 0.0


def test_direction_dependent_normalization_is_exact():
    pos, neg = np.array([100.0, 40.0]), np.array([50.0, 80.0])
    a, b = 0.5 * (1 / pos + 1 / neg), 0.5 * (1 / pos - 1 / neg)
    m = [np.array([30.0, -30.0]), np.array([-8.0, 8.0])]
    tor, _ = node_terms(m, [np.ones(2), np.ones(2)], a, b, None)
    np.testing.assert_allclose(tor[0], [30 / 100, 30 / 50])
    np.testing.assert_allclose(tor[1], [8 / 80, 8 / 40])
    smooth, _ = node_terms(m, [np.ones(2), np.ones(2)], a, b, 1e-3)
    assert np.all(smooth[0] >= tor[0]) and np.all(smooth[0] - tor[0] < 1e-3)


def test_axis_split_sums_to_total():
    s = split_by_axis(np.array([1.0, 2.0, 3.0, 4.0]), [0, 2, 2, 1])
    assert s == {"x": 1.0, "y": 4.0, "z": 5.0, "total": 10.0}


def test_balance_progress_checks_read_as_iteration_to_violation():
    assert PredictionSettings().solver.progress_checks() == {60: 3.0, 80: 0.1}
    assert PredictionSettings(balance_progress_check=(80, 0.1)).solver.progress_checks() == {
        80: 0.1
    }
    assert PredictionSettings(balance_progress_check=None).solver.progress_checks() == {}
    # a copy skips validation; the single pair is still one check
    copy = PredictionSettings().replace(**{"balance_progress_check": (5, 1.0)})
    assert copy.solver.progress_checks() == {5: 1.0}


@pytest.mark.parametrize(
    "kwargs,words",
    [
        ({"speed": 0.0}, "speed"),
        ({"speed": -1.0}, "speed"),
        ({"period": 0.0}, "period"),
        ({"double_support": 0.0}, "double-support"),
        ({"double_support": 0.6}, "2%-30% of T"),
        ({"speed": float("nan")}, "finite"),
        ({"mass": 5.0}, "mass"),
        ({"height": 3.5}, "height"),
        ({"balance_progress_check": (0, 0.1)}, "balance progress check"),
        ({"balance_progress_check": (80, -1.0)}, "balance progress check"),
        ({"balance_progress_check": ((60, 3.0), (0, 0.1))}, "balance progress check"),
        ({"posture_balance_max_iter": 0}, "iteration limits"),
        ({"full_max_iter": 0}, "iteration limits"),
    ],
)
def test_bad_settings_give_one_clear_message(kwargs, words):
    with pytest.raises(ValueError) as exc:
        PredictionSettings(**kwargs)
    msg = first_error(exc.value)
    assert words in msg and "\n" not in msg
