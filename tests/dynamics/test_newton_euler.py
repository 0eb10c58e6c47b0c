"""Inverse dynamics: the equations of motion hold and momentum balances."""

import numpy as np
import pytest
from helpers import assert_rel, fd1

from walk3d import G
from walk3d.dynamics.newton_euler import (
    inertial_loads,
    joint_loads,
    resolve_joint_moments,
    segment_residuals,
    total_ground_reaction,
    waist_from_below,
)
from walk3d.kinematics.forward import forward, joint_quaternions, root_foot_triples, stack_v
from walk3d.kinematics.quaternion import qrot, qrot_inv

T0 = np.array([0.1, 0.37, 0.52, 0.8])


def _momenta(body, pose):
    """Whole-body linear and angular momentum about the origin, (N, 3) each."""
    p = 0.0
    h = 0.0
    for i, seg in enumerate(body.segments):
        r, v = stack_v(pose.com[i][0]), stack_v(pose.com[i][1])
        q = pose.orientation[i][0]
        w_b = qrot_inv(q, pose.omega[i])
        iw = stack_v(qrot(q, tuple(seg.inertia[k] * w_b[k] for k in range(3))))
        p = p + seg.mass * v
        h = h + iw + seg.mass * np.cross(r, v)
    return p, h


def test_total_force_equals_momentum_rate_minus_weight(body, random_motion):
    f, _ = total_ground_reaction(body, random_motion(T0))
    p_dot = fd1(lambda t: _momenta(body, random_motion(t))[0], T0)
    assert_rel(stack_v(f), p_dot + np.array([0.0, body.mass * G, 0.0]))


def test_total_moment_equals_angular_momentum_rate_minus_gravity_moment(body, random_motion):
    pose = random_motion(T0)
    _, m = total_ground_reaction(body, pose)
    h_dot = fd1(lambda t: _momenta(body, random_motion(t))[1], T0)
    grav = sum(
        np.cross(stack_v(pose.com[i][0]), [0.0, -seg.mass * G, 0.0])
        for i, seg in enumerate(body.segments)
    )
    assert_rel(stack_v(m), h_dot - grav)


def _split_evenly(body, pose):
    """Put the whole reaction on the right foot, a known wrench elsewhere: any split works."""
    f, m = total_ground_reaction(body, pose)
    fl = tuple(0.3 * c for c in f)
    ml = tuple(0.3 * c for c in m)
    fr = tuple(a - b for a, b in zip(f, fl, strict=True))
    mr = tuple(a - b for a, b in zip(m, ml, strict=True))
    return {body.segment_index("foot_r"): (fr, mr), body.segment_index("foot_l"): (fl, ml)}


def test_every_segment_satisfies_newton_euler(body, random_motion):
    pose = random_motion(T0)
    ext = _split_evenly(body, pose)
    loads = joint_loads(body, pose, ext)
    res = segment_residuals(body, pose, loads, ext)
    scale = body.mass * G
    for i, (rf, rm) in enumerate(res):
        assert np.max(np.abs(stack_v(rf))) < 1e-9 * scale, body.segments[i].name
        assert np.max(np.abs(stack_v(rm))) < 1e-9 * scale, body.segments[i].name


def test_waist_from_above_equals_waist_from_below(body, random_motion):
    pose = random_motion(T0)
    ext = _split_evenly(body, pose)
    loads = joint_loads(body, pose, ext)
    f_below, m_below = waist_from_below(body, pose, loads, ext)
    w = body.joint_index("waist")
    np.testing.assert_allclose(stack_v(f_below), stack_v(loads.force[w]), atol=1e-9)
    np.testing.assert_allclose(stack_v(m_below), stack_v(loads.moment[w]), atol=1e-9)
    # a wrong ground reaction breaks the agreement: the check can fail
    bad = dict(ext)
    k = body.segment_index("foot_l")
    bad[k] = (tuple(c * 1.01 for c in ext[k][0]), ext[k][1])
    loads_bad = joint_loads(body, pose, bad)
    f_bad, _ = waist_from_below(body, pose, loads_bad, bad)
    assert np.max(np.abs(stack_v(f_bad) - stack_v(loads_bad.force[w]))) > 1e-3


@pytest.fixture()
def standing(body):
    zero = np.zeros(1)
    jq = joint_quaternions(body, [(zero, zero, zero)] * 24)
    q, p = root_foot_triples(body, "r", (zero, zero, zero), (0.0, body.joints[6].offset[2]))
    return forward(body, jq, body.segment_index("foot_r"), q, p)


def test_standing_body_carries_exactly_its_weight(body, standing):
    f, m = total_ground_reaction(body, standing)
    f = stack_v(f)[0]
    assert f[1] == pytest.approx(body.mass * G, rel=1e-15)
    assert abs(f[0]) < 1e-12 and abs(f[2]) < 1e-12
    forces, torques = inertial_loads(body, standing)
    for t in torques:
        assert np.max(np.abs(stack_v(t))) < 1e-12


def test_standing_on_both_feet_gives_small_symmetric_joint_moments(body, standing):
    from walk3d.contact.transition import static_split

    ext = static_split(body, standing)
    fr = stack_v(ext[body.segment_index("foot_r")][0])[0]
    fl = stack_v(ext[body.segment_index("foot_l")][0])[0]
    assert fr[1] == pytest.approx(body.mass * G / 2, rel=1e-12)
    assert fl[1] == pytest.approx(fr[1], rel=1e-12)
    loads = joint_loads(body, standing, ext)
    moments = np.array([stack_v(m)[0] for m in resolve_joint_moments(body, standing, loads)])
    # upright with all segments stacked: every sagittal/frontal moment is small (< 1 N m) ...
    assert np.max(np.abs(moments[:, [0, 2]])) < 1.0
    # ... and right and left mirror each other (x and y flip sign with the mirrored axes)
    for r, left in (
        ("hip_r", "hip_l"),
        ("knee_r", "knee_l"),
        ("ankle_r", "ankle_l"),
        ("shoulder_r", "shoulder_l"),
    ):
        np.testing.assert_allclose(
            moments[body.joint_index(r)], moments[body.joint_index(left)], atol=1e-9
        )
