"""Does a predicted cycle look like walking? Three checks, as numbers.

The two checks of issue #3:

* the knee flexes at least 40° in swing (real gait: about 60°);
* the vertical force under a foot has two humps over its stance (loading response and push-off)
  separated by a mid-stance dip: each maximum at least 0.1 body weight above the dip, less
  below 1.15 m/s (:func:`hump_min_bw`), where people's force flattens between its humps.

and a third one, because those two pass the crouched local optima that most random starts
reach (C_tor about 6.3–7.4 against 1.9–3.7 for walking, yet knee about 40° in swing and two
force humps; docs/solver.md):

* the hip flexes at most 27° on average over the middle third of stance
  (:mod:`walk3d.contact.crouch`, which the solver's crouch check applies too). A crouch
  keeps the hip flexed through stance; a long stride flexes it at heel strike only, so the
  stance maximum (``hip_stance_max_deg``, reported too) confuses the two at fast speeds. The
  knee does not separate them: walk3d's walking optima flex it about 30° in mid-stance too.

A converged optimum can fail any of them: :func:`walking_checks` reports each, and
``looks_like_walking`` is true only when all three pass (``issue_checks`` holds the issue's
two alone). Angles are read from the right side; the cycle is left/right symmetric.
"""

from __future__ import annotations

import numpy as np

from walk3d.constants import G
from walk3d.contact.crouch import midstance_mean, upright
from walk3d.contact.phases import GaitPhases

KNEE_SWING_MIN_DEG = 40.0
HUMP_MIN_BW = 0.1
"""Least height of each vertical-force hump above the mid-stance dip, body weights, from
1.15 m/s up: every healthy limb measured there cleared it (:data:`SLOW_HUMPS`)."""
SLOW_HUMPS = ((0.40, 0.015), (0.55, 0.02), (0.70, 0.045), (1.00, 0.065), (1.15, HUMP_MIN_BW))
"""``(speed m/s, least hump BW)``, linear in between and constant outside: just below the
smaller hump of every limb measured at that speed (42 limb-trials of 8 young adults walking on
a treadmill at 0.39–1.42 m/s, Fukuchi, Fukuchi & Duarte 2018, PeerJ 6:e4640; the lowest were
0.019 BW at 0.43 m/s, 0.024 at 0.54, 0.052 at 0.68, 0.067 at 0.85, 0.073 at 1.00 and 0.204
at 1.17 m/s; docs/validation.md)."""


def hump_min_bw(speed: float | None) -> float:
    """Least hump above the mid-stance dip for a walk at ``speed`` (m/s), body weights;
    :data:`HUMP_MIN_BW` when the speed is not known."""
    if speed is None:
        return HUMP_MIN_BW
    v, h = zip(*SLOW_HUMPS, strict=True)
    return float(np.interp(speed, v, h))


def walking_checks(
    arrays: dict, period: float, double_support: float, mass: float, speed: float | None = None
) -> dict:
    """Knee flexion in swing, hip flexion in stance and mid-stance, and the vertical-force humps
    (right foot).

    ``arrays`` is a prediction's array dict (``time`` in s, ``dof_names``, ``joint_angle`` in
    rad with time first, ``grf_force`` (N, 2, 3) in N with feet [right, left]); ``period`` and
    ``double_support`` in s, ``mass`` in kg, ``speed`` in m/s (None: the humps' bar of normal
    speeds). Angles in the result are in degrees, forces in body weights.
    """
    ph = GaitPhases(period, double_support)
    t = np.asarray(arrays["time"])
    names = list(arrays["dof_names"])
    angles = np.degrees(np.asarray(arrays["joint_angle"]))
    stance = ph.in_stance(t, "r")
    knee = angles[:, names.index("knee_flexion_r")]
    hip = angles[:, names.index("hip_flexion_r")]
    knee_max = float(knee[~stance].max()) if (~stance).any() else float("nan")
    hip_max = float(hip[stance].max()) if stance.any() else float("nan")
    hip_mid = midstance_mean(hip, np.mod(t - ph.heel_strike_r, period), ph)
    fy = np.asarray(arrays["grf_force"])[:, 0, 1] / (mass * G)
    f = fy[stance & (fy > 0.05)]
    humps = (float("nan"),) * 3
    if len(f) >= 4:
        n = len(f)
        i1, i2 = int(np.argmax(f[: n // 2])), n // 2 + int(np.argmax(f[n // 2 :]))
        humps = (float(f[i1]), float(f[i1 : i2 + 1].min()), float(f[i2]))
    bar = hump_min_bw(speed)
    two_humps = bool(humps[0] - humps[1] > bar and humps[2] - humps[1] > bar)
    issue = bool(knee_max >= KNEE_SWING_MIN_DEG and two_humps)
    upright_stance = upright(hip_mid)
    return {
        "knee_swing_max_deg": knee_max,
        "fy_first_dip_second_bw": list(humps),
        "two_fy_humps": two_humps,
        "fy_hump_min_bw": bar,
        "hip_stance_max_deg": hip_max,
        "hip_midstance_deg": hip_mid,
        "upright_stance": upright_stance,
        "issue_checks": issue,
        "looks_like_walking": issue and upright_stance,
    }


ROUGH_MIN_RANGE_DEG = 5.0
"""deg: the smallest range of a joint angle whose roughness counts."""


def roughness(y: np.ndarray) -> float:
    """Share of a periodic signal's variance above its 3rd harmonic (``y`` over one cycle, the
    last sample repeating the first): 0 for a signal made of harmonics 1–3 alone."""
    c = np.fft.rfft(y[:-1] - np.mean(y[:-1]))
    p = np.abs(c) ** 2
    total = float(p[1:].sum())
    return float(p[4:].sum() / total) if total > 1e-18 else 0.0


def realism_figures(arrays: dict, mass: float, step_width_m: float) -> dict:
    """Figures of human-likeness that need no measured reference (issue #23): peak vertical
    ground reaction under one foot and under both, in body weights; pelvis tilt, list and
    rotation ranges, deg; step width, m; and the largest share of a joint angle's variance
    above the 3rd harmonic (:func:`roughness`) with its DoF, over the DoFs that move at least
    :data:`ROUGH_MIN_RANGE_DEG` (as ``shared/tools/realism.py``: a wiggle of a few degrees is
    not a rough motion)."""
    from walk3d.results.angles import pelvis_angles

    force = np.asarray(arrays["grf_force"])[:, :, 1] / (mass * G)
    pelvis = np.degrees(pelvis_angles(np.asarray(arrays["segment_orientation"])[:, 0, :]))
    angles = np.asarray(arrays["joint_angle"])
    moving = np.degrees(np.ptp(angles, axis=0)) >= ROUGH_MIN_RANGE_DEG
    rough = {str(n): roughness(angles[:, i]) for i, n in enumerate(arrays["dof_names"])
             if moving[i]} or {"none": 0.0}  # fmt: skip
    worst = max(rough, key=rough.get)
    return {
        "peak_vertical_grf_bw": float(np.nanmax(force)),
        "peak_total_vertical_grf_bw": float(np.nanmax(np.nansum(force, axis=1))),
        "pelvis_tilt_range_deg": float(np.ptp(pelvis[:, 0])),
        "pelvis_list_range_deg": float(np.ptp(pelvis[:, 1])),
        "pelvis_rotation_range_deg": float(np.ptp(pelvis[:, 2])),
        "step_width_m": float(step_width_m),
        "roughness_worst": rough[worst],
        "roughness_worst_dof": worst,
    }
