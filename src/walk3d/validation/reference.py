"""Measured reference cycles (mean ± SD over 0–100 % from right heel strike) in Table 2 units.

Two sources:

* a cycle table (:func:`walk3d.io.read_cycle_table`), e.g.
  ``falisse2019/cycle_right_leg_mean_sd.csv`` (OpenSim coordinate names, right leg) or Winter's
  sagittal table;
* trial files (IK ``.mot``, GRF ``.mot``, optional ID ``.sto``) cut into cycles at force-plate
  heel strikes (:func:`trial_reference`, files read by :mod:`walk3d.trials.trial`).

Column mapping, explicit and with signs (measured value × sign = walk3d convention, see
:mod:`walk3d.validation.quantities`):

* OpenSim names: ``<coordinate>[_r]`` in ``deg`` (or ``rad``) for angles,
  ``<coordinate>[_r]_moment`` in ``Nm_per_kg`` (or ``Nm``, divided by the body mass) for
  moments, ``grf_right_{fore_aft,vertical,lateral}`` (or ``grf_{x,y,z}``) in ``N_per_kg`` (or
  ``N``) for the right foot's reaction in OpenSim's ground frame (z to the right). Every sign is
  +1 except the knee: gait2392-family models (gait2354, the Falisse 2019 subject, Hamner 2010)
  have ``knee_angle`` negative in flexion, Rajagopal 2016 positive. ``knee_sign="auto"`` reads it
  from the data (a knee in walking flexes ~60° and never hyper-extends much, so the sign of
  the larger excursion is flexion); the knee moment takes the same sign (same coordinate).
* Winter's table (``hip_angle``, ``hip_moment``...): angles flexion/dorsiflexion positive,
  moments **extensor** (and plantarflexor) positive, so the three moments flip sign;
  ``horizontal_grf`` is forward positive.

Quantities the source does not have are simply absent from :attr:`Reference.mean`; the
comparison lists them as missing.

Cycles: each heel strike on a force plate starts a cycle of that foot, which ends at the same
foot's next plate heel strike or, when that was off the plates (one plate per foot in most
overground trials), one period ``T`` later (``T`` from
:func:`walk3d.trials.descriptors.descriptors_from_trial`); a cycle is kept for a quantity only
when the quantity's file covers it. The foot's ground reaction is
known over its whole cycle even without a second plate strike: it is on its plate in stance and
in the air in swing. Left cycles stand in for right ones after mirroring the midline
frontal/transverse quantities and the lateral force (:data:`MIRRORED_ON_LEFT`); the
coordinate sign of the knee follows :func:`walk3d.trials.kinematics.detect_knee_sign`.
Cycles of both feet and all trials are pooled into mean ± SD (sample SD; NaN with one cycle).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from walk3d.io.cycle_table import CycleTable
from walk3d.io.storage import Storage
from walk3d.trials.events import mean_sd, normalize_cycles
from walk3d.trials.kinematics import detect_knee_sign
from walk3d.trials.trial import Trial
from walk3d.validation.quantities import MIRRORED_ON_LEFT, QUANTITIES, Quantity

__all__ = ["Reference", "reference_from_table", "trial_reference"]

N_PERCENT = 101

_GRF_ALIASES = {
    "grf_fore_aft": ("grf_right_fore_aft", "grf_r_fore_aft", "grf_fore_aft", "grf_right_x",
                     "grf_x", "ground_force_r_vx"),
    "grf_vertical": ("grf_right_vertical", "grf_r_vertical", "grf_vertical", "grf_right_y",
                     "grf_y", "ground_force_r_vy"),
    "grf_lateral": ("grf_right_lateral", "grf_r_lateral", "grf_lateral", "grf_right_z",
                    "grf_z", "ground_force_r_vz"),
}  # fmt: skip
_WINTER = {
    "angle:hip_flexion": ("hip_angle", 1.0),
    "angle:knee_flexion": ("knee_angle", 1.0),
    "angle:ankle_dorsiflexion": ("ankle_angle", 1.0),
    "grf:grf_fore_aft": ("horizontal_grf", 1.0),
    "grf:grf_vertical": ("vertical_grf", 1.0),
    "moment:hip_flexion": ("hip_moment", -1.0),
    "moment:knee_flexion": ("knee_moment", -1.0),
    "moment:ankle_dorsiflexion": ("ankle_moment", -1.0),
}
"""Winter (2009) sagittal table: walk3d key -> (base name, sign)."""


@dataclass(frozen=True)
class Reference:
    """Mean and SD of each available quantity over 0–100 % of the cycle (101 samples).

    ``mean`` and ``sd`` are keyed by :attr:`Quantity.key`; ``n_cycles`` gives the number of
    cycles per key (``None`` when the source does not say, e.g. a published table).
    """

    name: str
    percent: np.ndarray
    mean: dict[str, np.ndarray]
    sd: dict[str, np.ndarray]
    n_cycles: dict[str, int | None] = field(default_factory=dict)
    notes: tuple[str, ...] = ()

    def has(self, key: str) -> bool:
        return key in self.mean


def _resample(percent: np.ndarray, values: np.ndarray) -> np.ndarray:
    target = np.linspace(0.0, 100.0, N_PERCENT)
    if percent.size == N_PERCENT and np.allclose(percent, target):
        return np.asarray(values, dtype=float)
    return np.interp(target, percent, values)


def _find(table: CycleTable, bases: tuple[str, ...], units: dict[str, float]):
    """First ``<base>_<unit>`` column present: (name, unit factor) or None."""
    for base in bases:
        for unit, factor in units.items():
            name = f"{base}_{unit}"
            if name in table.names:
                return name, factor
    return None


def _column_candidates(q: Quantity) -> tuple[str, ...]:
    if q.group == "grf":
        return _GRF_ALIASES[q.name]
    c = q.coordinate
    if q.group == "angle":
        return (c, f"{c}_r")
    return (f"{c}_moment", f"{c}_r_moment", f"{c}_moment_r")


def reference_from_table(
    table: CycleTable,
    *,
    mass: float | None = None,
    name: str = "cycle table",
    knee_sign: float | str = "auto",
) -> Reference:
    """Map a cycle table's columns onto :data:`QUANTITIES` (see the module doc).

    Args:
        mass: Body mass (kg), needed only for columns in N or N m (divided by it).
        knee_sign: ``+1``, ``-1`` or ``"auto"`` (from the knee-angle column; -1, the gait2392
            convention, when the table has no knee angle).
    """
    per_kg = np.nan if mass is None else 1.0 / mass
    units = {
        "angle": {"deg": 1.0, "rad": float(np.degrees(1.0))},
        "moment": {"Nm_per_kg": 1.0, "Nm": per_kg},
        "grf": {"N_per_kg": 1.0, "N": per_kg},
    }
    winter = any(n.startswith("hip_moment") for n in table.names) and not any(
        n.startswith("hip_flexion") for n in table.names
    )
    notes = []
    if knee_sign == "auto":
        hit = _find(table, ("knee_angle", "knee_angle_r"), units["angle"])
        if hit is None:
            knee_sign = -1.0
            notes.append("no knee angle: knee sign assumed -1 (gait2392 convention)")
        else:
            knee_sign = detect_knee_sign(table.column(hit[0])[0])
    mean, sd, counts = {}, {}, {}
    for q in QUANTITIES:
        sign = 1.0
        if winter:
            if q.key not in _WINTER:
                continue
            base, sign = _WINTER[q.key]
            bases = (base,)
        else:
            bases = _column_candidates(q)
            if q.coordinate == "knee_angle":
                sign = float(knee_sign)
        hit = _find(table, bases, units[q.group])
        if hit is None:
            continue
        col, factor = hit
        if not np.isfinite(factor):
            notes.append(f"{col}: needs the body mass to convert, skipped")
            continue
        m, s = table.column(col)
        mean[q.key] = _resample(table.percent, sign * factor * m)
        sd[q.key] = _resample(table.percent, abs(factor) * s)
        counts[q.key] = None
    if winter:
        notes.append("Winter table: sagittal quantities only; moments were extensor-positive")
    return Reference(name, np.linspace(0.0, 100.0, N_PERCENT), mean, sd, counts, tuple(notes))


def _cycles(trial: Trial) -> list[tuple[str, float, float]]:
    if trial.descriptors is None:
        return []
    period = trial.descriptors.period
    out = []
    for side, ev in trial.descriptors.events.items():
        strikes = np.sort(ev.heel_strikes)
        for k, hs in enumerate(strikes):
            nxt = strikes[k + 1] if k + 1 < strikes.size else None
            end = float(nxt) if nxt is not None and nxt - hs < 1.5 * period else hs + period
            out.append((side, float(hs), end))
    return out


def _series(trial: Trial, q: Quantity, side: str, knee_sign: float, mass: float):
    """(time, values) of one quantity for one side in Table 2 units, or None."""
    s = side[0]
    sign = -1.0 if side == "left" and q.name in MIRRORED_ON_LEFT else 1.0
    if q.group == "grf":
        if trial.loads is None:
            return None
        return trial.loads.time, sign * trial.loads.foot(side).force[:, q.axis] / mass
    if q.coordinate == "knee_angle":
        sign *= knee_sign
    midline = q.coordinate.startswith(("pelvis_", "lumbar_"))
    if q.group == "angle":
        col = q.coordinate if midline else f"{q.coordinate}_{s}"
        st = trial.ik
        if st is None or not st.has_column(col):
            return None
        scale = np.degrees(1.0) if st.in_degrees is False else 1.0
        return st.time, sign * scale * st.column(col)
    col = f"{q.coordinate}_moment" if midline else f"{q.coordinate}_{s}_moment"
    st = trial.inverse_dynamics
    if st is None or not st.has_column(col):
        return None
    return st.time, sign * st.column(col) / mass


MIN_IK_CYCLE = 0.95
"""Shortest IK (or ID) taken as periodic when it holds no whole cycle, as a fraction of the
gait period: the rest of the cycle is bridged by linear interpolation across the seam."""


def periodic_storage(st: Storage, period: float) -> Storage:
    """``st`` repeated one period earlier and later, outside its own time span."""
    t = st.time
    before, after = t - period < t[0], t + period > t[-1]
    time = np.concatenate([t[before] - period, t, t[after] + period])
    data = np.concatenate([st.data[before], st.data, st.data[after]])
    return Storage(st.name, time, st.columns, data, st.in_degrees, st.header, st.path)


def _periodic_trial(trial: Trial) -> tuple[Trial, str | None]:
    """The trial with its IK and ID periodic (:func:`periodic_storage`) when they span at least
    :data:`MIN_IK_CYCLE` of its period, and the note that says so (None: unchanged)."""
    d = trial.descriptors
    if d is None or trial.ik is None:
        return trial, None
    span = float(trial.ik.time[-1] - trial.ik.time[0])
    if span < MIN_IK_CYCLE * d.period:
        return trial, None
    inv = trial.inverse_dynamics
    inv = None if inv is None else periodic_storage(inv, d.period)
    changed = replace(trial, ik=periodic_storage(trial.ik, d.period), inverse_dynamics=inv)
    return changed, (f"no complete cycle in the IK of {trial.name} ({span:.3f} s, T = "
                     f"{d.period:.4f} s): IK and ID repeated one period earlier and later, the "
                     "gap bridged linearly")  # fmt: skip


def _check_cycles_meet_ik(trials: list[Trial]) -> None:
    """Raise ValueError (one line) when no plate cycle of any trial meets its IK's time span:
    the GRF and IK overlap only where no cycle is, so the reference would have no angles."""
    spans = []
    for t in trials:
        cycles = _cycles(t)
        if t.ik is None or t.ik.time.size == 0 or not cycles:
            continue
        a, b = float(t.ik.time[0]), float(t.ik.time[-1])
        if any(start < b and end > a for _, start, end in cycles):
            return
        strikes = [start for _, start, _ in cycles]
        spans.append(f"the GRF's heel strikes of {t.name} at {min(strikes):.3g}-"
                     f"{max(strikes):.3g} s fall outside its IK's {a:.3g}-{b:.3g} s")  # fmt: skip
    if spans:
        raise ValueError("; ".join(spans) + ": no gait cycle has both angles and forces (are "
                         "the files' times from the same clock?)")  # fmt: skip


def trial_reference(trials: list[Trial], mass: float, knee_sign: float | str = "auto") -> Reference:
    """Pooled mean ± SD cycles of the trials (module doc), in Table 2 units. When no IK holds
    a whole cycle between plate heel strikes, IKs (and IDs) that span nearly one are taken as
    periodic (:func:`periodic_storage`; OpenSim's treadmill example: 1.20 s, T = 1.224 s)."""
    ref = _trial_reference(trials, mass, knee_sign)
    if ref.has("angle:knee_flexion") or not any(t.ik is not None for t in trials):
        return ref
    _check_cycles_meet_ik(trials)
    changed = [_periodic_trial(t) for t in trials]
    notes = tuple(n for _, n in changed if n)
    if not notes:
        return ref
    again = _trial_reference([t for t, _ in changed], mass, knee_sign)
    return replace(again, notes=again.notes + notes)


def _trial_reference(trials: list[Trial], mass: float, knee_sign: float | str) -> Reference:
    if knee_sign == "auto":
        knees = [t.ik.column(c) for t in trials if t.ik is not None and t.knee_sign is None
                 for c in ("knee_angle_r", "knee_angle_l") if t.ik.has_column(c)]  # fmt: skip
        knee_sign = detect_knee_sign(np.concatenate(knees)) if knees else -1.0
        signs = [float(knee_sign) if t.knee_sign is None else t.knee_sign for t in trials]
    else:
        signs = [float(knee_sign)] * len(trials)
    mean, sd, counts = {}, {}, {}
    for q in QUANTITIES:
        sets = []
        for trial, sign in zip(trials, signs, strict=True):
            for side, start, end in _cycles(trial):
                series = _series(trial, q, side, sign, mass)
                if series is not None:
                    sets.append(normalize_cycles(series[0], series[1], [start, end], N_PERCENT))
        n = sum(c.shape[1] for c in sets)
        if n == 0:
            continue
        m, s = mean_sd(*sets)
        mean[q.key], sd[q.key], counts[q.key] = m, s, n
    names = ", ".join(t.name for t in trials)
    stated = sorted({f"{s:+.0f}" for s in signs})
    notes = (f"knee sign {', '.join(stated)}", "cycles from plate heel strikes, both feet pooled")
    notes += tuple(n for t in trials for n in t.notes)
    return Reference(names, np.linspace(0.0, 100.0, N_PERCENT), mean, sd, counts, notes)
