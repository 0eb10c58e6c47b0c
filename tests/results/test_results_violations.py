"""The cycle's constraint excess: zero inside the limits, the distance × load outside."""

from types import SimpleNamespace

import numpy as np
import pytest

from walk3d import G
from walk3d.body.model import build_body
from walk3d.problem.settings import ModelSettings
from walk3d.results.violations import (
    LIMITS,
    block_violations,
    range_excess_deg,
    summarize_violations,
)


def _state(body, cop_x: float, fx: float = 0.0, clearance: float = 0.02):
    """Right foot at the origin, unrotated, carrying body weight at ``(cop_x, 0, z_mid)``."""
    wf = body.mass * G
    pts = body.foot.points("r")
    z_mid = 0.5 * (pts[2][2] + pts[3][2])
    one = np.ones(1)
    f = (fx * one, wf * one, 0.0 * one)
    m = (-z_mid * wf * one, 0.0 * one, cop_x * wf * one)
    zero = (0.0 * one,) * 3
    n = len(body.segments)
    pose = SimpleNamespace(orientation=[((one, 0 * one, 0 * one, 0 * one),)] * n,
                           origin=[((0 * one, 0 * one, 0 * one),)] * n)  # fmt: skip
    return SimpleNamespace(root="r", feet={"r": (f, m), "l": (zero, zero)}, pose=pose,
                           other_points_y=[clearance * one] * 4), wf, pts  # fmt: skip


def test_a_wrench_inside_the_foot_breaks_nothing():
    body = build_body()
    heel, toe = body.foot.points("r")[:2]
    st, wf, _ = _state(body, cop_x=0.5 * (heel[0] + toe[0]))
    v = block_violations(body, ModelSettings(), st, wf, np.zeros(1, dtype=bool))
    assert all(v[k] == 0.0 for k in v), v


def test_cop_friction_and_clearance_excess_are_measured_in_their_units():
    body = build_body()
    toe_x = body.foot.points("r")[1][0]
    st, wf, _ = _state(body, cop_x=toe_x + 0.05, fx=0.9 * body.mass * G, clearance=-0.004)
    v = block_violations(body, ModelSettings(friction=0.8), st, wf, np.zeros(1, dtype=bool))
    assert v["cop_bw_m"] == pytest.approx(0.05)  # 5 cm ahead of the toe at body weight
    assert v["friction_bw"] == pytest.approx(0.1)  # |Fx| = 0.9 BW against μ Fy = 0.8 BW
    assert v["swing_clearance_m"] == pytest.approx(0.004)
    s = summarize_violations([v], 0.0)
    assert s["worst"]["kind"] == "cop_bw_m" and not s["worst"]["holds"]


def test_joint_range_excess_in_degrees():
    ranges = np.radians(np.array([[-10.0, 10.0]] * 24))
    inside = np.zeros((5, 24))
    assert range_excess_deg(inside, ranges) == 0.0
    out = inside.copy()
    out[2, 3] = np.radians(12.5)
    assert range_excess_deg(out, ranges) == pytest.approx(2.5)
    s = summarize_violations([dict.fromkeys(LIMITS, 0.0)], 2.5)
    assert s["worst"] == {"kind": "joint_range_deg", "value": 2.5, "limit": 1.0, "holds": False}
