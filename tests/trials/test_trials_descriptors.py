"""Gait descriptors V, T and Td from trial files."""

import numpy as np
import pytest

from walk3d.io import Storage
from walk3d.trials.descriptors import descriptors_from_trial, half_cycle_lag


def _symmetric_ik(period: float, t: np.ndarray) -> Storage:
    cols, data = [], []
    for name, phase in (("hip_flexion", 0.1), ("knee_angle", 0.3), ("ankle_angle", 0.7)):
        right = np.sin(2 * np.pi * (t / period + phase)) + 0.3 * np.sin(4 * np.pi * t / period)
        left = np.sin(2 * np.pi * ((t - period / 2) / period + phase)) + 0.3 * np.sin(
            4 * np.pi * (t - period / 2) / period
        )
        cols += [f"{name}_r", f"{name}_l"]
        data += [right, left]
    return Storage("synthetic", t, tuple(cols), np.column_stack(data), in_degrees=True)


def test_half_cycle_lag_of_a_symmetric_gait_is_half_the_period():
    ik = _symmetric_ik(1.1, np.arange(0.0, 2.0, 0.01))
    assert half_cycle_lag(ik, guess=0.5) == pytest.approx(1.1 / 2, abs=2e-3)


@pytest.mark.parametrize("scale", [1e-9, 1e-6, 1.0])
def test_an_ik_time_in_the_wrong_unit_is_too_short_not_a_memory_error(scale):
    """An IK whose time is scaled by 1e-9 (its GRF's in seconds) made the lag search allocate
    447 GiB (MemoryError: a traceback in calibrate, validate and predict --from-trial), by 1e-6
    0.5 GB: every lag was made before those longer than the trial were left out. Found while
    probing the fuzz set's time scaling. Control: the time in seconds."""
    ik = _symmetric_ik(1.1 * scale, np.arange(0.0, 2.0, 0.01) * scale)
    if scale == 1.0:
        assert half_cycle_lag(ik, guess=0.5) == pytest.approx(0.55, abs=2e-3)
        return
    with pytest.raises(ValueError, match="too short to find the half-cycle lag"):
        half_cycle_lag(ik, guess=0.5)


def test_falisse_trial_descriptors(falisse):
    d = descriptors_from_trial(falisse / "gait_1_ik.mot", falisse / "gait_1_grf.mot")
    assert 1.26 < d.speed < 1.33  # info.json: 1.2705 m/s for gait_1 (11-trial mean ~1.32)
    assert 1.03 < d.period < 1.10  # ~1.05 s from stride / speed; one plate step gives 1.11
    assert d.period_method == "kinematic half-cycle lag"
    assert 0.61 < d.stance_fraction < 0.68  # stance ~65 % of the cycle
    assert 0.12 < d.double_support < 0.17
    assert d.stance_fraction == pytest.approx(0.5 + d.double_support / d.period, abs=0.02)
    # events: left strikes its plate first, then the right one
    assert d.events["left"].heel_strikes[0] < d.events["right"].heel_strikes[0]


def test_treadmill_needs_the_belt_speed(subject01):
    ik, grf = subject01 / "subject01_walk1_ik.mot", subject01 / "subject01_walk1_grf.mot"
    with pytest.raises(ValueError, match="treadmill"):
        descriptors_from_trial(ik, grf)
    d = descriptors_from_trial(ik, grf, speed=1.12)
    assert d.speed == 1.12 and d.period_method == "strides"
    assert d.period == pytest.approx(1.235, rel=0.03)  # README: cycle about 1.235 s
    assert d.double_support == pytest.approx(0.17, abs=0.02)


def test_grf_file_without_plates_is_refused(falisse):
    with pytest.raises(ValueError, match="no ground reaction columns"):
        descriptors_from_trial(falisse / "gait_1_ik.mot", falisse / "gait_1_ik.mot")


def test_an_ik_with_a_burst_of_samples_keeps_the_lag_search_small():
    """1001 samples inside 1 µs, then 10 ms steps: the median step (1 ns) asked for 6.6e8 lags
    (4.9 GiB); the lags are now at most 4 per sample over the searched span, and the lag is
    found. Control: the same IK without the burst gives the same lag."""
    t = np.concatenate([np.linspace(0.0, 1e-6, 1001), 1e-6 + np.arange(0.01, 2.0, 0.01)])
    burst = half_cycle_lag(_symmetric_ik(1.1, t), guess=0.5)
    plain = half_cycle_lag(_symmetric_ik(1.1, np.arange(0.0, 2.0, 0.01)), guess=0.5)
    assert burst == pytest.approx(plain, abs=5e-3) and burst == pytest.approx(0.55, abs=5e-3)
