"""Gait events from vertical force and cycle normalisation."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from walk3d.io import extract_foot_loads, read_storage
from walk3d.trials.events import detect_contacts, mean_sd, normalize_cycles, percent_axis


def _synthetic_force(rate: float = 1000.0, noise: float = 8.0):
    """Three stances of 0.6 s every 1.0 s, half-sine 800 N, with noise and a 60 N spike."""
    t = np.arange(0.0, 3.5, 1.0 / rate)
    f = np.zeros_like(t)
    for start in (0.3, 1.3, 2.3):
        inside = (t >= start) & (t <= start + 0.6)
        f[inside] = 800.0 * np.sin(np.pi * (t[inside] - start) / 0.6)
    rng = np.random.default_rng(0)
    f += rng.normal(0.0, noise, t.size)
    f[(t > 1.0) & (t < 1.01)] = 60.0  # a 10 ms spike in swing
    return t, f


def test_events_with_noise_and_spike() -> None:
    t, f = _synthetic_force()
    ev = detect_contacts(t, f)
    assert len(ev.heel_strikes) == 3 and len(ev.toe_offs) == 3
    np.testing.assert_allclose(ev.heel_strikes, [0.3, 1.3, 2.3], atol=0.01)
    np.testing.assert_allclose(ev.toe_offs, [0.9, 1.9, 2.9], atol=0.01)
    np.testing.assert_allclose(ev.stride_times, 1.0, atol=0.01)


def test_changed_threshold_moves_events() -> None:
    t, f = _synthetic_force(noise=0.0)
    low, high = detect_contacts(t, f, 20.0), detect_contacts(t, f, 400.0, hysteresis=0.0)
    # 800 sin(pi x / 0.6) = 400 at x = 0.1 s after the start and 0.1 s before the end
    np.testing.assert_allclose(high.heel_strikes, [0.4, 1.4, 2.4], atol=1e-3)
    np.testing.assert_allclose(high.toe_offs, [0.8, 1.8, 2.8], atol=1e-3)
    assert np.all(low.heel_strikes < high.heel_strikes)
    # without a minimum duration the swing spike becomes a contact
    spiky = detect_contacts(t, f, 20.0, min_contact=0.0)
    assert len(spiky.heel_strikes) == 4 and spiky.heel_strikes[1] == pytest.approx(1.0, abs=2e-3)


def test_hysteresis_stops_chatter() -> None:
    t = np.arange(0.0, 1.0, 0.001)
    f = np.where((t > 0.2) & (t < 0.8), 300.0, 0.0)
    chatter = (t > 0.75) & (t < 0.8)
    f[chatter] = 20.0 + 3.0 * np.sign(np.sin(2 * np.pi * 200 * t[chatter]))  # 17..23 N
    ev = detect_contacts(t, f, 20.0, hysteresis=5.0, min_gap=0.0)
    assert len(ev.heel_strikes) == 1 and len(ev.toe_offs) == 1
    no_hyst = detect_contacts(t, f, 20.0, hysteresis=0.0, min_gap=0.0, min_contact=0.0)
    assert len(no_hyst.toe_offs) > 5


def test_contacts_at_record_edges_have_no_event() -> None:
    t = np.linspace(0.0, 1.0, 101)
    f = np.where(t < 0.295, 500.0, 0.0) + np.where(t > 0.705, 500.0, 0.0)
    ev = detect_contacts(t, f)
    # interpolated crossings of 20 N (on) and 15 N (off) between 0/500 N samples 10 ms apart
    assert ev.heel_strikes.tolist() == pytest.approx([0.70 + 0.01 * 20 / 500])
    assert ev.toe_offs.tolist() == pytest.approx([0.29 + 0.01 * 485 / 500])


def test_normalize_cycles_and_mean_sd() -> None:
    t = np.linspace(0.0, 3.0, 3001)
    hs = np.array([0.2, 1.2, 2.2, 3.5])  # the last cycle is incomplete
    phase = np.interp(t, [0.2, 1.2, 2.2], [0.0, 1.0, 2.0])
    signal = np.column_stack([np.sin(2 * np.pi * phase), 2.0 * np.cos(2 * np.pi * phase)])
    cycles = normalize_cycles(t, signal, hs, n=51)
    assert cycles.shape == (51, 2, 2)
    expected = np.sin(2 * np.pi * percent_axis(51) / 100.0)
    np.testing.assert_allclose(cycles[:, 0, 0], expected, atol=1e-5)
    shifted = cycles + np.array([1.0, -1.0])[None, :, None]
    mean, sd = mean_sd(shifted, cycles)  # pooled over two "trials"
    np.testing.assert_allclose(mean, cycles[:, 0], atol=1e-5)
    np.testing.assert_allclose(sd, np.sqrt(2.0 / 3.0), atol=1e-5)
    one_mean, one_sd = mean_sd(cycles[:, :1])
    assert np.isnan(one_sd).all() and np.isfinite(one_mean).all()


def test_subject01_cycle_and_knee_swing(subject01: Path) -> None:
    loads = extract_foot_loads(subject01 / "subject01_walk1_grf.mot")
    ev = detect_contacts(loads.time, loads.left.force[:, 1])
    fy = normalize_cycles(loads.time, loads.left.force[:, 1], ev.heel_strikes, n=101)
    assert fy.shape == (101, 1)
    stance_pct = 100 * (ev.toe_offs[1] - ev.heel_strikes[0]) / np.diff(ev.heel_strikes)[0]
    assert 55.0 < stance_pct < 70.0
    loaded = percent_axis(101)[fy[:, 0] > 20.0]
    assert loaded.max() == pytest.approx(stance_pct, abs=1.5)
    # the IK (0.4-1.6 s) spans the whole left swing: flexed beyond 40 deg, negative in OpenSim
    ik = read_storage(subject01 / "subject01_walk1_ik.mot")
    swing = (ik.time > ev.toe_offs[0]) & (ik.time < ev.heel_strikes[0])
    knee = ik.column("knee_angle_l")
    assert swing.sum() > 20 and knee[swing].min() < -50.0
    assert knee[np.argmin(np.abs(ik.time - ev.heel_strikes[0]))] > -15.0
