"""Centre-of-pressure and free-moment rows: zero on the boundary, sign tells inside/outside."""

import numpy as np
import pytest

from walk3d.contact.support import support_rows

HEEL, TOE = (-0.05, 0.0, 0.0), (0.21, 0.0, 0.0)
MET1, MET5 = (0.14, 0.0, -0.03), (0.12, 0.0, 0.04)  # right foot: met1 medial (-z)


def _wrench(p, force, torque):
    """Ground wrench of ``force`` at floor point ``p`` plus free moment ``torque`` about y."""
    m = np.cross(p, force) + np.array([0.0, torque, 0.0])
    return tuple(force), tuple(m)


def _rows(p, force=(30.0, 700.0, -20.0), torque=0.0, radius=0.02):
    w = _wrench(np.array(p), np.array(force), torque)
    return np.array(support_rows(w, [HEEL, TOE, MET1, MET5], "r", 700.0, 0.8, radius))


def test_rows_are_the_distances_of_the_cop_to_the_footprint_edges():
    r = _rows((0.10, 0.0, 0.01))
    fy = 700.0 / 700.0
    np.testing.assert_allclose(r[:4], [0.15 * fy, 0.11 * fy, 0.04 * fy, 0.03 * fy], atol=1e-12)


@pytest.mark.parametrize(
    ("p", "row"), [((-0.06, 0, 0), 0), ((0.22, 0, 0), 1), ((0.1, 0, -0.04), 2), ((0.1, 0, 0.05), 3)]
)
def test_a_cop_outside_the_foot_breaks_exactly_one_row(p, row):
    r = _rows(p)
    assert r[row] < 0
    assert np.all(np.delete(r[:4], row) > 0)


def test_free_moment_rows_bound_the_twist_by_torsional_friction():
    limit = 0.8 * 0.02 * 700.0  # 11.2 N m
    inside = _rows((0.1, 0.0, 0.0), torque=0.9 * limit)
    outside = _rows((0.1, 0.0, 0.0), torque=-1.1 * limit)
    assert np.all(inside[4:] > 0)
    assert outside[4] > 0 > outside[5]
    on_edge = _rows((0.1, 0.0, 0.0), torque=limit)
    assert on_edge[4] == pytest.approx(0.0, abs=1e-12)
