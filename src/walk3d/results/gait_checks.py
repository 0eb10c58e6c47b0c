"""Does a predicted cycle look like walking? The two checks of issue #3, as numbers.

* the knee flexes at least 40° in swing (real gait: about 60°);
* the vertical force under a foot has two humps over its stance (loading response and push-off)
  separated by a mid-stance dip: each maximum at least 0.1 body weight above the dip.

A converged optimum can fail both (a crouched or shuffling local optimum): campaigns and the
benchmark report these alongside convergence.
"""

from __future__ import annotations

import numpy as np

from walk3d import G
from walk3d.contact.phases import GaitPhases

KNEE_SWING_MIN_DEG = 40.0
HUMP_MIN_BW = 0.1


def walking_checks(arrays: dict, period: float, double_support: float, mass: float) -> dict:
    """Knee flexion in swing and the vertical-force humps of the right foot.

    ``arrays`` is a prediction's array dict (``time`` in s, ``dof_names``, ``joint_angle`` in
    rad with time first, ``grf_force`` (N, 2, 3) in N with feet [right, left]).
    """
    ph = GaitPhases(period, double_support)
    t = np.asarray(arrays["time"])
    names = list(arrays["dof_names"])
    knee = np.degrees(np.asarray(arrays["joint_angle"])[:, names.index("knee_flexion_r")])
    swing = ~ph.in_stance(t, "r")
    knee_max = float(knee[swing].max()) if swing.any() else float("nan")
    fy = np.asarray(arrays["grf_force"])[:, 0, 1] / (mass * G)
    f = fy[ph.in_stance(t, "r") & (fy > 0.05)]
    humps = (float("nan"),) * 3
    if len(f) >= 4:
        n = len(f)
        i1, i2 = int(np.argmax(f[: n // 2])), n // 2 + int(np.argmax(f[n // 2 :]))
        humps = (float(f[i1]), float(f[i1 : i2 + 1].min()), float(f[i2]))
    two_humps = bool(humps[0] - humps[1] > HUMP_MIN_BW and humps[2] - humps[1] > HUMP_MIN_BW)
    return {
        "knee_swing_max_deg": knee_max,
        "fy_first_dip_second_bw": list(humps),
        "two_fy_humps": two_humps,
        "looks_like_walking": bool(knee_max >= KNEE_SWING_MIN_DEG and two_humps),
    }
