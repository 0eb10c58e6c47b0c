"""Finite-difference helpers shared by the physics tests."""

import numpy as np

FD_STEP = 1e-3


def fd1(f, t, h=FD_STEP):
    """Fourth-order central first derivative of f (array-valued, time first)."""
    return (-f(t + 2 * h) + 8 * f(t + h) - 8 * f(t - h) + f(t - 2 * h)) / (12 * h)


def fd2(f, t, h=FD_STEP):
    """Fourth-order central second derivative."""
    return (-f(t + 2 * h) + 16 * f(t + h) - 30 * f(t) + 16 * f(t - h) - f(t - 2 * h)) / (12 * h**2)


def assert_rel(actual, expected, rel=1e-6):
    """|actual - expected| <= rel * max|expected| (relative to the signal's scale)."""
    actual, expected = np.asarray(actual), np.asarray(expected)
    scale = max(np.max(np.abs(expected)), 1e-12)
    err = np.max(np.abs(actual - expected))
    assert err <= rel * scale, f"max error {err:.3e} > {rel:.0e} x scale {scale:.3e}"
