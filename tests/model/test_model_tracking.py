"""The track term's target and integrand (:mod:`walk3d.model.tracking`)."""

import numpy as np
import pytest

from walk3d.model.tracking import TRACK_REF, Tracking, fit_series, integrand


def _tracking(weights=None, coef=None) -> Tracking:
    c = np.zeros((24, 21)) if coef is None else coef
    w = np.ones(24) if weights is None else weights
    return Tracking(coefficients=tuple(map(tuple, c)), weights=tuple(w))


def test_fit_series_is_exact_for_a_band_limited_signal():
    phase = np.linspace(0, 1, 100, endpoint=False)
    signal = np.column_stack([0.3 + 0.2 * np.cos(2 * np.pi * 3 * phase),
                              0.1 * np.sin(2 * np.pi * 10 * phase)])  # fmt: skip
    coef = fit_series(phase, signal)
    t = _tracking(coef=np.vstack([coef, np.zeros((22, 21))]))
    np.testing.assert_allclose(t.target(phase)[:, :2], signal, atol=1e-12)
    # negative control: a harmonic above the order is not followed
    high = np.sin(2 * np.pi * 11 * phase)[:, None]
    assert np.max(np.abs(_basis_fit(phase, high) - high)) > 0.5


def _basis_fit(phase, values):
    coef = fit_series(phase, values)
    return _tracking(coef=np.vstack([coef, np.zeros((23, 21))])).target(phase)[:, :1]


def test_the_integrand_is_the_weighted_mean_square_deviation_over_the_scale():
    w = np.zeros(24)
    w[[14, 15]] = [1.0, 3.0]
    t = _tracking(weights=w)
    axes = [0, 1, 2] * 8
    values = [np.full(5, 0.1) for _ in range(24)]
    target = np.zeros((5, 24))
    x, y, z = integrand(t, values, target, axes)
    expect = (1.0 * 0.2**2 + 3.0 * 0.2**2) / (4.0 * TRACK_REF**2)
    np.testing.assert_allclose(x + y + z, expect)
    np.testing.assert_allclose(z, expect / 4)  # DoF 14 on axis 2 of this labelling
    np.testing.assert_allclose(x, 3 * expect / 4)  # DoF 15 on axis 0
    target[:, :] = 0.2  # on target: nothing to pay
    assert np.all(sum(integrand(t, values, target, axes)) == 0)


@pytest.mark.parametrize("bad", [
    {"weights": np.zeros(24)},
    {"weights": -np.ones(24)},
    {"coef": np.zeros((23, 21))},
    {"coef": np.full((24, 21), np.nan)},
])  # fmt: skip
def test_a_bad_target_is_refused(bad):
    with pytest.raises(ValueError):
        _tracking(**bad)
    _tracking()  # control
