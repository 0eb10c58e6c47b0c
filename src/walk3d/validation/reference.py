"""Measured reference cycles (mean ± SD over 0–100 % from right heel strike) in Table 2 units.

Two sources:

* a cycle table (:func:`walk3d.io.read_cycle_table`), e.g.
  ``falisse2019/cycle_right_leg_mean_sd.csv`` (OpenSim coordinate names, right leg) or Winter's
  sagittal table;
* trial files (IK ``.mot``, GRF ``.mot``, optional ID ``.sto``) cut into cycles at force-plate
  heel strikes (:mod:`walk3d.validation.trial`).

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
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from walk3d.io.cycle_table import CycleTable
from walk3d.validation.quantities import QUANTITIES, Quantity

__all__ = ["Reference", "detect_knee_sign", "reference_from_table"]

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


def detect_knee_sign(knee: np.ndarray) -> float:
    """``+1`` if a knee-angle series is positive in flexion, ``-1`` if negative (see module doc)."""
    k = np.asarray(knee, dtype=float)
    k = k[np.isfinite(k)]
    if k.size == 0:
        raise ValueError("no finite knee angles to detect the knee sign from")
    return 1.0 if abs(float(k.max())) >= abs(float(k.min())) else -1.0


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
