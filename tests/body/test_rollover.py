"""Roll-over spline: exact derivatives, the default arc, and fitting from measured paths."""

import numpy as np

from walk3d.body.rollover import RollOver, arc_ankle_path, arc_rollover, fit_rollover


def test_spline_interpolates_its_knots_with_exact_derivatives():
    s = np.linspace(-0.4, 0.3, 8)
    xyz = np.stack([np.sin(3 * s), 0.07 + s**2, 0.01 * s], axis=1)
    ro = RollOver.from_samples(s, xyz)
    v, d1, d2 = ro.evaluate(s)
    np.testing.assert_allclose(np.stack(v, axis=1), xyz, atol=1e-12)
    q, h = np.linspace(-0.35, 0.25, 9), 1e-4
    v0, d1, d2 = (np.stack(a, axis=1) for a in ro.evaluate(q))
    vp = np.stack(ro.evaluate(q + h)[0], axis=1)
    vm = np.stack(ro.evaluate(q - h)[0], axis=1)
    np.testing.assert_allclose(d1, (vp - vm) / (2 * h), atol=1e-6)
    np.testing.assert_allclose(d2, (vp - 2 * v0 + vm) / h**2, atol=1e-3)


def test_default_arc_rolls_without_slip():
    # rolling: the ankle's horizontal travel over a rotation is radius x angle (plus the lever)
    theta = np.radians(np.array([-30.0, 0.0, 20.0]))
    p = arc_ankle_path(theta, radius=0.35, centre_forward=0.03, ankle_height=0.07)
    np.testing.assert_allclose(p[1], [0.0, 0.07, 0.0], atol=1e-15)
    assert p[0, 0] > 0 > p[2, 0]  # toes down -> ankle ahead; heel down -> ankle behind
    ro = arc_rollover(0.35, 0.03, 0.07)
    v = np.stack(ro.evaluate(np.sin(theta / 2))[0], axis=1)
    np.testing.assert_allclose(v, p, atol=2e-4)


def test_fit_recovers_a_rolling_foot_from_heel_ankle_and_toe_paths():
    radius, cf, ha = 0.35, 0.03, 0.07
    theta = np.radians(np.linspace(20, -40, 120))
    ankle = arc_ankle_path(theta, radius, cf, ha) + [0.4, 0.0, 0.1]
    heel_local = np.array([-0.05, -ha, 0.0])
    toe_local = np.array([0.21, -ha, 0.0])

    def rot(v):
        c, s = np.cos(theta), np.sin(theta)
        return np.stack([c * v[0] - s * v[1], s * v[0] + c * v[1], np.full_like(c, v[2])], 1)

    ro = fit_rollover(ankle + rot(heel_local), ankle, ankle + rot(toe_local), 9, flat_pitch=0.0)
    fitted = np.stack(ro.evaluate(np.sin(theta / 2))[0], axis=1)
    expect = ankle - ankle[np.argmin(np.abs(theta))]
    expect[:, 1] = ankle[:, 1]
    np.testing.assert_allclose(fitted, expect, atol=1e-3)
    # markers at unequal heights: the slowest-rotation rule finds the flat foot instead
    t = np.linspace(-1, 1, 200)
    theta = np.radians(np.where(t < 0, 20 * t**2 * np.sign(-t), -40 * t**2))
    ankle = arc_ankle_path(theta, radius, cf, ha)
    raised_toe = toe_local + [0.0, 0.02, 0.0]
    ro = fit_rollover(ankle + rot(heel_local), ankle, ankle + rot(raised_toe), 9)
    fitted = np.stack(ro.evaluate(np.sin(theta / 2))[0], axis=1)
    np.testing.assert_allclose(fitted[:, 1], ankle[:, 1], atol=1e-3)
