"""Input checks of :func:`walk3d.validation.target.tracking_target`: one DataFileError line each.

They run before the files are cut into cycles, so that a bad file is named with its problem
(a missing column, NaN, a time column that does not increase, no heel strike) rather than
failing later inside event detection or cycle normalisation with a message that names neither.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping
from pathlib import Path

import numpy as np

from walk3d.io.checks import increasing
from walk3d.io.errors import DataFileError
from walk3d.io.external_loads import find_plates
from walk3d.io.storage import Storage
from walk3d.results.opensim import OPENSIM_COORDINATES
from walk3d.trials.events import FootEvents, detect_contacts, stride_periods
from walk3d.validation.reference import Reference

__all__ = [
    "REQUIRED_IK",
    "check_grf",
    "check_ik",
    "ik_span",
    "plate_period",
    "require_angles",
    "table_stance",
]

REQUIRED_IK = tuple(f"{c}_{s}" for s in "rl" for c in ("hip_flexion", "knee_angle", "ankle_angle"))
"""IK columns a target needs: the sagittal leg angles of both legs (the half-cycle lag and
the pooled cycles use both)."""
_REQUIRED_TABLE = {
    "hip_flexion": ("hip_flexion", "hip angle"),
    "knee_flexion": ("knee_angle", "knee angle"),
    "ankle_dorsiflexion": ("ankle_angle", "ankle angle"),
}
"""walk3d DoF (no side) -> (OpenSim coordinate, Winter's column) every cycle table needs."""
_USED_IK = ("pelvis_tilt", "pelvis_list", "pelvis_rotation", *sorted(OPENSIM_COORDINATES.values()))
"""IK columns the target reads (when present); ``pelvis_tx`` too when it gives the speed."""
_PLATE_FORCE = re.compile(r"^(?P<ident>.*ground_force_(?:.*_)?)v[xyz]$")
HEEL_STRIKE_TOLERANCE = 0.05
"""Farthest a table's right heel strike may lie from 0 %, as a fraction of the cycle."""


def _path(storage: Storage) -> Path:
    return storage.path if storage.path is not None else Path(storage.name or "storage")


def _check_time(storage: Storage) -> None:
    if storage.time.size < 2:
        raise DataFileError(_path(storage), f"holds {storage.time.size} sample(s): no motion")
    increasing(_path(storage), "the time column", storage.time)


def check_ik(ik: Storage, need_speed: bool) -> None:
    """Time increasing, :data:`REQUIRED_IK` (and ``pelvis_tx`` when the speed comes from it)
    present, every column the target reads finite."""
    _check_time(ik)
    required = REQUIRED_IK + (("pelvis_tx",) if need_speed else ())
    missing = [c for c in required if not ik.has_column(c)]
    if missing:
        why = (
            "the speed comes from it (or give the speed)"
            if missing[0] == "pelvis_tx"
            else ("a tracking target needs the hip, knee and ankle angles of both legs")
        )
        raise DataFileError(_path(ik), f"no column {missing[0]!r}: {why}")
    for column in _USED_IK + (("pelvis_tx",) if need_speed else ()):
        if ik.has_column(column):
            ik.column(column)  # DataFileError naming the column when not finite


def _plates(grf: Storage) -> list[str]:
    """Force identifiers of the GRF's plates; a plate missing a force or point column is named
    in a DataFileError."""
    columns = set(grf.columns)
    idents = sorted({m["ident"] for c in grf.columns if (m := _PLATE_FORCE.match(c))})
    for ident in idents:
        needed = [f"{ident}{kind}{a}" for kind in "vp" for a in "xyz"]
        absent = [n for n in needed if n not in columns]
        if absent:
            raise DataFileError(_path(grf), f"no column {absent[0]!r} (plate {ident}v*)")
    if not find_plates(grf):
        raise DataFileError(_path(grf), "no ground reaction columns (ground_force_v[xyz], "
                            "ground_force_p[xyz])")  # fmt: skip
    return [p.force_identifier for p in find_plates(grf)]


def check_grf(grf: Storage, threshold: float) -> None:
    """Time increasing, complete plate columns, finite vertical forces, and some heel strike:
    a plate whose vertical force rises above ``threshold`` (N)."""
    _check_time(grf)
    verticals = [f"{force}y" for force in _plates(grf)]
    for name in verticals:
        if detect_contacts(grf.time, grf.column(name), threshold).heel_strikes.size:
            return
    raise DataFileError(_path(grf), f"no heel strike found: the vertical force "
                        f"({', '.join(verticals)}) never rises above {threshold:g} N")  # fmt: skip


def ik_span(ik: Storage) -> float:
    """Time from the first to the last IK sample, s."""
    return float(ik.time[-1] - ik.time[0])


def plate_period(events: Mapping[str, FootEvents]) -> float:
    """The period the plates alone show: the mean stride, else twice the mean step between
    heel strikes of opposite feet, else 0 (s). Unlike the kinematic half-cycle lag, it does not
    depend on the IK's length."""
    strides = stride_periods(events)
    if strides.size:
        return float(np.mean(strides))
    strikes = sorted((float(t), side) for side, ev in events.items() for t in ev.heel_strikes)
    steps = [b[0] - a[0] for a, b in zip(strikes[:-1], strikes[1:], strict=True) if a[1] != b[1]]
    return 2.0 * float(np.mean(steps)) if steps else 0.0


def require_angles(path: Path, ref: Reference, names: Iterable[str]) -> None:
    """A cycle table's reference must have hip flexion, knee and ankle angles; else one line
    naming the expected column (OpenSim names, or Winter's for a Winter-layout table)."""
    names = tuple(names)
    winter = any(n.startswith("hip_moment") for n in names) and not any(
        n.startswith("hip_flexion") for n in names
    )
    for dof, (coordinate, winter_name) in _REQUIRED_TABLE.items():
        if not ref.has(f"angle:{dof}"):
            expected = (
                f"{winter_name!r} in deg"
                if winter
                else f"{coordinate}_deg_mean (or {coordinate}_r_deg_mean, or _rad_mean)"
            )
            raise DataFileError(path, f"no column {expected}: a tracking target needs the hip, "
                                "knee and ankle angles")  # fmt: skip


def table_stance(path: Path, percent: np.ndarray, vertical: np.ndarray, threshold: float) -> float:
    """Right stance as a fraction of the cycle, from a table's right vertical GRF (N/kg; contact
    above ``threshold`` N/kg), whose heel strike must lie at 0 % (within
    :data:`HEEL_STRIKE_TOLERANCE`, the table read as periodic)."""
    p = np.asarray(percent, float)[:-1] / 100.0
    time = np.concatenate([p - 1.0, p, p + 1.0])
    force = np.tile(np.asarray(vertical, float)[:-1], 3)
    ev = detect_contacts(time, force, threshold, min_contact=0.1, min_gap=0.05)
    near = ev.heel_strikes[np.abs(ev.heel_strikes) <= HEEL_STRIKE_TOLERANCE]
    if near.size == 0:
        inside = ev.heel_strikes[(ev.heel_strikes >= 0) & (ev.heel_strikes < 1)]
        if inside.size == 0:
            raise DataFileError(path, "no heel strike found: the right vertical GRF never rises "
                                f"above {threshold:.3g} N/kg")  # fmt: skip
        raise DataFileError(
            path,
            f"the right heel strike is at {100 * inside[0]:.0f} % of the "
            "cycle, not at 0 %: a cycle table starts at right heel strike",
        )
    offs = ev.toe_offs[ev.toe_offs > near[0]]
    if offs.size == 0:
        raise DataFileError(path, "no toe off found: the right vertical GRF never falls below "
                            f"{threshold:.3g} N/kg")  # fmt: skip
    return float(offs[0] - near[0])
