"""Left against right on one predicted cycle (``summary.json``'s ``asymmetry``, issue #43): step
length, stance time, peak vertical force, and the peak sagittal hip, knee and ankle angles and
moments. Each entry is ``{"right", "left", "difference"}`` (right − left). The half-cycle
problem makes the sides mirror images, so its differences are zero up to sampling.
"""

from __future__ import annotations

import numpy as np

from walk3d.constants import G

__all__ = ["LOADED_BW", "asymmetry", "asymmetry_or_none"]

LOADED_BW = 0.02
"""Vertical force, in body weights, above which a foot counts as on the ground (15 N at 75 kg,
as force plates' usual 10–20 N threshold). The trailing foot's last few percent of load in
double support fall below it, so a stance is a little shorter than ``T/2 + Td``."""


def _foot_on(fy: np.ndarray, weight: float) -> np.ndarray:
    return fy > LOADED_BW * weight


def _strike(on: np.ndarray) -> int:
    """Index of the cycle's first sample where the foot touches down (cyclic)."""
    rise = np.flatnonzero(on & ~np.roll(on, 1))
    if rise.size == 0:
        raise ValueError(
            "a foot never touches down on the cycle (it never leaves the ground, or never loads)"
        )
    return int(rise[0])


def asymmetry(arrays: dict, mass: float) -> dict[str, dict[str, float]]:
    """Right and left figures of a prediction's array dict (``time`` s, ``dof_names``,
    ``joint_angle`` rad, ``joint_names``, ``joint_moment`` N·m, ``grf_force`` N,
    ``segment_names``, ``segment_com_position`` m; the last sample closes the cycle) for a body
    of ``mass`` kg: step length (m, the foot's centre of mass at its touch-down ahead of the
    other's at the touch-down before; the two add up to the stride), stance time (s), peak
    vertical force (BW), peak flexion of hip and knee and peak dorsiflexion and plantarflexion
    (deg), peak hip and knee extensor and ankle plantarflexor moments (N·m/kg)."""
    t = np.asarray(arrays["time"])[:-1]
    dt = float(arrays["time"][-1] - arrays["time"][0]) / t.size
    fy = np.asarray(arrays["grf_force"])[:-1, :, 1]
    angle = np.degrees(np.asarray(arrays["joint_angle"])[:-1])
    moment = np.asarray(arrays["joint_moment"])[:-1, :, 2] / mass
    dofs, joints = list(arrays["dof_names"]), list(arrays["joint_names"])
    segs = list(arrays["segment_names"])
    com_x_all = np.asarray(arrays["segment_com_position"])[:, :, 0]
    com_x = com_x_all[:-1]
    weight = mass * G
    out: dict[str, dict[str, float]] = {}

    def put(name: str, right: float, left: float) -> None:
        out[name] = {"right": float(right), "left": float(left), "difference": float(right - left)}

    sides = ("r", "l")
    on = [_foot_on(fy[:, k], weight) for k in range(2)]
    feet = [segs.index(f"foot_{s}") for s in sides]
    strikes = [_strike(o) for o in on]
    stride = [float(com_x_all[-1, f] - com_x_all[0, f]) for f in feet]
    x_strike = [com_x[strikes[k], feet[k]] for k in range(2)]

    def step(k: int) -> float:
        """Foot k's lead at its touch-down over the other foot's touch-down before it."""
        back = x_strike[1 - k] - (stride[1 - k] if strikes[1 - k] > strikes[k] else 0.0)
        return float(x_strike[k] - back)

    steps = [step(0), step(1)]
    put("step_length_m", *steps)
    put("stance_time_s", *(dt * float(np.count_nonzero(o)) for o in on))
    put("peak_vertical_grf_bw", *(fy[:, k].max() / weight for k in range(2)))

    def dof(name: str) -> list[np.ndarray]:
        return [angle[:, dofs.index(f"{name}_{s}")] for s in sides]

    def joint(name: str) -> list[np.ndarray]:
        return [moment[:, joints.index(f"{name}_{s}")] for s in sides]

    put("peak_hip_flexion_deg", *(a.max() for a in dof("hip_flexion")))
    put("peak_knee_flexion_deg", *(a.max() for a in dof("knee_flexion")))
    put("peak_ankle_dorsiflexion_deg", *(a.max() for a in dof("ankle_dorsiflexion")))
    put("peak_ankle_plantarflexion_deg", *(-a.min() for a in dof("ankle_dorsiflexion")))
    put("peak_hip_extensor_moment_nm_per_kg", *(-m.min() for m in joint("hip")))
    put("peak_knee_extensor_moment_nm_per_kg", *(-m.min() for m in joint("knee")))
    put("peak_ankle_plantarflexor_moment_nm_per_kg", *(-m.min() for m in joint("ankle")))
    return out


def asymmetry_or_none(arrays: dict, mass: float) -> dict[str, dict[str, float]] | None:
    """:func:`asymmetry`, or None for a cycle without steps (a foot that never touches down,
    as in a standing result)."""
    try:
        return asymmetry(arrays, mass)
    except ValueError:
        return None
