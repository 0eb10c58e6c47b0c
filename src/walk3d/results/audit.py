"""The cost audit: what walk3d's criterion charges one gait against another, phase by phase,
with the mechanics that explain it (docs/tracking.md).

* :func:`term_table`: each criterion term's integral over the gait phases of the right leg's
  cycle (loading, mid-stance, push-off, swing) and in total, raw and weighted as the criterion
  weighs it, with ``effort`` and ``effort3`` also reported;
* :func:`limb_work`: the centre-of-mass work of each leg in double support (the
  individual-limbs method, Donelan, Kram & Kuo 2002, J Exp Biol 205:3717): the trailing leg's
  positive work and the leading leg's negative work, per step, J/kg;
* :func:`power_bursts`: the sagittal joint-power bursts of the right leg, J/kg (Winter's A1/A2,
  K1–K3, H1–H3).

All of it reads an evaluated cycle (:class:`walk3d.results.evaluate.CycleEvaluation`).
"""

from __future__ import annotations

from os import PathLike
from pathlib import Path

import numpy as np

from walk3d.model import terms

__all__ = ["AUDIT_KEYS", "BURSTS", "PHASES", "is_audit_file", "is_tracking", "limb_work",
           "phase_masks", "power_bursts", "term_table"]  # fmt: skip

AUDIT_KEYS = ("criterion", "terms", "limb_work", "bursts")
"""Keys every audit file holds (:func:`walk3d.tracking.audit`): how walk3d knows an earlier
audit, which ``walk3d audit --out`` replaces, from a user's JSON file, which it keeps."""


def is_audit_file(path: str | PathLike[str]) -> bool:
    """Whether ``path`` is a JSON object with every one of :data:`AUDIT_KEYS`."""
    from walk3d.outputs import json_holds

    return json_holds(path, *AUDIT_KEYS)


def is_tracking(folder: str | PathLike[str]) -> bool:
    """Whether the result folder ``folder`` records a tracking (``walk3d track``: settings with
    a measured gait to follow); False for a prediction or a summary that cannot be read."""
    from walk3d.io.checks import read_json_object
    from walk3d.problem.settings import recorded_settings

    try:
        summary = read_json_object(Path(folder) / "summary.json", "walk3d summary")
    except (OSError, ValueError):
        return False
    return recorded_settings(summary).get("tracking") is not None


PHASES = ("loading", "mid-stance", "push-off", "swing")
"""The right leg's phases: heel strike to the other foot's toe-off (Td), then to 30 % of the
cycle (heel rise, Perry's mid-stance), then to its own toe-off (terminal stance and pre-swing),
then swing."""
BURSTS = {
    "A1": ("ankle_dorsiflexion_r", -1, 0.00, 0.45),
    "A2": ("ankle_dorsiflexion_r", +1, 0.40, 0.70),
    "K1": ("knee_flexion_r", -1, 0.00, 0.15),
    "K2": ("knee_flexion_r", +1, 0.10, 0.40),
    "K3": ("knee_flexion_r", -1, 0.45, 0.70),
    "H1": ("hip_flexion_r", +1, 0.00, 0.30),
    "H2": ("hip_flexion_r", -1, 0.25, 0.55),
    "H3": ("hip_flexion_r", +1, 0.50, 0.80),
}
"""Burst: (DoF, sign of the power counted, window start and end as fractions of the cycle from
right heel strike); windows after Winter (2009), Biomechanics and Motor Control of Human
Movement, Fig. 7.9, widened to hold the burst at other speeds."""


def _phase_of_cycle(time: np.ndarray, period: float, double_support: float) -> np.ndarray:
    """Fraction of the cycle from right heel strike (``t = T/2 − Td`` on walk3d's clock)."""
    return np.mod((time - time[0] - (period / 2 - double_support)) / period, 1.0)


def phase_masks(time: np.ndarray, period: float, double_support: float) -> dict[str, np.ndarray]:
    """Boolean masks of :data:`PHASES` over the periodic samples ``time[:-1]``."""
    f = _phase_of_cycle(time[:-1], period, double_support)
    d = double_support / period
    edges = {"loading": (0.0, d), "mid-stance": (d, 0.30), "push-off": (0.30, 0.5 + d),
             "swing": (0.5 + d, 1.0)}  # fmt: skip
    return {k: (f >= lo) & (f < hi) for k, (lo, hi) in edges.items()}


def term_table(ev: dict, criterion: str, period: float, double_support: float) -> list[dict]:
    """Per term, its integral (s) in each phase and in total for each named evaluation in
    ``ev`` (``{"tracked": CycleEvaluation, "predicted": ...}``), raw and weighted by
    ``criterion``'s weights (0 for a term it does not weigh)."""
    weights = terms.parse(criterion)
    names = [k for k in next(iter(ev.values())).integrands if k != "C_track"]
    rows = []
    for key in names:
        row = {"term": key, "weight": weights.get(key[2:], 0.0)}
        for label, e in ev.items():
            time = e.prediction_arrays["time"]
            dt = (time[-1] - time[0]) / (time.size - 1)
            per = np.sum(e.integrands[key][:-1], axis=1) * dt
            for phase, mask in phase_masks(time, period, double_support).items():
                row[f"{label} {phase}"] = float(np.sum(per[mask]))
            row[f"{label} total"] = float(np.sum(per))
        rows.append(row)
    return rows


def _com(arrays: dict) -> np.ndarray:
    m = np.asarray(arrays["segment_mass"], dtype=float)
    return np.einsum("j,tjk->tk", m, arrays["segment_com_position"]) / m.sum()


def _periodic_rate(values: np.ndarray, time: np.ndarray, jump: np.ndarray) -> np.ndarray:
    """Central differences of samples over one cycle whose end is the start plus ``jump``."""
    v = values[:-1]
    dt = time[1] - time[0]
    nxt = np.roll(v, -1, axis=0)
    nxt[-1] = v[0] + jump
    prv = np.roll(v, 1, axis=0)
    prv[0] = v[-1] - jump
    return (nxt - prv) / (2 * dt)


def limb_work(ev, period: float, double_support: float) -> dict[str, float]:
    """Per step, J/kg: each leg's centre-of-mass work in double support (``trailing positive``,
    ``trailing negative``, ``leading positive``, ``leading negative``) and the whole double
    support's net, from ``F_leg · v_com``."""
    a = ev.prediction_arrays
    time = a["time"]
    com = _com(a)
    v = _periodic_rate(com, time, com[-1] - com[0])
    mass = float(np.sum(a["segment_mass"]))
    f = np.asarray(a["grf_force"])[:-1]  # (n, 2 feet [r, l], 3)
    phase = _phase_of_cycle(time[:-1], period, double_support)
    d = double_support / period
    dt = time[1] - time[0]
    out = {"trailing positive": 0.0, "trailing negative": 0.0, "leading positive": 0.0,
           "leading negative": 0.0}  # fmt: skip
    for start, lead, trail in ((0.0, 0, 1), (0.5, 1, 0)):  # right, then left heel strike
        ds = (phase >= start) & (phase < start + d)
        for role, foot in (("leading", lead), ("trailing", trail)):
            p = np.einsum("tk,tk->t", f[ds, foot], v[ds]) / mass
            out[f"{role} positive"] += float(np.sum(np.maximum(p, 0))) * dt / 2
            out[f"{role} negative"] += float(np.sum(np.minimum(p, 0))) * dt / 2
    out["net"] = sum(out.values())
    return out


def power_bursts(ev, dof_names: tuple[str, ...], joint_names: tuple[str, ...], period: float,
                 double_support: float) -> dict[str, float]:  # fmt: skip
    """:data:`BURSTS` of the right leg, J/kg: the work of the counted sign in each window, from
    the sagittal joint power ``M θ̇`` (moment about the flexion axis, angle rate)."""
    a = ev.prediction_arrays
    time = a["time"]
    mass = float(np.sum(a["segment_mass"]))
    phase = _phase_of_cycle(time[:-1], period, double_support)
    dt = time[1] - time[0]
    out = {}
    for name, (dof, sign, lo, hi) in BURSTS.items():
        i = dof_names.index(dof)
        joint = joint_names.index(dof.split("_")[0] + "_r")
        theta = np.asarray(a["joint_angle"])[:, i]
        rate = _periodic_rate(theta, time, np.zeros(()))
        power = np.asarray(a["joint_moment"])[:-1, joint, 2] * rate / mass
        window = (phase >= lo) & (phase < hi)
        out[name] = float(np.sum(np.where(sign * power > 0, power, 0.0)[window])) * dt
    return out
