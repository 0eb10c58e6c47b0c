"""The walking checks tell a two-humped, knee-flexing cycle from a flat, stiff-legged one."""

import numpy as np
import pytest

from walk3d import G
from walk3d.contact.phases import GaitPhases
from walk3d.results.gait_checks import HUMP_MIN_BW, hump_min_bw, walking_checks

T, TD, MASS = 1.08, 0.16, 70.0


def _arrays(
    knee_peak_deg: float,
    humps: bool,
    hip_stance_peak_deg: float = 30.0,
    hip_floor_deg: float = 0.0,
    depth: float = 0.4,
) -> dict:
    ph = GaitPhases(T, TD)
    t = np.linspace(0.0, T, 101)
    stance = ph.in_stance(t, "r")
    knee = np.where(stance, 0.1, np.radians(knee_peak_deg))
    idx = np.flatnonzero(stance)
    s = np.zeros_like(t)
    s[idx] = np.linspace(0.0, 1.0, len(idx))
    if depth < 0.1:  # slow walking: a plateau with two small bumps
        bumps = np.exp(-(((s - 0.25) / 0.08) ** 2)) + np.exp(-(((s - 0.75) / 0.08) ** 2))
        ramp = np.clip(np.minimum(s, 1.0 - s) / 0.1, 0.0, 1.0)
        fy = np.where(stance, ramp * (0.95 + depth * bumps), 0.0) * MASS * G
    else:
        shape = 1.0 + depth * np.cos(2 * np.pi * s) if humps else np.ones_like(t)
        fy = np.where(stance, np.sin(np.pi * s) ** 0.5 * shape, 0.0) * MASS * G
    grf = np.zeros((101, 2, 3))
    grf[:, 0, 1] = fy
    angles = np.zeros((101, 2))
    angles[:, 1] = knee
    # from its peak at heel strike to extension at toe off, but not below ``hip_floor_deg``
    hip = np.maximum(hip_stance_peak_deg * np.cos(np.pi * s), hip_floor_deg)
    angles[:, 0] = np.where(stance, np.radians(hip), 0.0)
    return {"time": t, "dof_names": ["hip_flexion_r", "knee_flexion_r"], "joint_angle": angles,
            "grf_force": grf}  # fmt: skip


def test_walking_cycle_passes():
    c = walking_checks(_arrays(60.0, True), T, TD, MASS)
    assert c["knee_swing_max_deg"] > 59.0
    assert c["two_fy_humps"] and c["looks_like_walking"]


def test_flat_force_or_stiff_knee_fails():
    assert not walking_checks(_arrays(60.0, False), T, TD, MASS)["two_fy_humps"]
    stiff = walking_checks(_arrays(20.0, True), T, TD, MASS)
    assert stiff["two_fy_humps"] and not stiff["looks_like_walking"]


def test_crouched_hip_fails_only_the_third_check():
    """The crouched optima pass the issue's two checks with the hip flexed through stance."""
    crouched = walking_checks(_arrays(42.0, True, 65.0, hip_floor_deg=40.0), T, TD, MASS)
    assert crouched["issue_checks"] and not crouched["upright_stance"]
    assert not crouched["looks_like_walking"]
    assert abs(crouched["hip_stance_max_deg"] - 65.0) < 1.0
    assert crouched["hip_midstance_deg"] > 39.0
    upright = walking_checks(_arrays(42.0, True, hip_stance_peak_deg=36.0), T, TD, MASS)
    assert upright["upright_stance"] and upright["looks_like_walking"]


def test_a_long_stride_is_not_a_crouch():
    """A hip flexed 50° at heel strike that extends through stance walks; mid-stance is the
    middle third of stance, where this cosine crosses zero (sampled: within 10°)."""
    long = walking_checks(_arrays(60.0, True, hip_stance_peak_deg=50.0), T, TD, MASS)
    assert long["hip_stance_max_deg"] > 49.0 and abs(long["hip_midstance_deg"]) < 10.0
    assert long["upright_stance"] and long["looks_like_walking"]


def test_roughness_is_the_share_above_the_third_harmonic():
    from walk3d.results.gait_checks import roughness

    t = np.linspace(0.0, 1.0, 101)
    smooth = np.sin(2 * np.pi * t) + 0.5 * np.cos(6 * np.pi * t)
    assert roughness(smooth) < 1e-20
    rough = smooth + 0.5 * np.sin(10 * np.pi * t)  # 5th harmonic: 0.125 of 1.25 variance
    assert roughness(rough) == pytest.approx(0.125 / (0.5 + 0.125 + 0.125))


def test_realism_figures_read_peaks_ranges_and_width():
    from walk3d.results.gait_checks import realism_figures

    a = _arrays(60.0, True)
    n = len(a["time"])
    ori = np.zeros((n, 13, 4))
    yaw = np.radians(5.0) * np.sin(2 * np.pi * a["time"] / T)  # ±5° rotation about y
    ori[:, 0, 0], ori[:, 0, 2] = np.cos(yaw / 2), np.sin(yaw / 2)
    ori[:, 1:, 0] = 1.0
    a["segment_orientation"] = ori
    f = realism_figures(a, MASS, 0.1)
    assert f["peak_vertical_grf_bw"] == pytest.approx(a["grf_force"][:, 0, 1].max() / (MASS * G))
    assert f["pelvis_rotation_range_deg"] == pytest.approx(10.0, abs=0.05)
    assert f["pelvis_list_range_deg"] == pytest.approx(0.0, abs=1e-9)
    assert f["step_width_m"] == 0.1


def test_roughness_counts_only_joints_that_move_5_degrees():
    """As the shared yardstick: a rough wiggle of 3° is left out, the same wiggle at 8° counts
    (its negative control)."""
    from walk3d.results.gait_checks import realism_figures

    a = _arrays(60.0, True)
    t = a["time"]
    rough = np.sin(2 * np.pi * t / T) + np.sin(2 * np.pi * 7 * t / T)  # half above harmonic 3
    smooth = np.sin(2 * np.pi * t / T)
    ori = np.zeros((len(t), 13, 4))
    ori[:, :, 0] = 1.0
    a["segment_orientation"] = ori
    for wiggle_deg, counted in ((3.0, False), (8.0, True)):
        a["joint_angle"] = np.column_stack([np.radians(40.0) * smooth,
                                            np.radians(wiggle_deg / 2.5) * rough])  # fmt: skip
        f = realism_figures(a, MASS, 0.1)
        assert (f["roughness_worst_dof"] == "knee_flexion_r") is counted
        assert (f["roughness_worst"] > 0.4) is counted


def test_slow_walking_humps_pass_slowly_but_not_at_normal_speed():
    """A force that dips about 0.04 body weight between its humps, as people's at 0.55 m/s
    (Fukuchi et al. 2018), walks at that speed; the same curve at 1.3 m/s does not (control)."""
    flat = _arrays(60.0, True, depth=0.04)
    humps = walking_checks(flat, T, TD, MASS, speed=0.55)["fy_first_dip_second_bw"]
    assert 0.02 < min(humps[0], humps[2]) - humps[1] < HUMP_MIN_BW
    assert walking_checks(flat, T, TD, MASS, speed=0.55)["two_fy_humps"]
    assert not walking_checks(flat, T, TD, MASS, speed=1.3)["two_fy_humps"]
    assert not walking_checks(flat, T, TD, MASS)["two_fy_humps"]  # no speed: the normal bar


@pytest.mark.parametrize(
    ("speed", "lowest"), [(0.43, 0.019), (0.54, 0.024), (0.68, 0.052), (0.85, 0.067),
                          (1.00, 0.073), (1.17, 0.204)],
)  # fmt: skip
def test_the_hump_bar_is_below_every_measured_limb(speed, lowest):
    """The smallest hump of the limbs measured at each treadmill speed (Fukuchi et al. 2018,
    docs/validation.md) clears the bar, and the bar is never above the normal one."""
    assert 0.0 < hump_min_bw(speed) < lowest
    assert hump_min_bw(speed) <= HUMP_MIN_BW == hump_min_bw(None) == hump_min_bw(2.0)
