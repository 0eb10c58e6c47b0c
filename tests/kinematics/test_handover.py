"""The root passed from the trailing to the leading foot (blended_root): a rigid motion of the
whole body with exact derivatives, rooted at the trailing foot at share 1."""

import numpy as np
import pytest
from helpers import assert_rel, fd1, fd2

from walk3d.contact.phases import GaitPhases, handover_share
from walk3d.kinematics import fourier
from walk3d.kinematics.forward import (
    blended_root,
    forward,
    joint_quaternions,
    root_foot_triples,
    stack_q,
    stack_v,
)

PERIOD = 1.08

T0 = np.array([0.41, 0.45, 0.5])
"""Inside the double support that starts at 0.38 s (T 1.08 s, Td 0.16 s)."""
PHASES = GaitPhases(PERIOD, 0.16)


@pytest.fixture(scope="module")
def motion(body):
    rng = np.random.default_rng(11)
    decay = np.array([1.0] + [1.0 / k for k in range(1, 6) for _ in range(2)])
    coef = rng.uniform(-1, 1, (26, fourier.N_COEF)) * decay * 0.15
    i_l, i_r = body.segment_index("foot_l"), body.segment_index("foot_r")

    def at(t, share=None):
        """The chain from the right foot, and the body blended towards the left foot's own
        roll-over pose by ``share(t)`` (default: the handover share)."""
        b = fourier.basis(np.atleast_1d(t), PERIOD)
        c = [tuple(m @ row for m in b) for row in coef]
        jq = joint_quaternions(body, c[:24])
        root = root_foot_triples(body, "r", c[24], (0.0, 0.1))
        pose = forward(body, jq, i_r, *root)
        expected = root_foot_triples(body, "l", tuple(0.7 * v for v in c[25]), (-0.7, -0.1))
        chain = (pose.orientation[i_l], pose.origin[i_l])
        h = PHASES.handover(np.atleast_1d(t)) if share is None else share(np.atleast_1d(t))
        return pose, forward(body, jq, i_r, *blended_root(root, chain, expected, h)), expected

    return at


def test_the_share_falls_from_one_to_zero_with_flat_ends():
    h, d1, d2 = handover_share(np.array([0.0, 0.5, 1.0]))
    np.testing.assert_allclose(h, [1.0, 0.5, 0.0])
    np.testing.assert_allclose(d1[[0, 2]], 0.0) and np.testing.assert_allclose(d2[[0, 2]], 0.0)
    x = np.linspace(0.1, 0.9, 5)
    assert_rel(handover_share(x)[1], fd1(lambda v: handover_share(v)[0], x))
    assert_rel(handover_share(x)[2], fd2(lambda v: handover_share(v)[0], x))
    h, hd, _ = PHASES.handover(np.array([0.2, 0.38, 0.54, 0.7]))  # swing, heel strike, toe off
    np.testing.assert_allclose(h, [0.0, 1.0, 0.0, 0.0], atol=1e-12)


@pytest.mark.parametrize("seg", [0, 3, 9, 12])
def test_blended_velocities_and_accelerations_match_finite_differences(motion, seg):
    def x(t):
        return stack_v(motion(t)[1].com[seg][0])

    blended = motion(T0)[1]
    assert_rel(stack_v(blended.com[seg][1]), fd1(x, T0))
    assert_rel(stack_v(blended.com[seg][2]), fd2(x, T0))


def test_a_share_without_its_rates_fails_the_finite_differences(motion):
    """Negative control: the share's time derivatives matter (they carry the landing)."""

    def frozen(t):
        return (PHASES.handover(t)[0], 0.0 * t, 0.0 * t)

    def x(t):
        return stack_v(motion(t, frozen)[1].com[0][0])

    with pytest.raises(AssertionError):
        assert_rel(stack_v(motion(T0, frozen)[1].com[0][1]), fd1(x, T0))


def test_share_one_roots_the_body_at_the_trailing_foot_and_zero_leaves_it(motion, body):
    i_l = body.segment_index("foot_l")
    one = lambda t: (1.0 + 0.0 * t, 0.0 * t, 0.0 * t)  # noqa: E731
    zero = lambda t: (0.0 * t, 0.0 * t, 0.0 * t)  # noqa: E731
    chain, rooted, (q_exp, p_exp) = motion(T0, one)
    for d in range(3):  # pose, velocity and acceleration of the trailing foot are its own
        assert_rel(stack_v(rooted.origin[i_l][d]), stack_v(p_exp[d]), 1e-10)
    np.testing.assert_allclose(stack_q(rooted.orientation[i_l][0]), stack_q(q_exp[0]), atol=1e-12)
    assert np.abs(stack_v(chain.origin[i_l][1]) - stack_v(p_exp[1])).max() > 1e-3  # control
    _, same, _ = motion(T0, zero)
    for seg in range(13):
        for d in range(3):
            np.testing.assert_allclose(stack_v(same.com[seg][d]), stack_v(chain.com[seg][d]),
                                       atol=1e-12)  # fmt: skip


def test_the_blend_is_rigid(motion, body):
    chain, blended, _ = motion(T0)
    a, b = (np.stack([stack_v(p.com[i][0]) for i in range(13)], axis=1) for p in (chain, blended))
    d_chain = np.linalg.norm(a[:, :, None] - a[:, None, :], axis=-1)
    d_blend = np.linalg.norm(b[:, :, None] - b[:, None, :], axis=-1)
    np.testing.assert_allclose(d_blend, d_chain, atol=1e-12)
    assert np.abs(b - a).max() > 1e-3  # the random loop is open: the blend moves the body
