"""The measured side of ``walk3d track`` (issue #58): a trial or cycle table on walk3d's DoFs.

:func:`tracking_target` reads an IK ``.mot`` with its GRF ``.mot`` or a cycle table and returns
a :class:`TrackingTarget`: joint angles on walk3d's 24 DoFs, pelvis angles and both feet's
ground reactions over 0–100 % of the cycle from right heel strike (101 samples), with masks of
what the source measures, and V, T, Td.

The quantities are exactly those of ``walk3d validate`` (:mod:`.reference`, same functions):
the target's right-side and midline series are :class:`~walk3d.validation.reference.Reference`
means in radians (angles) and body weights (forces), so a tracking RMSE over the 101 samples
equals ``walk3d validate``'s RMSE of the same prediction read as validate reads it: 0 % at
``t = T/2 - Td`` of walk3d's cycle, which starts at right toe off
(:func:`walk3d.validation.compare.align_prediction`). Angles are OpenSim coordinates with
Rajagopal's signs (knee flexion positive: a gait2392 knee, negative in flexion, is flipped),
which is what ``Prediction.joint_angle`` reports: ``2 asin(q)`` for hinges and both ankle axes,
:func:`walk3d.results.angles.ball_joint_angles` (Z-X-Y; left joints mirrored) for ball joints.
The 100 % sample is the measured one (a mean cycle need not close exactly), as validate has it.

Left side: validate pools both feet's cycles into one right-side mean (left cycles mirrored),
and a right-leg table has only the right side, so every left-limb series is the right one half
a cycle later (walk3d's symmetric layout, as :func:`.measured.fit_measured_gait` fits it); the
left foot's lateral force changes sign. The left masks equal the right ones.

Checks, each one :class:`~walk3d.io.errors.DataFileError` line naming the file, before any
solve: a missing required column, NaN or infinite values, a time column that does not
increase, no heel strike in the vertical GRF (a table's must be at 0 %), and an IK that spans
less than :data:`MIN_IK_CYCLE` of a gait cycle. An IK with no complete cycle of either foot
between plate heel strikes but at least that much of one (the OpenSim example trial: 1.20 s,
T = 1.224 s) is taken as periodic: repeated one period earlier and later before validate's
cutting, which bridges the gap by linear interpolation (``walk3d validate`` finds no angle
cycle in such a trial).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from functools import cache
from os import PathLike
from pathlib import Path

import numpy as np

from walk3d.body.model import build_body
from walk3d.constants import G
from walk3d.io.checks import positive_numbers
from walk3d.io.cycle_table import CycleTable, read_cycle_table
from walk3d.io.errors import DataFileError
from walk3d.io.storage import Storage, read_storage
from walk3d.trials.trial import Trial, load_trial
from walk3d.validation.quantities import MIRRORED_ON_LEFT, QUANTITIES
from walk3d.validation.reference import (
    MIN_IK_CYCLE,
    N_PERCENT,
    Reference,
    reference_from_table,
    trial_reference,
)
from walk3d.validation.target_checks import (
    check_grf,
    check_ik,
    ik_span,
    plate_period,
    require_angles,
    table_stance,
)

__all__ = ["MIN_IK_CYCLE", "TrackingTarget", "target_from_reference", "tracking_target"]

PELVIS = ("pelvis_tilt", "pelvis_list", "pelvis_rotation")


@cache
def _walk3d_dofs() -> tuple[str, ...]:
    """walk3d's 24 DoFs in :attr:`walk3d.body.model.BodyModel.dof_names` order."""
    return build_body().dof_names


@dataclass(frozen=True)
class TrackingTarget:
    """A measured gait cycle on walk3d's DoFs (module doc); unmeasured entries are 0."""

    source: str
    """One line: the files and how the cycle was made."""
    percent: np.ndarray
    """(101,) percent of the cycle, 0 and 100 at right heel strikes."""
    angles: np.ndarray
    """(101, 24) rad, walk3d DoF order (:attr:`dof_names`), ``Prediction.joint_angle``'s
    convention (module doc)."""
    angle_mask: np.ndarray
    """(24,) bool: the source measures this DoF (the neck never, arms not in gait2354)."""
    pelvis: np.ndarray
    """(101, 3) rad: OpenSim pelvis tilt, list, rotation (global Z-X-Y, as
    :func:`walk3d.results.angles.pelvis_angles`)."""
    pelvis_mask: np.ndarray
    """(3,) bool."""
    grf: np.ndarray | None
    """(101, 2, 3) ground reaction on the (right, left) foot in body weights, ground axes
    (x forward, y up, z right); None without any ground reaction in the source."""
    grf_mask: np.ndarray | None
    """(2, 3) bool, rows (right, left) equal; None with ``grf``."""
    speed: float | None
    """V, m/s; None when the source cannot give it (a table without speed or period)."""
    period: float | None
    """T, s."""
    double_support: float | None
    """Td, s (one double-support phase)."""
    mass: float
    """Body mass, kg, that divided forces given in N."""
    dof_names: tuple[str, ...] = field(default_factory=_walk3d_dofs)
    notes: tuple[str, ...] = ()
    """Where V, T, Td came from, the knee sign, fallbacks taken."""

    def __post_init__(self) -> None:
        for name in ("percent", "angles", "angle_mask", "pelvis", "pelvis_mask", "grf", "grf_mask"):
            value = getattr(self, name)
            if value is not None:
                value = np.array(value)
                value.flags.writeable = False
                object.__setattr__(self, name, value)

    def angle(self, dof: str) -> np.ndarray:
        """(101,) rad of one DoF (``KeyError`` when it is not a walk3d DoF)."""
        if dof not in self.dof_names:
            raise KeyError(f"no DoF {dof!r}")
        return self.angles[:, self.dof_names.index(dof)]


def _half_cycle_later(percent: np.ndarray, values: np.ndarray) -> np.ndarray:
    """``values`` at ``percent + 50`` (periodic, on the sample grid 0..100 %)."""
    return np.interp(np.mod(percent + 50.0, 100.0), percent[:-1], values[:-1], period=100.0)


def _side_free(dof: str) -> tuple[str, str | None]:
    return (dof[:-2], dof[-1]) if dof.endswith(("_r", "_l")) else (dof, None)


def target_from_reference(
    ref: Reference,
    *,
    mass: float,
    source: str,
    speed: float | None = None,
    period: float | None = None,
    double_support: float | None = None,
    notes: tuple[str, ...] = (),
) -> TrackingTarget:
    """A :class:`TrackingTarget` of a validate reference's means (deg -> rad, N/kg -> body
    weights; left limbs and the left foot half a cycle later, module doc)."""
    p = np.asarray(ref.percent, float)
    if p.size != N_PERCENT or not np.allclose(p, np.linspace(0.0, 100.0, N_PERCENT)):
        raise ValueError("a reference must be on 101 samples from 0 to 100 %")
    names = _walk3d_dofs()
    angles, mask = np.zeros((p.size, len(names))), np.zeros(len(names), bool)
    for k, dof in enumerate(names):
        name, side = _side_free(dof)
        if ref.has(f"angle:{name}"):
            right = np.radians(ref.mean[f"angle:{name}"])
            angles[:, k] = _half_cycle_later(p, right) if side == "l" else right
            mask[k] = True
    pelvis, pelvis_mask = np.zeros((p.size, 3)), np.zeros(3, bool)
    for k, name in enumerate(PELVIS):
        if ref.has(f"angle:{name}"):
            pelvis[:, k], pelvis_mask[k] = np.radians(ref.mean[f"angle:{name}"]), True
    grf, grf_mask = np.zeros((p.size, 2, 3)), np.zeros((2, 3), bool)
    for q in (q for q in QUANTITIES if q.group == "grf" and ref.has(q.key)):
        right = ref.mean[q.key] / G
        flip = -1.0 if q.name in MIRRORED_ON_LEFT else 1.0
        grf[:, 0, q.axis], grf[:, 1, q.axis] = right, flip * _half_cycle_later(p, right)
        grf_mask[:, q.axis] = True
    for array in (angles, pelvis, grf):
        if not np.isfinite(array).all():
            raise ValueError(f"{ref.name}: the reference holds non-finite means")
    have_grf = bool(grf_mask.any())
    return TrackingTarget(
        source, p.copy(), angles, mask, pelvis, pelvis_mask, grf if have_grf else None,
        grf_mask if have_grf else None, speed, period, double_support, float(mass),
        notes=tuple(notes),
    )  # fmt: skip


def tracking_target(
    *,
    table: str | PathLike[str] | None = None,
    ik: str | PathLike[str] | None = None,
    grf: str | PathLike[str] | None = None,
    mass: float,
    speed: float | None = None,
    period: float | None = None,
    double_support: float | None = None,
    threshold: float = 20.0,
) -> TrackingTarget:
    """The tracking target of a cycle table, or of an IK with its GRF (module doc).

    Args:
        table: Cycle table ``.csv`` (:func:`walk3d.io.read_cycle_table`; right leg, 0 % at
            right heel strike), or else ``ik`` and ``grf``: a trial's OpenSim storages.
        mass: Body mass, kg: forces given in N are divided by it; the heel-strike threshold of
            a table in N/kg is ``threshold / mass``.
        speed, period, double_support: V (m/s), T and Td (s), replacing the source's. A trial
            gives all three (a treadmill trial needs ``speed``); a table gives V and T from its
            notes (Winter's), or one from the other and the pelvis's stride, and Td from the
            stance of its vertical GRF once T is known.
        threshold: Vertical force (N) above which a foot is in contact.

    Raises:
        DataFileError: Bad data (module doc), one line naming the file.
        FileNotFoundError: A file does not exist. ValueError: Bad arguments.
    """
    positive_numbers(mass=mass, speed=speed, period=period, double_support=double_support,
                     threshold=threshold)  # fmt: skip
    if period is not None and double_support is not None and double_support >= period / 2:
        raise ValueError(f"double_support {double_support:g} s must be under half the period "
                         f"{period:g} s")  # fmt: skip
    given = {"speed": speed, "period": period, "double_support": double_support}
    if table is not None:
        if ik is not None or grf is not None:
            raise ValueError("give a cycle table or an IK and GRF file, not both")
        return _from_table(Path(table), float(mass), given, threshold)
    if ik is None or grf is None:
        raise ValueError("a tracking target needs a cycle table, or an IK file with its GRF file "
                         "(the GRF's heel strikes cut the cycle)")  # fmt: skip
    return _from_trial(Path(ik), Path(grf), float(mass), given, threshold)


_NUMBER = re.compile(r"[-+]?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?")


def _metadata_value(table: CycleTable, *words: str) -> float | None:
    """First number of a metadata entry whose key holds one of ``words`` (Winter's notes)."""
    for key, text in table.metadata.items():
        if any(w in key.lower() for w in words):
            match = _NUMBER.search(str(text))
            if match and 0 < float(match.group()) < np.inf:
                return float(match.group())
    return None


def _stride(table: CycleTable) -> float | None:
    """Pelvis progression over the cycle (m) from a ``pelvis_tx_m`` column, or None. A column
    that drops back at its last row (Falisse's, reset to 0 at 100 %) is extrapolated."""
    if "pelvis_tx_m" not in table.names:
        return None
    tx, p = table.column("pelvis_tx_m")[0], table.percent
    if tx.size > 3 and tx[-1] < tx[-2]:
        tx, p = tx[:-1], p[:-1]
    stride = (tx[-1] - tx[0]) / (p[-1] - p[0]) * 100.0
    return float(stride) if stride > 0 else None


def _from_table(path: Path, mass: float, given: dict, threshold: float) -> TrackingTarget:
    table = read_cycle_table(path)
    ref = reference_from_table(table, mass=mass, name=path.name)
    require_angles(path, ref, table.names)
    notes = list(ref.notes)
    stance = None
    if ref.has("grf:grf_vertical"):
        stance = table_stance(path, ref.percent, ref.mean["grf:grf_vertical"], threshold / mass)
        notes.append(f"stance {100 * stance:.1f} % of the cycle (right vertical GRF > "
                     f"{threshold:g} N)")  # fmt: skip
    else:
        notes.append("no vertical GRF: 0 % taken as the right heel strike, no Td")
    speed, period = given["speed"], given["period"]
    speed = speed if speed is not None else _metadata_value(table, "speed")
    period = period if period is not None else _metadata_value(table, "duration", "period")
    stride = _stride(table)
    if stride is not None:
        notes.append(f"stride {stride:.4f} m (pelvis_tx)")
        if speed is None and period is not None:
            speed = stride / period
        elif period is None and speed is not None:
            period = stride / speed
    td = given["double_support"]
    if td is None and stance is not None and period is not None:
        td = (stance - 0.5) * period if stance > 0.5 else None
        if td is None:
            notes.append("stance under half the cycle: no double support, no Td")
    missing = [k for k, v in (("V", speed), ("T", period), ("Td", td)) if v is None]
    if missing:
        notes.append(f"the table does not give {', '.join(missing)}")
    source = f"cycle table {path.name} (right leg; left = right half a cycle later)"
    return target_from_reference(ref, mass=mass, source=source, speed=speed, period=period,
                                 double_support=td, notes=tuple(notes))  # fmt: skip


def _load(ik: Storage, grf: Storage, threshold: float, speed: float | None) -> Trial:
    """:func:`load_trial`, its ValueErrors as one DataFileError line naming the file at fault
    (speed and half-cycle lag: the IK; plates, events, period and Td: the GRF)."""
    try:
        return load_trial(ik, grf, threshold=threshold, speed=speed)
    except DataFileError:
        raise
    except ValueError as exc:
        text = " ".join(str(exc).split())
        at_ik = any(w in text for w in ("pelvis", "IK", "speed"))
        raise DataFileError(ik.path if at_ik else grf.path, text) from None


def _from_trial(ik_path: Path, grf_path: Path, mass: float, given: dict, threshold: float):
    ik, grf = read_storage(ik_path), read_storage(grf_path)
    check_ik(ik, need_speed=given["speed"] is None)
    check_grf(grf, threshold)
    trial = _load(ik, grf, threshold, given["speed"])
    d = trial.descriptors
    cycle = max(d.period, plate_period(d.events))
    span = ik_span(ik)
    if span < MIN_IK_CYCLE * cycle:
        raise DataFileError(ik_path, f"the IK spans {span:.3f} s, shorter than one gait cycle "
                            f"(about {cycle:.3f} s)")  # fmt: skip
    ref = trial_reference([trial], mass)  # periodic when the IK holds no whole cycle
    notes = [f"T from {d.period_method}", *d.notes, *ref.notes]
    if not ref.has("angle:knee_flexion"):
        where = f"IK {ik.time[0]:g}-{ik.time[-1]:g} s"
        raise DataFileError(ik_path, "holds no gait cycle from the force plates' heel strikes "
                            f"({where}: do the files overlap?)")  # fmt: skip
    if not ref.has("grf:grf_vertical"):
        raise DataFileError(grf_path, "holds no complete gait cycle of either foot")
    n_angle, n_grf = ref.n_cycles["angle:knee_flexion"], ref.n_cycles["grf:grf_vertical"]
    source = (f"trial {ik_path.name} + {grf_path.name}: {n_angle} angle and {n_grf} GRF "
              "cycle(s), both feet pooled (left = right half a cycle later)")  # fmt: skip
    values = {"speed": d.speed, "period": d.period, "double_support": d.double_support}
    values |= {k: v for k, v in given.items() if v is not None}
    return target_from_reference(ref, mass=mass, source=source, notes=tuple(notes), **values)
