"""The pure comparisons of walk3d verify, and model.osim's ranges against predicted motion
(no OpenSim needed)."""

from __future__ import annotations

import numpy as np
import pytest

import walk3d.results.osim_model as osim_model_module
from walk3d.verify.compare import (
    BARS,
    FLEXION_COORDINATES,
    RESIDUAL_FORCES,
    compare_generalized_forces,
    foot_flat_mask,
    largest_drift,
    smooth_mask,
)

T = np.linspace(0.0, 1.0, 101)
W = 700.0


def _walk3d():
    out = {f"{c}_moment": 50 * np.sin(2 * np.pi * T + k) for k, c in enumerate(FLEXION_COORDINATES)}
    out.update({f: np.zeros_like(T) for f in RESIDUAL_FORCES})
    return out


def test_identical_forces_pass_and_each_bar_can_fail():
    ours = _walk3d()
    same = compare_generalized_forces(ours, dict(ours), W)
    assert same.passes() and same.n_samples == 101
    assert all(r.r == pytest.approx(1.0) and r.rmse == 0.0 for r in same.moments)
    # RMSE of 3 % of peak with r = 1: fails the RMSE bar only
    scaled = dict(ours, hip_flexion_r_moment=1.03 * ours["hip_flexion_r_moment"])
    row = compare_generalized_forces(ours, scaled, W).moments[0]
    assert row.r == pytest.approx(1.0) and not row.passes()
    # a lag: r below 0.99
    lagged = dict(ours, knee_angle_l_moment=np.roll(ours["knee_angle_l_moment"], 3))
    assert not compare_generalized_forces(ours, lagged, W).passes()
    # one sample of 3 % body weight residual fails, 1 % passes
    spike = np.zeros_like(T)
    spike[40] = 0.03 * W
    assert not compare_generalized_forces(ours, dict(ours, pelvis_ty_force=spike), W).passes()
    assert compare_generalized_forces(ours, dict(ours, pelvis_ty_force=spike / 3), W).passes()


def test_the_smooth_mask_drops_touch_downs_and_ends():
    fy = np.zeros((101, 2))
    fy[40:90, 0] = 500.0
    fy[:45, 1] = fy[85:, 1] = 500.0
    keep = smooth_mask(fy, halfwidth=2)
    assert not keep[:2].any() and not keep[-2:].any()
    assert not keep[37:43].any() and keep[36] and keep[43]  # touch-down between 39 and 40
    assert not keep[82:88].any() and keep[81] and keep[88]
    mask = np.zeros(101, bool)
    mask[50] = True
    spike = np.zeros(101)
    spike[39] = 1.0
    assert compare_generalized_forces(
        {"a_moment": T, "pelvis_tx_force": spike, "pelvis_ty_force": spike,
         "pelvis_tz_force": spike},
        {"a_moment": T, "pelvis_tx_force": 0 * T, "pelvis_ty_force": 0 * T,
         "pelvis_tz_force": 0 * T},
        W, keep, coordinates=("a",),
    ).passes()  # fmt: skip


def test_drift_is_measured_within_each_foot_flat_period():
    pitch = np.radians(np.concatenate([[20.0, 10.0, 4.0, 2.0], np.full(20, -1.0), [-30.0]]))
    loaded = np.ones(pitch.size, bool)
    loaded[10] = False  # two foot-flat periods: samples 3-9 and 11-23
    flat = foot_flat_mask(pitch, loaded, np.radians(3.0))
    assert flat.sum() == 20
    points = np.zeros((pitch.size, 3))
    points[:, 0] = np.arange(pitch.size) * 1e-4  # slides 0.1 mm a sample
    assert largest_drift(points, flat) == pytest.approx(12e-4)
    assert np.isnan(largest_drift(points, np.zeros(len(points), bool)))  # nothing checked
    points[15, 2] = 0.006  # one sample 6 mm aside
    assert largest_drift(points, flat) >= BARS.drift_max_m


def test_ranges_contain_the_predicted_motion_and_would_not_without_the_margin(monkeypatch):
    from verify_support import atlas_prediction

    from walk3d.results.osim_model import motion_extent, osim_model

    pred, body = atlas_prediction()
    extent = motion_extent(pred)

    def outside(model):
        return [
            c.name
            for c in model.coordinates
            if not c.range[0] <= extent[c.name][0] <= extent[c.name][1] <= c.range[1]
        ]

    assert outside(osim_model(body)) == []
    monkeypatch.setattr(osim_model_module, "RANGE_MARGIN_DEG", 0.0)
    assert "ankle_angle_r" in outside(osim_model(body))  # exceeds 20 deg between nodes
    assert outside(osim_model(body, extent)) == []
