"""Measured joint angles against their stated unit: a file whose angles cannot be walking in
that unit is refused (one DataFileError line) instead of being scored as if they were.

Two mislabellings are caught, with bounds that no real walking trial comes near:

* degrees read as radians (``inDegrees=no`` over degrees, degrees in a ``_rad`` column): a
  knee at 60 becomes 3438°. No joint coordinate exceeds ±180°, and a pelvis heading stays
  within a turn in a walking trial, so any angle beyond :data:`MAX_ANGLE_DEG` is refused;
* radians read as degrees (``inDegrees=yes`` over radians, radians in a ``_deg`` column): the
  knee's 60° range becomes 1.05 "degrees". In walking the knee flexes through 50-70°, the hip
  through 35-45° and the ankle through 25-35° (Winter's and Falisse's data; a stiff-knee gait
  keeps a hip range above 20°), while in radians none of them spans even 1.5, so a file whose
  every sagittal hip, knee and ankle angle spans less than :data:`MIN_SAGITTAL_RANGE_DEG` is
  refused. A file without those angles is not checked for range.
"""

from __future__ import annotations

from collections.abc import Mapping
from os import PathLike

import numpy as np

from walk3d.io.errors import DataFileError
from walk3d.io.storage import Storage

__all__ = ["MAX_ANGLE_DEG", "MIN_SAGITTAL_RANGE_DEG", "SAGITTAL", "check_angles",
           "check_storage_angles"]  # fmt: skip

MAX_ANGLE_DEG = 360.0
"""Largest magnitude of a measured angle, deg (module doc)."""
MIN_SAGITTAL_RANGE_DEG = 3.0
"""Smallest range, deg, that the widest sagittal hip, knee or ankle angle of a walking file
spans (module doc)."""
SAGITTAL = ("hip_flexion", "knee_angle", "ankle_angle")
"""Name prefixes of the sagittal leg angles the range check reads."""
TRANSLATIONS = ("_tx", "_ty", "_tz")


def check_angles(
    path: str | PathLike[str] | None, degrees: Mapping[str, np.ndarray], stated: str
) -> None:
    """Raise :class:`DataFileError` (one line naming ``path``) unless the angles ``degrees``
    (column name: values converted to degrees as their stated unit says) are plausible for
    walking (module doc). ``stated`` says what the unit was read from, e.g. ``inDegrees=no``."""
    where = path if path is not None else "angles"
    peaks = {name: float(np.nanmax(np.abs(v))) for name, v in degrees.items()
             if np.isfinite(v).any()}  # fmt: skip
    if peaks and max(peaks.values()) > MAX_ANGLE_DEG:
        name = max(peaks, key=peaks.__getitem__)
        raise DataFileError(where, f"{name} reaches {peaks[name]:.0f}° read as {stated}, "
                            f"beyond ±{MAX_ANGLE_DEG:g}° for any joint angle: are the angles "
                            "in another unit than stated?")  # fmt: skip
    ranges = {name: float(np.nanmax(v) - np.nanmin(v)) for name, v in degrees.items()
              if name.startswith(SAGITTAL) and np.isfinite(v).any()}  # fmt: skip
    if ranges and max(ranges.values()) < MIN_SAGITTAL_RANGE_DEG:
        name = max(ranges, key=ranges.__getitem__)
        raise DataFileError(where, f"every hip, knee and ankle flexion spans less than "
                            f"{MIN_SAGITTAL_RANGE_DEG:g}° read as {stated} (the widest, {name}, "
                            f"{ranges[name]:.3g}°), which no walking does: are the angles in "
                            "radians?")  # fmt: skip


def check_storage_angles(storage: Storage) -> None:
    """:func:`check_angles` for an IK storage's coordinates (every column but the
    translations), read in degrees unless its header says ``inDegrees=no``."""
    scale = np.degrees(1.0) if storage.in_degrees is False else 1.0
    stated = {True: "inDegrees=yes", False: "inDegrees=no"}
    unit = stated.get(storage.in_degrees, "degrees (no inDegrees)")
    degrees = {c: scale * storage.data[:, k] for k, c in enumerate(storage.columns)
               if not c.endswith(TRANSLATIONS)}  # fmt: skip
    check_angles(storage.path, degrees, unit)
