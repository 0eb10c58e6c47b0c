"""The animation's per-frame geometry: feet on the ground in stance, rigid segments, ground
reaction arrows from the centre of pressure; each check also fails on spoilt geometry."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from walk3d import G
from walk3d.plots.animation import animation_frames

_TIME_FIELDS = ("segment_com_position", "segment_orientation", "joint_angle", "joint_moment",
                "grf_force", "grf_cop", "grf_free_moment", "pelvis_position")  # fmt: skip


@pytest.fixture(scope="module")
def frames(atlas_result):
    pred, body, _ = atlas_result
    return animation_frames(pred, body, cycles=2, fps=30)


def _stance_gap(f, loaded_bw: float = 0.1) -> float:
    """Largest |lowest foot point height| over frames whose foot carries > loaded_bw BW."""
    worst = 0.0
    weight = None
    for k, side in enumerate("rl"):
        low = f.points[:, f.foot_points[side], 1].min(axis=1)
        load = (f.grf_tip[:, k, 1] - f.cop[:, k, 1]) / f.grf_scale  # in body weights
        weight = np.nan_to_num(load) > loaded_bw
        assert weight.sum() > 10
        worst = max(worst, float(np.abs(low[weight]).max()))
    return worst


def _stick_spread(f) -> float:
    d = np.linalg.norm(f.points[:, f.lines[:, 0]] - f.points[:, f.lines[:, 1]], axis=-1)
    return float(np.ptp(d, axis=0).max())


def test_frame_count_and_stride(frames, atlas_result):
    pred = atlas_result[0]
    d = pred.summary.get("descriptors") or {}
    period = float(pred.time[-1] - pred.time[0])
    assert frames.n_frames == round(2 * period * 30)
    assert frames.points.shape == (frames.n_frames, frames.point_segment.size, 3)
    # two cycles: the pelvis moves two strides forward (less one frame)
    moved = frames.pelvis[-1, 0] - frames.pelvis[0, 0]
    assert moved == pytest.approx(2 * frames.stride[0] - frames.stride[0] / (period * 30), abs=0.05)
    assert frames.stride[0] == pytest.approx(d.get("stride_length", frames.stride[0]))


def test_stance_foot_lowest_point_on_the_ground(frames):
    assert _stance_gap(frames) < 0.003  # m
    lifted = replace(frames, points=frames.points + np.array([0.0, 0.01, 0.0]))
    assert _stance_gap(lifted) > 0.005  # negative control: a foot 1 cm up is seen


def test_segments_rigid(frames):
    assert _stick_spread(frames) < 1e-9
    spoilt = frames.points.copy()
    spoilt[7, frames.lines[5, 1]] += 0.01
    assert _stick_spread(replace(frames, points=spoilt)) > 0.005  # negative control


def _arrow_error(f, pred) -> float:
    """Largest distance between a drawn arrow's start and the prediction's centre of pressure
    interpolated independently (np.interp) at the frame's time, over the first cycle."""
    t = pred.time - pred.time[0]
    err = 0.0
    for i in np.flatnonzero(f.time < f.period):
        for k in range(2):
            if not f.loaded[i, k]:
                assert np.isnan(f.grf_tip[i, k]).all()
                continue
            cop = np.array([np.interp(f.time[i], t, pred.grf_cop[:, k, a]) for a in range(3)])
            err = max(err, float(np.linalg.norm(f.cop[i, k] - cop)))
            err = max(err, abs(float(f.cop[i, k, 1])))  # on the ground
    return err


def test_grf_arrow_starts_at_the_cop(frames, atlas_result):
    pred = atlas_result[0]
    assert frames.loaded.any(axis=0).all()
    assert _arrow_error(frames, pred) < 1e-9
    moved = replace(frames, cop=frames.cop + np.array([0.02, 0.0, 0.0]))  # negative control
    assert _arrow_error(moved, pred) > 0.01


def test_arrow_length_is_force_per_body_weight(frames, atlas_result):
    pred = atlas_result[0]
    weight = pred.body_mass * G
    k = 0
    i = int(np.nanargmax(np.where(frames.loaded[:, k], frames.grf_tip[:, k, 1], np.nan)))
    # the sample nearest in time: its force / weight is the arrow, within interpolation
    t = frames.time[i] % frames.period
    j = int(np.argmin(np.abs(pred.time - pred.time[0] - t)))
    assert frames.grf_tip[i, k, 1] - frames.cop[i, k, 1] == pytest.approx(
        pred.grf_force[j, k, 1] / weight, rel=0.1
    )


def test_bad_arguments(atlas_result):
    pred, body, _ = atlas_result
    with pytest.raises(ValueError):
        animation_frames(pred, body, cycles=0)
    with pytest.raises(ValueError):
        animation_frames(pred, body, fps=0.0)


def _with_period(pred, period):
    return replace(pred, summary={**pred.summary, "descriptors": {"period": period}})


@pytest.mark.parametrize("period", [1e7, 1e4, [1], 1e-6, float("nan"), True, "1.0"])
def test_a_summary_period_not_the_time_span_is_refused(atlas_result, period):
    """A damaged ``descriptors.period`` once sized the frame arrays (23 GB at 1e7, a hang at
    1e4, a TypeError at [1], a silently wrong video at 1e-6); now one ValueError line."""
    pred, body, _ = atlas_result
    with pytest.raises(ValueError, match="descriptors.period .* is not the cycle's period"):
        animation_frames(_with_period(pred, period), body, cycles=1, fps=5)


def test_the_period_is_the_time_span(atlas_result):
    pred, body, _ = atlas_result
    span = float(pred.time[-1] - pred.time[0])
    # negative control of the refusals above: the span itself (written by walk3d), and an open
    # cycle whose last sample is one step before T, are animated
    assert animation_frames(_with_period(pred, span), body, cycles=1, fps=5).period == span
    open_cycle = replace(_with_period(pred, span), time=pred.time[:-1],
                         **{name: getattr(pred, name)[:-1] for name in _TIME_FIELDS})  # fmt: skip
    assert animation_frames(open_cycle, body, cycles=1, fps=5).period == span


def test_a_time_axis_of_no_gait_cycle_is_refused(atlas_result):
    pred, body, _ = atlas_result
    with pytest.raises(ValueError, match="not a gait cycle"):
        animation_frames(replace(pred, time=pred.time * 1000.0), body, cycles=1, fps=5)
