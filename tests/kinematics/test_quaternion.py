"""Quaternion identities, scalar-first [w, x, y, z], checked against SciPy (scalar-last)."""

import numpy as np
from scipy.spatial.transform import Rotation

from walk3d.kinematics import quaternion as qt

rng = np.random.default_rng(1)


def _random_unit(n):
    q = rng.normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def _scipy(q):
    """walk3d scalar-first -> SciPy scalar-last."""
    return Rotation.from_quat(q[:, [1, 2, 3, 0]])


def test_product_matches_scipy_composition():
    a, b = _random_unit(50), _random_unit(50)
    ours = qt.multiply(a, b)
    ref = (_scipy(a) * _scipy(b)).as_quat()[:, [3, 0, 1, 2]]
    # q and -q are the same rotation
    sign = np.sign(np.sum(ours * ref, axis=1, keepdims=True))
    np.testing.assert_allclose(ours, sign * ref, atol=1e-12)


def test_rotation_matches_scipy_apply():
    q, v = _random_unit(50), rng.normal(size=(50, 3))
    np.testing.assert_allclose(qt.rotate(q, v), _scipy(q).apply(v), atol=1e-12)


def test_conjugate_is_inverse():
    q, v = _random_unit(20), rng.normal(size=(20, 3))
    np.testing.assert_allclose(qt.rotate(qt.conjugate(q), qt.rotate(q, v)), v, atol=1e-12)
    ident = qt.multiply(q, qt.conjugate(q))
    np.testing.assert_allclose(ident, np.tile([1.0, 0, 0, 0], (20, 1)), atol=1e-12)


def test_axis_angle_scalar_first():
    q = qt.from_axis_angle(np.array([0.0, 0.0, 1.0]), np.pi / 2)
    np.testing.assert_allclose(q, [np.cos(np.pi / 4), 0, 0, np.sin(np.pi / 4)])
    # +90 deg about +z takes the forward axis (x) to up (y)
    np.testing.assert_allclose(qt.rotate(q, np.array([1.0, 0, 0])), [0, 1, 0], atol=1e-15)
    np.testing.assert_allclose(
        qt.to_matrix(q), Rotation.from_rotvec([0, 0, np.pi / 2]).as_matrix(), atol=1e-15
    )


def test_mirror_reflects_rotations_through_sagittal_plane():
    q = _random_unit(10)
    mirror = np.diag([1.0, 1.0, -1.0])
    r = qt.to_matrix(q)
    np.testing.assert_allclose(qt.to_matrix(qt.mirror(q)), mirror @ r @ mirror, atol=1e-12)


def _sine_traj(t):
    s = 0.4 * np.sin(3 * t) + 0.1
    return s, 1.2 * np.cos(3 * t), -3.6 * np.sin(3 * t)


def test_hinge_and_ball_quaternion_derivatives_match_finite_differences():
    t, h = np.linspace(0, 2, 7), 1e-5
    u = (0.0, 0.6, 0.8)
    q = qt.from_sine_triple(u, *_sine_traj(t))
    qp = qt.from_sine_triple(u, *_sine_traj(t + h))[0]
    qm = qt.from_sine_triple(u, *_sine_traj(t - h))[0]
    for c in range(4):
        np.testing.assert_allclose(q[1][c], (qp[c] - qm[c]) / (2 * h), rtol=1e-6, atol=1e-8)
        np.testing.assert_allclose(
            q[2][c], (qp[c] - 2 * q[0][c] + qm[c]) / h**2, rtol=1e-5, atol=1e-4
        )

    def vec(t):
        return (
            (0.3 * np.sin(t), 0.2 * np.cos(2 * t), 0.1 * t),
            (0.3 * np.cos(t), -0.4 * np.sin(2 * t), 0.1 + 0 * t),
            (-0.3 * np.sin(t), -0.8 * np.cos(2 * t), 0 * t),
        )

    qb = qt.from_vector_triple(*vec(t))
    qbp = qt.from_vector_triple(*vec(t + h))[0]
    qbm = qt.from_vector_triple(*vec(t - h))[0]
    np.testing.assert_allclose(qb[1][0], (qbp[0] - qbm[0]) / (2 * h), rtol=1e-6, atol=1e-8)
    np.testing.assert_allclose(
        qb[2][0], (qbp[0] - 2 * qb[0][0] + qbm[0]) / h**2, rtol=1e-4, atol=1e-4
    )
    norm = sum(c**2 for c in qb[0])
    np.testing.assert_allclose(norm, 1.0, atol=1e-14)


def test_omega_from_L_matches_rotation_finite_difference():
    t, h = np.linspace(0, 1, 5), 1e-6
    u = (0.0, 0.0, 1.0)

    def q_of(t):
        a = qt.from_sine_triple(u, *_sine_traj(t))
        b = qt.from_vector_triple(
            (0.2 * np.sin(t), 0.1 + 0 * t, 0.3 * np.cos(t)),
            (0.2 * np.cos(t), 0 * t, -0.3 * np.sin(t)),
            (-0.2 * np.sin(t), 0 * t, -0.3 * np.cos(t)),
        )
        return qt.qmul_triple(a, b)

    Q = q_of(t)
    w_b, a_b = qt.omega_alpha_body(Q)
    qa = np.stack(Q[0], axis=-1)
    rp = _scipy(np.stack(q_of(t + h)[0], -1))
    rm = _scipy(np.stack(q_of(t - h)[0], -1))
    # body-frame angular velocity: log(R^T(t-h) R(t+h)) / 2h
    w_fd = (rm.inv() * rp).as_rotvec() / (2 * h)
    np.testing.assert_allclose(np.stack(w_b, -1), w_fd, rtol=1e-6, atol=1e-7)
    # global angular velocity = R ω_body; α by differencing ω
    w_g = qt.rotate(qa, np.stack(w_b, -1))
    np.testing.assert_allclose(w_g, (rp * rm.inv()).as_rotvec() / (2 * h), rtol=1e-6, atol=1e-7)
    wp = np.stack(qt.omega_alpha_body(q_of(t + 1e-5))[0], -1)
    wm = np.stack(qt.omega_alpha_body(q_of(t - 1e-5))[0], -1)
    np.testing.assert_allclose(np.stack(a_b, -1), (wp - wm) / 2e-5, rtol=1e-6, atol=1e-6)
