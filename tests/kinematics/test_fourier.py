import numpy as np

from walk3d.kinematics import fourier

T = 1.08


def test_basis_derivatives_match_finite_differences():
    rng = np.random.default_rng(3)
    c = rng.normal(size=fourier.N_COEF)
    t, h = np.linspace(0, T, 13), 1e-5
    b0, b1, b2 = fourier.basis(t, T)
    f = lambda tt: fourier.basis(tt, T)[0] @ c  # noqa: E731
    np.testing.assert_allclose(b1 @ c, (f(t + h) - f(t - h)) / (2 * h), rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(
        b2 @ c, (f(t + h) - 2 * f(t) + f(t - h)) / h**2, rtol=1e-5, atol=1e-3
    )


def test_series_is_periodic_and_half_shift_is_exact():
    rng = np.random.default_rng(4)
    c = rng.normal(size=fourier.N_COEF)
    t = np.linspace(0, T, 17)
    b0 = fourier.basis(t, T)[0]
    np.testing.assert_allclose(fourier.basis(t + T, T)[0] @ c, b0 @ c, atol=1e-12)
    shifted = fourier.basis(t + T / 2, T)[0] @ c
    np.testing.assert_allclose(b0 @ (fourier.half_cycle_shift() @ c), shifted, atol=1e-12)


def test_parity_masks_select_half_period_symmetry():
    odd = fourier.harmonic_parity_mask("odd")
    even = fourier.harmonic_parity_mask("even")
    assert odd.sum() == 6 and even.sum() == 5 and not np.any(odd & even)
    rng = np.random.default_rng(5)
    c = rng.normal(size=fourier.N_COEF) * odd
    t = np.linspace(0, T, 9)
    f = lambda tt: fourier.basis(tt, T)[0] @ c  # noqa: E731
    np.testing.assert_allclose(f(t + T / 2), -f(t), atol=1e-12)


def test_fit_recovers_coefficients():
    rng = np.random.default_rng(6)
    c = rng.normal(size=fourier.N_COEF)
    t = np.linspace(0, T, 50, endpoint=False)
    np.testing.assert_allclose(fourier.fit(t, fourier.basis(t, T)[0] @ c, T), c, atol=1e-10)
