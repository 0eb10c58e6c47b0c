"""The measured gait through walk3d's own model: Fourier fit of measured angles and Table 3.

:func:`fit_measured_gait` builds the decision vector ``x`` (:mod:`walk3d.problem.layout`) whose
Fourier quaternion series best match measured joint angles, so that
:func:`walk3d.results.evaluate.evaluate_cycle` runs walk3d's inverse dynamics on the measured
motion: that gives the criteria of the measured gait (the "Measurement" columns of Table 3).

Choices:

* Time: walk3d's cycle starts at right toe off, so a measured right heel strike at ``t_hs`` maps
  to walk3d time ``τ = t - t_hs + T/2 - Td``.
* Left and right: each series is the right side's; a left-side sample at ``τ`` is a sample of
  the right series at ``τ + T/2`` (layout's symmetry). With both legs measured (a trial), both
  feed the same least-squares fit; a right-leg cycle table feeds the right side only.
* Midline joints keep the layout's parity (waist frontal/transverse: odd harmonics, sagittal and
  neck: even): the other coefficients stay zero.
* DoFs not measured (the neck in OpenSim's gait models) are held at zero and listed.
* Stance foot (series 14): the foot's global pitch from the measured pelvis orientation and leg
  angles (:func:`walk3d.trials.kinematics.foot_pitch`), minus its value at foot flat (the
  slowest rotation in single stance), because walk3d's roll-over is anchored at foot flat and
  OpenSim's and walk3d's foot frames differ by a few degrees there.
* Half step width: half the mean lateral distance of the ankles over double support, from the
  chain itself (it does not change moments or criteria, only the contact residual).
* Stance legs are first projected onto walk3d's pure-pitch stance foot
  (:mod:`walk3d.validation.projection`), otherwise the foot's roll tilts the whole body.
* Smoothing: a small roughness penalty (``1e-3 · n · Σ k⁴ (a_k² + b_k²)``) keeps the fit
  within about a degree of the measured angles but removes most of the 4–5 Hz content whose
  amplification by the long stance-leg lever (acceleration ∝ k²) otherwise dominates the
  frontal-plane moments (C_tor's x part drops from 11.8 to 4.7 on the Falisse mean cycle).
* Fit quality: RMSE (deg) between the measured angles and those of the fitted series at the
  measured samples, per DoF.

Known limitation, measured and reported rather than hidden: walk3d's chain starts at the stance
foot and switches root at each heel strike. Measured motion does not satisfy walk3d's closed
double-support loop and roll-over exactly, so the pelvis velocity computed from the new root
differs from the one the old root gave, and the total ground reaction right after heel strike,
which the transition function hands to the trailing foot, is far off (on the Falisse mean cycle:
fore-aft GRF RMSE ≈ 5 N/kg, almost all of it in double support). The criteria from walk3d's
inverse dynamics on measured motion are therefore inflated;
:func:`walk3d.validation.criteria.criteria_from_reference` computes them from measured
inverse-dynamics moments as a cross-check.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from walk3d.body.model import BodyModel
from walk3d.constants import __version__
from walk3d.contact.phases import GaitPhases
from walk3d.kinematics import fourier
from walk3d.kinematics import quaternion as qt
from walk3d.problem import layout
from walk3d.problem.settings import PredictionSettings
from walk3d.results.angles import ball_joint_angles
from walk3d.results.evaluate import CycleEvaluation, evaluate_cycle, make_prediction
from walk3d.results.prediction import PredictedCycle
from walk3d.trials.kinematics import MeasuredKinematics, foot_pitch, joint_coordinates
from walk3d.validation.projection import LEG_DOFS, project_stance

__all__ = ["SMOOTHING", "GaitFit", "fit_measured_gait", "measured_prediction"]


@dataclass(frozen=True)
class GaitFit:
    """Result of :func:`fit_measured_gait`."""

    x: np.ndarray
    settings: PredictionSettings
    rmse_deg: dict[str, float]
    """RMSE (deg) of the fitted series against the measured angles, per DoF (walk3d names, both
    sides) and ``foot_r``/``foot_l`` (against the foot-flat-corrected measured pitch)."""
    fit_rmse_deg: dict[str, float]
    """RMSE (deg) against the fitted (projected) angles: the Fourier series' own error."""
    projection_change_deg: dict[str, float]
    """RMS change of each leg DoF by the stance projection (:mod:`.projection`), deg."""
    projection_residual_deg: float
    not_measured: tuple[str, ...]
    foot_flat_pitch_deg: dict[str, float]
    evaluation: CycleEvaluation
    notes: tuple[str, ...] = field(default_factory=tuple)

    @property
    def criteria(self) -> dict:
        return self.evaluation.criteria


def _flat_pitch(tau: np.ndarray, pitch: np.ndarray, ph: GaitPhases, shift: float) -> float:
    """Pitch at the slowest rotation within single stance (walk3d time, shifted for the left)."""
    p = np.mod(tau + shift, ph.period)
    single = (p >= ph.toe_off_l) & (p <= ph.heel_strike_l)
    rate = np.abs(np.gradient(pitch, tau))
    if not single.any():
        return float(np.median(pitch))
    i = np.flatnonzero(single)[int(np.argmin(rate[single]))]
    return float(pitch[i])


def _observations(body, angles, feet, tau, period):
    """Per coordinate index (0..25): (walk3d times of the right series, values) or None."""
    coords = joint_coordinates(body, angles, tau.size)
    obs: list[tuple[np.ndarray, np.ndarray] | None] = []
    for i, dof in enumerate(body.dof_names):
        _, shifted = layout.COORD_SOURCE[i]
        obs.append(
            None if dof not in coords else (tau + (period / 2 if shifted else 0), coords[dof])
        )
    for side, shift in (("r", 0.0), ("l", period / 2)):
        obs.append(None if side not in feet else (tau + shift, np.sin(feet[side] / 2)))
    return obs


SMOOTHING = 1e-3
"""Default roughness penalty of the fit (see :func:`fit_measured_gait`)."""


def _fit_series(obs, allowed: np.ndarray, period: float, smoothing: float) -> np.ndarray:
    """Least squares with the penalty ``smoothing · n · Σ k⁴ (a_k² + b_k²)`` (n samples), i.e.
    on the mean squared second derivative of the series."""
    t = np.concatenate([o[0] for o in obs])
    v = np.concatenate([o[1] for o in obs])
    b0, _, _ = fourier.basis(t, period)
    k = np.array([0] + [h for h in range(1, fourier.ORDER + 1) for _ in range(2)], float)
    ridge = np.diag(np.sqrt(smoothing * t.size) * k**2)
    a = np.vstack([b0, ridge])[:, allowed]
    rhs = np.concatenate([v, np.zeros(k.size)])
    coef = np.zeros(layout.N_COEF)
    coef[allowed] = np.linalg.lstsq(a, rhs, rcond=None)[0]
    return coef


def _angles_back(body: BodyModel, dof_values: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Inverse of joint_coordinates: anatomical angles (rad) of fitted coordinates."""
    out = {}
    for joint in body.joints:
        names = joint.dof_names
        if joint.kind == "ball":
            if not all(d in dof_values for d in names):
                continue
            v = np.column_stack([dof_values[d] for d in names])
            w = np.sqrt(np.clip(1 - np.sum(v * v, axis=1), 0, None))
            ang = ball_joint_angles(np.column_stack([w, v]), "r")
            out.update({d: ang[:, k] for k, d in enumerate(names)})
        else:
            out.update({d: 2 * np.arcsin(np.clip(dof_values[d], -1, 1))
                        for d in names if d in dof_values})  # fmt: skip
    return out


def _ankle(ev: CycleEvaluation, body: BodyModel, side: str) -> np.ndarray:
    i = body.segment_index(f"foot_{side}")
    a = ev.prediction_arrays
    local = np.broadcast_to(body.segments[i].com, (a["time"].size, 3))
    return a["segment_com_position"][:, i] - qt.rotate(a["segment_orientation"][:, i], local)


def fit_measured_gait(
    kin: MeasuredKinematics,
    body: BodyModel,
    *,
    period: float,
    double_support: float,
    right_heel_strike: float,
    speed: float,
    smoothing: float = SMOOTHING,
) -> GaitFit:
    """Fit walk3d's Fourier series to measured angles and evaluate the cycle (module doc).

    Args:
        kin: Measured angles (both legs from a trial, or the right leg from a cycle table).
        body: The subject's walk3d body (mass, height, sex).
        period, double_support, speed: The measured descriptors T, Td, V.
        right_heel_strike: Time of a right heel strike on ``kin.time``.
        smoothing: Roughness penalty on the coefficients (weight ``k⁴`` on harmonic ``k``).
    """
    settings = PredictionSettings(
        speed=speed, period=period, double_support=double_support, mass=body.mass,
        height=body.height, sex=body.sex,
    )  # fmt: skip
    ph = GaitPhases(period, double_support)
    tau = kin.time - right_heel_strike + ph.heel_strike_r
    pitch, flat = {}, {}
    for side, shift in (("r", 0.0), ("l", period / 2)):
        needed = [f"{d}_{side}" for d in LEG_DOFS]
        if kin.pelvis_angles is not None and all(d in kin.angles for d in needed):
            pitch[side] = foot_pitch(body, kin, side)
            flat[side] = _flat_pitch(tau, pitch[side], ph, shift)
    stance = {side: ph.in_stance(tau, side) for side in pitch}
    proj = project_stance(body, kin, stance, pitch, flat, tau, period)
    obs = _observations(body, proj.angles, proj.foot_rotation, tau, period)
    x = np.zeros(layout.N_X)
    allowed_all = ~layout.fixed_zero_mask()
    for s in range(layout.N_SERIES):
        feeds = [obs[i] for i, (src, _) in enumerate(layout.COORD_SOURCE) if src == s]
        feeds = [f for f in feeds if f is not None]
        if feeds:
            block = slice(s * layout.N_COEF, (s + 1) * layout.N_COEF)
            x[block] = _fit_series(feeds, allowed_all[block], period, smoothing)
    missing = tuple(d for i, d in enumerate(body.dof_names) if obs[i] is None) + tuple(
        f"foot_{s}" for s, o in zip("rl", obs[24:], strict=True) if o is None
    )
    rmse = _fit_rmse(body, kin.angles, x, obs, period)
    rmse_target = _fit_rmse(body, proj.angles, x, obs, period)
    ev = evaluate_cycle(body, settings, x)
    t = ev.prediction_arrays["time"]
    ds = ph.double_support_mask(t)
    dz = _ankle(ev, body, "r")[:, 2] - _ankle(ev, body, "l")[:, 2]
    x[layout.I_HALF_STEP] = 0.5 * float(np.mean(dz[ds])) if ds.any() else 0.05
    ev = evaluate_cycle(body, settings, x)
    notes = (f"fitted {int(allowed_all[: layout.I_HALF_STEP].sum())} free coefficients to "
             f"{kin.time.size} samples",)  # fmt: skip
    flat_deg = {k: float(np.degrees(v)) for k, v in flat.items()}
    return GaitFit(x, settings, rmse, rmse_target, proj.change_deg, proj.residual_deg, missing,
                   flat_deg, ev, notes)  # fmt: skip


def _fit_rmse(body, angles, x, obs, period) -> dict[str, float]:
    coef = layout.coefficients(x)
    fitted: dict[str, np.ndarray] = {}
    measured: dict[str, np.ndarray] = {}
    names = list(body.dof_names) + ["foot_r", "foot_l"]
    for i, o in enumerate(obs):
        if o is None:
            continue
        s, _ = layout.COORD_SOURCE[i]
        b0, _, _ = fourier.basis(o[0], period)
        fitted[names[i]] = b0 @ coef[s]
        measured[names[i]] = o[1]
    back = _angles_back(body, fitted)
    out = {}
    for name in names:
        if name.startswith("foot_") and name in fitted:
            err = 2 * np.arcsin(fitted[name]) - 2 * np.arcsin(measured[name])
        elif name in back and name in angles:
            err = back[name] - angles[name]
        else:
            continue
        out[name] = float(np.degrees(np.sqrt(np.mean(err**2))))
    return out


def measured_prediction(fit: GaitFit, source: str) -> PredictedCycle:
    """A :class:`PredictedCycle` of the fitted measured gait (no optimization), e.g. to compare
    walk3d's inverse dynamics on measured motion with the measured loads."""
    ev = fit.evaluation
    recorded = fit.settings.model_dump()
    summary = {
        "walk3d_version": __version__,
        "kind": "measured gait fitted with walk3d's Fourier series (no optimization)",
        "source": source,
        "settings": recorded | {"model": recorded["model"] | {"criterion": "measured"}},
        "converged": True,
        "status": "not optimized",
        "objective": ev.criteria,
        "objective_smoothed": ev.criteria_smoothed,
        "fit_rmse_deg": fit.rmse_deg,
        "double_support_contact_residual_m": ev.contact_residual_m,
        "root_switch_continuity_residual_m": ev.continuity_residual_m,
        "stride_length_m": ev.stride_length_m,
        "stride_length_target_m": fit.settings.gait.stride_length,
        "step_width_m": ev.step_width_m,
    }
    return make_prediction(ev.prediction_arrays, summary)
