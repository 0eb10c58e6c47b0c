"""Forward kinematics from the stance foot: exact derivatives and geometry."""

import numpy as np
import pytest
from helpers import assert_rel, fd1, fd2

from walk3d.kinematics import quaternion as qt
from walk3d.kinematics.forward import (
    forward,
    joint_quaternions,
    point_triple,
    root_foot_triples,
    stack_q,
    stack_v,
)

T0 = np.array([0.05, 0.3, 0.61, 0.9])


@pytest.mark.parametrize("seg", range(13))
def test_com_velocity_and_acceleration_match_finite_differences(random_motion, seg):
    def x(t):
        return stack_v(random_motion(t).com[seg][0])

    p0 = random_motion(T0)
    assert_rel(stack_v(p0.com[seg][1]), fd1(x, T0))
    assert_rel(stack_v(p0.com[seg][2]), fd2(x, T0))


@pytest.mark.parametrize("seg", range(13))
def test_angular_velocity_and_acceleration_match_finite_differences(random_motion, seg):
    from scipy.spatial.transform import Rotation

    p0 = random_motion(T0)

    def rot(t):
        return Rotation.from_quat(stack_q(random_motion(t).orientation[seg][0])[:, [1, 2, 3, 0]])

    # rotation vector of R(t) R(t0)^-1 near t0: its derivative at t0 is the global omega
    def rel_rotvec(t):
        return (rot(t) * rot(T0).inv()).as_rotvec()

    assert_rel(stack_v(p0.omega[seg]), fd1(rel_rotvec, T0))

    def omega(t):
        return stack_v(random_motion(t).omega[seg])

    assert_rel(stack_v(p0.alpha[seg]), fd1(omega, T0))


def test_orientations_stay_unit(random_motion):
    p = random_motion(np.linspace(0, 1, 20))
    for q in p.orientation:
        np.testing.assert_allclose(np.linalg.norm(stack_q(q[0]), axis=1), 1.0, atol=1e-13)


def test_upright_standing_geometry(body):
    zero = np.zeros(1)
    dof = [(zero, zero, zero)] * 24
    jq = joint_quaternions(body, dof)
    q, p = root_foot_triples(body, "r", (zero, zero, zero), (0.0, 0.1))
    pose = forward(body, jq, body.segment_index("foot_r"), q, p)
    # ankle at its height above the floor, heel and toe on the floor
    heel = stack_v(point_triple(pose, 9, body.foot.heel)[0])[0]
    assert abs(heel[1]) < 1e-12
    left_heel = stack_v(point_triple(pose, 12, body.foot.points("l")[0])[0])[0]
    assert abs(left_heel[1]) < 1e-12
    # the left foot is the mirror of the right about the pelvis midline
    pelvis = stack_v(pose.origin[0][0])[0]
    np.testing.assert_allclose(left_heel[2] - pelvis[2], -(heel[2] - pelvis[2]), atol=1e-12)
    # the top of the head is near stature (de Leva lengths chain to about 1 % of it)
    head = stack_v(pose.origin[2][0])[0]
    top = head[1] + body.segments[2].length
    assert abs(top - body.height) / body.height < 0.03
    for i in range(13):
        np.testing.assert_allclose(stack_q(pose.orientation[i][0])[0], [1, 0, 0, 0], atol=1e-14)


def test_stance_foot_follows_rollover_without_slip(body):
    t = np.linspace(-0.3, 0.2, 6)  # s = sin(theta/2) directly
    one = np.ones_like(t)
    q, p = root_foot_triples(body, "r", (t, 0 * one, 0 * one), (0.2, 0.1))
    pose_p = stack_v(p[0])
    # contact point on the arc is instantaneously at rest: the ankle moves as a rolling body,
    # so its height stays near the ankle height and it moves forward as the toes go down
    assert np.all(np.diff(pose_p[:, 0]) < 0)
    np.testing.assert_allclose(
        pose_p[np.argmin(abs(t)), :], [0.2, body.foot.ankle_height, 0.1], atol=1e-12
    )
    ql, pl = root_foot_triples(body, "l", (t, 0 * one, 0 * one), (0.2, -0.1))
    np.testing.assert_allclose(qt.mirror(stack_q(q[0])), stack_q(ql[0]), atol=1e-14)
