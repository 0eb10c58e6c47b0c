"""The walking checks tell a two-humped, knee-flexing cycle from a flat, stiff-legged one."""

import numpy as np

from walk3d import G
from walk3d.contact.phases import GaitPhases
from walk3d.results.gait_checks import walking_checks

T, TD, MASS = 1.08, 0.16, 70.0


def _arrays(knee_peak_deg: float, humps: bool) -> dict:
    ph = GaitPhases(T, TD)
    t = np.linspace(0.0, T, 101)
    stance = ph.in_stance(t, "r")
    knee = np.where(stance, 0.1, np.radians(knee_peak_deg))
    idx = np.flatnonzero(stance)
    s = np.zeros_like(t)
    s[idx] = np.linspace(0.0, 1.0, len(idx))
    shape = 1.0 + 0.4 * np.cos(2 * np.pi * s) if humps else np.ones_like(t)
    fy = np.where(stance, np.sin(np.pi * s) ** 0.5 * shape, 0.0) * MASS * G
    grf = np.zeros((101, 2, 3))
    grf[:, 0, 1] = fy
    angles = np.zeros((101, 2))
    angles[:, 1] = knee
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
