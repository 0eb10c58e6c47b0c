"""Calibration files (JSON): the fitted roll-over and transition ratios of a subject.

Layout (version 1; SI units)::

    {
      "walk3d_calibration": 1,
      "rollover": {"s": [...], "ankle_m": [[dx, y, dz], ...], "measured_s_range": [lo, hi]},
      "transition": {"mu_x": ..., "mu_z": ..., "varpi_x": ..., "varpi_y": ...},
      "subject": {...}, "descriptors": {...}, "quality": {...}, "source": {...}
    }

``s`` are the roll-over knots (``sin(θ/2)`` of the foot rotation, strictly increasing, at least
three) and ``ankle_m`` the ankle displacement at each knot (:class:`walk3d.body.rollover.
RollOver`). The last four objects are free-form records. :func:`read_calibration` checks the
layout and raises :class:`~walk3d.io.errors.DataFileError` naming the file and line.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from os import PathLike
from pathlib import Path
from typing import Any

from walk3d.io.atomic import atomic_write_text
from walk3d.io.checks import read_json_object
from walk3d.io.errors import DataFileError

__all__ = ["CALIBRATION_VERSION", "read_calibration", "write_calibration"]

CALIBRATION_VERSION = 1
_RATIOS = ("mu_x", "mu_z", "varpi_x", "varpi_y")


def _default(value: Any) -> Any:
    if hasattr(value, "tolist"):
        return value.tolist()
    if hasattr(value, "item"):
        return value.item()
    raise TypeError(f"value of type {type(value).__name__} is not JSON serialisable")


def write_calibration(path: str | PathLike[str], data: Mapping[str, Any]) -> Path:
    """Write a calibration dictionary (see the module doc) as indented JSON, atomically."""
    text = json.dumps(dict(data), indent=2, sort_keys=True, default=_default, allow_nan=False)
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    return atomic_write_text(target, text + "\n")


def _line_of(text: str, key: str) -> int | None:
    at = text.find(f'"{key}"')
    return None if at < 0 else text.count("\n", 0, at) + 1


MAX_ANKLE_M = 1.0
"""m: a bound on the ankle's displacement at a roll-over knot, well above the calibrations seen
(Falisse ``gait_1``: 0.17 m; OpenSim subject01 on a treadmill: 0.47 m)."""
RATIO_RANGES = {"mu_x": (0.0, 1.0), "mu_z": (-1.0, 1.0), "varpi_x": (-5.0, 5.0),
                "varpi_y": (-5.0, 5.0)}  # fmt: skip
"""Accepted transition ratios: the trailing foot pushes forward at heel strike (``μ_x ≥ 0``)
with a horizontal force under its vertical one; the moment ratios of measured walking are
about 0.1 (Falisse ``gait_1``: 0.14, −0.007)."""


def _number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def read_calibration(path: str | PathLike[str]) -> dict[str, Any]:
    """Read and check a calibration file; returns the parsed dictionary.

    Raises:
        FileNotFoundError: No such file.
        DataFileError: Not JSON, another version, or a missing or malformed entry.
    """
    path = Path(path)
    data = read_json_object(path, "calibration file")
    text = path.read_text(encoding="utf-8-sig")

    def fail(reason: str, key: str | None = None) -> DataFileError:
        return DataFileError(path, reason, _line_of(text, key) if key else None)

    version = data.get("walk3d_calibration")
    if version != CALIBRATION_VERSION:
        raise fail(f"not a walk3d calibration of version {CALIBRATION_VERSION} "
                   f"('walk3d_calibration' is {version!r})", "walk3d_calibration")  # fmt: skip
    ro = data.get("rollover")
    if not isinstance(ro, dict):
        raise fail("missing 'rollover' object", "rollover")
    s, ankle = ro.get("s"), ro.get("ankle_m")
    if not isinstance(s, list) or len(s) < 3 or not all(_number(v) for v in s):
        raise fail("'rollover.s' must be a list of at least 3 numbers", "s")
    if any(b <= a for a, b in zip(s[:-1], s[1:], strict=True)):
        raise fail("'rollover.s' must be strictly increasing", "s")
    if not -1 < s[0] < 0 < s[-1] < 1:
        raise fail(
            "'rollover.s' must run from below 0 to above 0 (the flat foot) within (-1, 1) "
            f"(sin of half the foot's rotation); it runs {s[0]:g} to {s[-1]:g}",
            "s",
        )
    if (not isinstance(ankle, list) or len(ankle) != len(s)
            or not all(isinstance(p, list) and len(p) == 3 and all(_number(c) for c in p)
                       for p in ankle)):  # fmt: skip
        raise fail(f"'rollover.ankle_m' must hold {len(s)} [x, y, z] number triples", "ankle_m")
    if max(abs(c) for p in ankle for c in p) > MAX_ANKLE_M:
        raise fail(f"'rollover.ankle_m' moves the ankle by more than {MAX_ANKLE_M:g} m: not a "
                   "roll-over of a foot", "ankle_m")  # fmt: skip
    tr = data.get("transition")
    if not isinstance(tr, dict):
        raise fail("missing 'transition' object", "transition")
    for key in _RATIOS:
        if not _number(tr.get(key)):
            raise fail(f"'transition.{key}' must be a finite number", key if key in tr else
                       "transition")  # fmt: skip
        lo, hi = RATIO_RANGES[key]
        if not lo <= tr[key] <= hi:
            raise fail(f"'transition.{key}' must be in [{lo:g}, {hi:g}], got {tr[key]:g}", key)
    return data
