"""Measured trials (IK + GRF + optional ID storages) and their mean ± SD cycles.

Files are recognised by their columns: ground reaction columns (``*ground_force_*v[xyz]``) make a
GRF file, ``*_moment`` columns an ID file, OpenSim coordinates (``knee_angle_r``...) an IK file.

Cycles: each heel strike on a force plate starts a cycle of that foot, which ends at the same
foot's next plate heel strike or, when that was off the plates (one plate per foot in most
overground trials), one period ``T`` later (``T`` from :func:`descriptors_from_trial`); a cycle
is kept for a quantity only when the quantity's file covers it. The foot's ground reaction is
known over its whole cycle even without a second plate strike: it is on its plate in stance and
in the air in swing. Left cycles stand in for right ones after mirroring the midline
frontal/transverse quantities and the lateral force (:data:`MIRRORED_ON_LEFT`); the
coordinate sign of the knee follows :func:`walk3d.validation.reference.detect_knee_sign`.
Cycles of both feet and all trials are pooled into mean ± SD (sample SD; NaN with one cycle).

C3D trials (:func:`load_c3d_trial`) go through the same code: :func:`walk3d.io.read_c3d_trial`
turns the force platforms into a GRF storage in walk3d's ground frame (plates assigned to the
feet by :func:`walk3d.io.extract_foot_loads`'s rules) and the Plug-in Gait angles into an IK
storage whose knee is flexion positive (the trial's ``knee_sign`` is +1, not detected).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from os import PathLike
from pathlib import Path

import numpy as np

from walk3d.io.c3d_trial import read_c3d_trial
from walk3d.io.events import mean_sd, normalize_cycles
from walk3d.io.external_loads import FootLoads, find_plates
from walk3d.io.storage import Storage, read_storage
from walk3d.validation.descriptors import GaitDescriptors, descriptors_from_trial, foot_loads
from walk3d.validation.quantities import MIRRORED_ON_LEFT, QUANTITIES, Quantity
from walk3d.validation.reference import N_PERCENT, Reference, detect_knee_sign

__all__ = ["Trial", "classify_storage", "load_c3d_trial", "load_trial", "trial_reference"]


@dataclass(frozen=True)
class Trial:
    """One measured trial; ``descriptors`` needs the GRF (and IK for V and the lag).

    ``knee_sign`` is the sign of the IK knee coordinate in flexion when the source states it
    (C3D: +1); None lets :func:`trial_reference` detect it.
    """

    name: str
    ik: Storage | None
    loads: FootLoads | None
    inverse_dynamics: Storage | None
    descriptors: GaitDescriptors | None
    knee_sign: float | None = None
    notes: tuple[str, ...] = ()


def classify_storage(storage: Storage) -> str | None:
    """``"grf"``, ``"id"``, ``"ik"`` or None, from the column labels (module doc)."""
    if find_plates(storage):
        return "grf"
    if any(c.endswith("_moment") for c in storage.columns):
        return "id"
    if any(c.startswith(("knee_angle", "hip_flexion", "pelvis_tilt")) for c in storage.columns):
        return "ik"
    return None


def load_trial(
    ik: str | PathLike[str] | Storage | None = None,
    grf: str | PathLike[str] | Storage | None = None,
    inverse_dynamics: str | PathLike[str] | Storage | None = None,
    *,
    threshold: float = 20.0,
    speed: float | None = None,
    name: str | None = None,
) -> Trial:
    """Read a trial's files (any may be None) and its descriptors when the GRF is given.

    Raises:
        DataFileError: A file is malformed. ValueError: the plates cannot be assigned or the
        events do not give a period / double support.
    """

    def read(x):
        return None if x is None else (x if isinstance(x, Storage) else read_storage(x))

    ik_s, grf_s, id_s = read(ik), read(grf), read(inverse_dynamics)
    loads = None if grf_s is None else foot_loads(grf_s)
    desc = None
    if loads is not None:
        desc = descriptors_from_trial(ik_s, loads, threshold=threshold, speed=speed)
    if name is None:
        first = next((s.path for s in (ik_s, grf_s, id_s) if s is not None and s.path), None)
        name = Path(first).stem if first else "trial"
    return Trial(name, ik_s, loads, id_s, desc)


def load_c3d_trial(
    path: str | PathLike[str],
    *,
    threshold: float = 20.0,
    speed: float | None = None,
    forward: str | None = None,
) -> Trial:
    """A C3D file as a trial (module doc; lab axes as in :mod:`walk3d.io.c3d_trial`).

    Raises:
        DataFileError: Malformed file, no force platform or no walking direction.
        ValueError: As :func:`load_trial`.
    """
    c3d = read_c3d_trial(path, forward=forward)
    plates = find_plates(c3d.grf)
    if len(plates) != 2:
        raise ValueError(
            f"{c3d.path.name}: {len(plates)} loaded force platforms; a C3D reference needs two, "
            "one per foot (assigned by their lateral position)"
        )
    trial = load_trial(c3d.ik, c3d.grf, None, threshold=threshold, speed=speed, name=c3d.path.stem)
    return replace(trial, knee_sign=1.0, notes=c3d.notes)


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


def trial_reference(trials: list[Trial], mass: float, knee_sign: float | str = "auto") -> Reference:
    """Pooled mean ± SD cycles of the trials (module doc), in Table 2 units."""
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
