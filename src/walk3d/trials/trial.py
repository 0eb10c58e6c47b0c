"""Measured trials (IK + GRF + optional ID storages).

Files are recognised by their columns: ground reaction columns (``*ground_force_*v[xyz]``) make a
GRF file, ``*_moment`` columns an ID file, OpenSim coordinates (``knee_angle_r``...) an IK file.

C3D trials (:func:`load_c3d_trial`) go through the same code:
:func:`walk3d.trials.c3d_trial.read_c3d_trial` turns the force platforms into a GRF storage in
walk3d's ground frame (plates assigned to the feet by :func:`walk3d.io.extract_foot_loads`'s
rules) and the Plug-in Gait angles into an IK storage whose knee is flexion positive (the
trial's ``knee_sign`` is +1, not detected).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from os import PathLike
from pathlib import Path

from walk3d.io.angle_units import check_storage_angles
from walk3d.io.external_loads import FootLoads, find_plates
from walk3d.io.storage import Storage, read_storage
from walk3d.trials.c3d_trial import read_c3d_trial
from walk3d.trials.descriptors import GaitDescriptors, descriptors_from_trial, foot_loads

__all__ = ["Trial", "check_overlap", "classify_storage", "load_c3d_trial", "load_trial"]


@dataclass(frozen=True)
class Trial:
    """One measured trial; ``descriptors`` needs the GRF (and IK for V and the lag).

    ``knee_sign`` is the sign of the IK knee coordinate in flexion when the source states it
    (C3D: +1); None lets :func:`walk3d.validation.reference.trial_reference` detect it.
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


def check_overlap(storage: Storage | None, grf: Storage | None, kind: str) -> None:
    """Raise ValueError (one line) when ``storage`` (the trial's ``kind`` file) and the GRF
    ``grf`` both hold samples but their times do not overlap: not the same trial, and the
    cycles cut by the plates would hold none of its samples."""
    if storage is None or grf is None or storage.time.size == 0 or grf.time.size == 0:
        return
    a, b = (
        (float(storage.time[0]), float(storage.time[-1])),
        (float(grf.time[0]), float(grf.time[-1])),
    )
    if a[1] < b[0] or b[1] < a[0]:
        name = storage.path.name if storage.path else kind
        grf_name = grf.path.name if grf.path else "GRF"
        raise ValueError(f"the {kind} file {name} ({a[0]:g}-{a[1]:g} s) and the GRF file "
                         f"{grf_name} ({b[0]:g}-{b[1]:g} s) do not overlap in time: not the "
                         "same trial")  # fmt: skip


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
        DataFileError: A file is malformed, or the IK's angles are implausible for its
            ``inDegrees`` (:mod:`walk3d.io.angle_units`).
        ValueError: the plates cannot be assigned or the events do not give a period / double
            support.
    """

    def read(x):
        return None if x is None else (x if isinstance(x, Storage) else read_storage(x))

    ik_s, grf_s, id_s = read(ik), read(grf), read(inverse_dynamics)
    if ik_s is not None:
        check_storage_angles(ik_s)  # angles in another unit than the header's
    for other, kind in ((ik_s, "IK"), (id_s, "ID")):
        check_overlap(other, grf_s, kind)
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
    """A C3D file as a trial (module doc; lab axes as in :mod:`walk3d.trials.c3d_trial`).

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
