"""OpenSim Z-X-Y angles of ball joints and of the pelvis, checked against SciPy."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from walk3d.kinematics import quaternion
from walk3d.results import ball_joint_angles, pelvis_angles


def _scipy_to_wxyz(rot: Rotation) -> np.ndarray:
    xyzw = rot.as_quat()
    return np.column_stack([xyzw[:, 3], xyzw[:, :3]])


def _random_angles(rng: np.random.Generator, n: int) -> np.ndarray:
    """(n, 3) [about z, about x, about y] away from the gimbal lock."""
    return np.column_stack(
        [rng.uniform(-3.0, 3.0, n), rng.uniform(-1.4, 1.4, n), rng.uniform(-3.0, 3.0, n)]
    )


def test_matches_scipy_intrinsic_zxy():
    rng = np.random.default_rng(0)
    q = _scipy_to_wxyz(Rotation.random(200, random_state=rng))
    q[::2] *= -1.0  # both quaternion signs
    expected = Rotation.from_quat(q[:, [1, 2, 3, 0]]).as_euler("ZXY")  # [z, x, y]
    got = ball_joint_angles(q, "r")
    np.testing.assert_allclose(got, expected[:, [1, 2, 0]], atol=1e-10)
    np.testing.assert_allclose(pelvis_angles(q), expected, atol=1e-10)


def test_round_trip_from_angles():
    rng = np.random.default_rng(1)
    zxy = _random_angles(rng, 100)
    q = _scipy_to_wxyz(Rotation.from_euler("ZXY", zxy))
    got = ball_joint_angles(q, "r")
    np.testing.assert_allclose(got, zxy[:, [1, 2, 0]], atol=1e-10)
    # and rebuilding the rotation from the returned angles gives the same matrix
    rebuilt = Rotation.from_euler("ZXY", got[:, [2, 0, 1]]).as_matrix()
    np.testing.assert_allclose(rebuilt, quaternion.to_matrix(q), atol=1e-12)


def test_single_axis_signs():
    # pure flexion about +z, adduction about +x, rotation about +y land in slots z, x, y
    for slot, axis in ((2, [0, 0, 1]), (0, [1, 0, 0]), (1, [0, 1, 0])):
        q = quaternion.from_axis_angle(np.array(axis, float), np.array([0.3]))
        expected = np.zeros((1, 3))
        expected[0, slot] = 0.3
        np.testing.assert_allclose(ball_joint_angles(q, "r"), expected, atol=1e-14)


def test_left_mirror_gives_identical_angles():
    rng = np.random.default_rng(2)
    q_right = _scipy_to_wxyz(Rotation.from_euler("ZXY", _random_angles(rng, 50)))
    q_left = quaternion.mirror(q_right)
    np.testing.assert_allclose(
        ball_joint_angles(q_left, "l"), ball_joint_angles(q_right, "r"), atol=1e-12
    )
    # a left rotation about the left joint's own flexion (+z), adduction (-x) and rotation
    # (-y) axes gives positive angles
    q = quaternion.from_axis_angle(np.array([-1.0, 0.0, 0.0]), np.array([0.2]))
    np.testing.assert_allclose(ball_joint_angles(q, "l"), [[0.2, 0.0, 0.0]], atol=1e-14)
    # without mirroring, the angles of the mirrored posture differ in x and y
    unmirrored = ball_joint_angles(q_left, "r")
    np.testing.assert_allclose(unmirrored[:, 2], ball_joint_angles(q_right, "r")[:, 2], atol=1e-12)
    assert not np.allclose(unmirrored[:, :2], ball_joint_angles(q_right, "r")[:, :2])


def test_rejects_bad_input():
    with pytest.raises(ValueError):
        ball_joint_angles(np.zeros((3, 3)), "r")
    with pytest.raises(ValueError):
        ball_joint_angles(np.zeros((2, 4)), "r")
    with pytest.raises(ValueError):
        ball_joint_angles(np.tile([1.0, 0, 0, 0], (2, 1)), "x")
