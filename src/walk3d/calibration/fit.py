"""Calibration from a measured trial: the stance-foot roll-over and the transition ratios.

Roll-over (paper Eq. 1, Fig. 2). For every stance fully inside the trial (force-plate heel
strike to toe off), walk3d's forward kinematics driven by the measured pelvis pose and leg
angles (:func:`walk3d.trials.kinematics.segment_poses`) gives the ankle joint centre and the
foot's pitch ``θ``. ``θ`` is taken relative to foot flat (the slowest rotation in mid-stance)
and the ankle relative to its position there; the height is re-based so that the ankle sits at
walk3d's ankle height at foot flat (the model's floor). Left stances are mirrored. The pooled
samples are binned into knots by :func:`walk3d.body.rollover.fit_rollover`. Outside the
measured range the default arc (:func:`walk3d.body.model.build_body`) continues the curve,
shifted to join it, so an optimizer that tries larger foot rotations meets a sensible shape
instead of a cubic extrapolation. Quality: the spline's RMS distance to the samples, and the
ankle's drift while the foot is flat (``|θ| < 1°``), which measures how far walk3d's segment
lengths are from the subject's (the ankle should not move then).

Transition ratios (paper Eqs. 6–8, Fig. 3). In each double support seen on two plates, the
trailing foot's measured wrench (force, and moment about its ankle from the centre of pressure,
the free torque and the kinematic ankle) is compared with the model: ``F_y = F_y0 e(τ)``,
``M_z = M_z0 e(τ)``, ``e = exp(-(τ/T_ds)³)``, ``T_ds`` half that phase's duration, and the
ratios ``F_x = μ_x F_y``, ``F_z = μ_z F_y``, ``M_x = ϖ_x M_z``, ``M_y = ϖ_y M_z``, fitted by least
squares through the origin (right-foot signs, left phases mirrored). The RMSE of each component
(N/kg, N m/kg) is reported for the fitted ratios and for walk3d's data-free default, which takes
the ratios at heel strike.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from walk3d.body.model import BodyModel
from walk3d.body.rollover import RollOver, fit_rollover
from walk3d.contact.transition import TransitionRatios
from walk3d.io.external_loads import FootLoads
from walk3d.trials.events import FootEvents
from walk3d.trials.kinematics import MeasuredKinematics, ankle_positions, foot_pitch

__all__ = [
    "Calibration",
    "TransitionCheck",
    "apply_calibration",
    "fit_rollover_from_trial",
    "fit_transition",
]

FORMAT_VERSION = 1
_SIDES = {"right": "r", "left": "l"}
COMPONENTS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")


@dataclass(frozen=True)
class Calibration:
    """A calibration file's content (SI units)."""

    rollover_s: tuple[float, ...]
    rollover_ankle: tuple[tuple[float, float, float], ...]
    measured_s_range: tuple[float, float]
    ratios: TransitionRatios
    subject: dict[str, Any] = field(default_factory=dict)
    descriptors: dict[str, Any] = field(default_factory=dict)
    quality: dict[str, Any] = field(default_factory=dict)
    source: dict[str, Any] = field(default_factory=dict)

    def rollover(self) -> RollOver:
        return RollOver.from_samples(np.array(self.rollover_s), np.array(self.rollover_ankle))

    def to_dict(self) -> dict[str, Any]:
        r = self.ratios
        return {
            "walk3d_calibration": FORMAT_VERSION,
            "rollover": {
                "s": list(self.rollover_s),
                "ankle_m": [list(p) for p in self.rollover_ankle],
                "measured_s_range": list(self.measured_s_range),
            },
            "transition": {
                "mu_x": r.mu_x,
                "mu_z": r.mu_z,
                "varpi_x": r.varpi_x,
                "varpi_y": r.varpi_y,
            },  # fmt: skip
            "subject": self.subject,
            "descriptors": self.descriptors,
            "quality": self.quality,
            "source": self.source,
        }

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> Calibration:
        """From :meth:`to_dict`'s layout (as validated by :func:`walk3d.io.read_calibration`)."""
        ro, tr = d["rollover"], d["transition"]
        return cls(
            tuple(float(v) for v in ro["s"]),
            tuple(tuple(float(c) for c in p) for p in ro["ankle_m"]),  # type: ignore[misc]
            tuple(float(v) for v in ro.get("measured_s_range", (ro["s"][0], ro["s"][-1]))),  # type: ignore[arg-type]
            TransitionRatios(*(float(tr[k]) for k in ("mu_x", "mu_z", "varpi_x", "varpi_y"))),
            dict(d.get("subject", {})),
            dict(d.get("descriptors", {})),
            dict(d.get("quality", {})),
            dict(d.get("source", {})),
        )


def apply_calibration(body: BodyModel, calibration: Calibration) -> BodyModel:
    """``body`` with the calibrated roll-over (a new model; ``body`` is unchanged).

    The transition ratios are not part of the body: pass ``calibration.ratios`` where the
    double-support split is computed (:func:`walk3d.contact.transition.apply_ratios`).
    """
    return replace(body, rollover=calibration.rollover())


def _stance_windows(events: dict[str, FootEvents], t0: float, t1: float):
    for side, ev in events.items():
        for hs in ev.heel_strikes:
            later = ev.toe_offs[ev.toe_offs > hs]
            if later.size and hs >= t0 and later[0] <= t1:
                yield side, float(hs), float(later[0])


def _flat_index(t: np.ndarray, theta: np.ndarray) -> int:
    n = theta.size
    mid = slice(int(0.2 * n), max(int(0.6 * n), int(0.2 * n) + 1))
    rate = np.abs(np.gradient(theta, t))
    return mid.start + int(np.argmin(rate[mid]))


def fit_rollover_from_trial(
    body: BodyModel, kin: MeasuredKinematics, events: dict[str, FootEvents], n_knots: int = 9
) -> tuple[RollOver, dict[str, Any], tuple[np.ndarray, np.ndarray]]:
    """Roll-over spline of the trial's stances (module doc).

    Returns:
        ``(rollover, quality, (s_samples, ankle_samples))``; ``quality`` has ``stances``,
        ``rms_m``, ``flat_drift_m``, ``theta_range_deg`` and ``flat_pitch_deg``.
    """
    s_all, a_all, drift, flats = [], [], [], []
    h = body.foot.ankle_height
    for side, hs, to in _stance_windows(events, kin.time[0], kin.time[-1]):
        sel = (kin.time >= hs) & (kin.time <= to)
        if sel.sum() < 8:
            continue
        pitch = foot_pitch(body, kin, side)[sel]
        ankle = ankle_positions(body, kin, side)[sel]
        f = _flat_index(kin.time[sel], pitch)
        theta = pitch - pitch[f]
        rel = ankle - ankle[f]
        rel[:, 1] += h
        if side == "left":
            rel[:, 2] *= -1.0
        flat = np.abs(theta) < np.radians(1.0)
        drift.append(float(np.ptp(ankle[flat, 0])) if flat.sum() > 1 else 0.0)
        flats.append(float(np.degrees(pitch[f])))
        s_all.append(np.sin(theta / 2))
        a_all.append(rel)
    if not s_all:
        raise ValueError("no complete stance (heel strike to toe off) inside the IK trial")
    s, a = np.concatenate(s_all), np.concatenate(a_all)
    theta = 2 * np.arcsin(s)
    sole = np.column_stack([np.zeros_like(theta), -h * np.ones_like(theta), np.zeros_like(theta)])
    c, si = np.cos(theta)[:, None], np.sin(theta)[:, None]

    def marker(dx: float) -> np.ndarray:
        local = sole + np.array([dx, 0.0, 0.0])
        return a + np.column_stack([c[:, 0] * local[:, 0] - si[:, 0] * local[:, 1],
                                    si[:, 0] * local[:, 0] + c[:, 0] * local[:, 1],
                                    local[:, 2]])  # fmt: skip

    measured = fit_rollover(marker(-0.05), a, marker(0.15), n_knots=n_knots, flat_pitch=0.0)
    rollover = _extend(measured, body.rollover)
    fitted = np.column_stack(rollover.evaluate(s)[0])
    quality = {
        "stances": len(s_all),
        "rms_m": float(np.sqrt(np.mean(np.sum((fitted - a) ** 2, axis=1)))),
        "flat_drift_m": float(max(drift)),
        "theta_range_deg": [float(np.degrees(theta.min())), float(np.degrees(theta.max()))],
        "flat_pitch_deg": flats,
    }
    return rollover, quality, (s, a)


def _extend(measured: RollOver, default: RollOver) -> RollOver:
    """Measured knots, continued beyond both ends by the default shape shifted to join."""
    ks = np.array(measured.knots)
    kv = np.column_stack(measured.evaluate(ks)[0])
    ds = np.array(default.knots)
    lo, hi = ds[ds < ks[0] - 0.02], ds[ds > ks[-1] + 0.02]
    parts_s, parts_v = [ks], [kv]
    if lo.size:
        shift = kv[0] - np.column_stack(default.evaluate(np.array([ks[0]]))[0])[0]
        parts_s.insert(0, lo)
        parts_v.insert(0, np.column_stack(default.evaluate(lo)[0]) + shift)
    if hi.size:
        shift = kv[-1] - np.column_stack(default.evaluate(np.array([ks[-1]]))[0])[0]
        parts_s.append(hi)
        parts_v.append(np.column_stack(default.evaluate(hi)[0]) + shift)
    return RollOver.from_samples(np.concatenate(parts_s), np.concatenate(parts_v))


@dataclass(frozen=True)
class TransitionCheck:
    """Fig. 3 data: per double-support phase, normalised time and trailing-foot wrenches."""

    phases: tuple[dict[str, Any], ...]
    """Each: ``side`` (trailing foot), ``t`` (s from heel strike), ``duration``, ``measured``
    and ``model`` ((n, 6) in N/kg and N m/kg, right-foot signs, order :data:`COMPONENTS`)."""
    ratios: TransitionRatios
    rmse: dict[str, float]
    """Per component, fitted ratios."""
    rmse_heel_strike_ratios: dict[str, float]
    """Per component, walk3d's default ratios (taken at heel strike)."""


def _trailing_wrenches(loads, ankle_fn, events, threshold):
    out = []
    for lead, trail in (("right", "left"), ("left", "right")):
        f_trail = loads.foot(trail).force
        for hs in events[lead].heel_strikes:
            offs = events[trail].toe_offs[events[trail].toe_offs > hs]
            if not offs.size or np.interp(hs, loads.time, f_trail[:, 1]) <= threshold:
                continue
            sel = (loads.time >= hs) & (loads.time <= offs[0])
            foot = loads.foot(trail)
            force = foot.force[sel]
            arm = foot.cop[sel] - ankle_fn(trail, loads.time[sel])
            moment = np.cross(arm, force) + foot.torque[sel]
            w = np.hstack([force, moment])
            if trail == "left":
                w = w * np.array([1, 1, -1, -1, -1, 1])
            out.append((trail, float(hs), loads.time[sel] - hs, float(offs[0] - hs), w))
    return out


def fit_transition(
    body: BodyModel,
    kin: MeasuredKinematics,
    loads: FootLoads,
    events: dict[str, FootEvents],
    mass: float,
    threshold: float = 20.0,
) -> TransitionCheck:
    """Fit and check the transition function on the trial's double supports (module doc)."""
    ankles = {side: ankle_positions(body, kin, side) for side in ("right", "left")}

    def ankle_fn(side, t):
        a = ankles[side]
        return np.column_stack([np.interp(t, kin.time, a[:, k]) for k in range(3)])

    raw = [p for p in _trailing_wrenches(loads, ankle_fn, events, threshold)
           if kin.time[0] <= p[1] and p[1] + p[3] <= kin.time[-1]]  # fmt: skip
    if not raw:
        raise ValueError("no double support with both feet on the force plates inside the IK trial")
    w = np.vstack([p[4] for p in raw]) / mass

    def ratio(num: int, den: int) -> float:
        return float(np.sum(w[:, num] * w[:, den]) / np.sum(w[:, den] ** 2))

    ratios = TransitionRatios(ratio(0, 1), ratio(2, 1), ratio(3, 5), ratio(4, 5))
    phases, err_fit, err_hs = [], [], []
    for side, _, t, duration, wr in raw:
        wr = wr / mass
        e = np.exp(-((t / (duration / 2)) ** 3))
        fy, mz = wr[0, 1] * e, wr[0, 5] * e
        model = np.column_stack([ratios.mu_x * fy, fy, ratios.mu_z * fy,
                                 ratios.varpi_x * mz, ratios.varpi_y * mz, mz])  # fmt: skip
        hs = np.column_stack([wr[0, 0] / wr[0, 1] * fy, fy, wr[0, 2] / wr[0, 1] * fy,
                              wr[0, 3] / wr[0, 5] * mz, wr[0, 4] / wr[0, 5] * mz, mz])  # fmt: skip
        phases.append({"side": side, "t": t, "duration": duration, "measured": wr, "model": model})
        err_fit.append(model - wr)
        err_hs.append(hs - wr)
    ef, eh = np.vstack(err_fit), np.vstack(err_hs)
    rmse = {c: float(np.sqrt(np.mean(ef[:, k] ** 2))) for k, c in enumerate(COMPONENTS)}
    rmse_hs = {c: float(np.sqrt(np.mean(eh[:, k] ** 2))) for k, c in enumerate(COMPONENTS)}
    return TransitionCheck(tuple(phases), ratios, rmse, rmse_hs)
