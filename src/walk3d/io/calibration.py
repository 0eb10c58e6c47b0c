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
from collections.abc import Mapping
from os import PathLike
from pathlib import Path
from typing import Any

from walk3d.io.atomic import atomic_write_text
from walk3d.io.checks import read_input, read_json_object
from walk3d.io.errors import DataFileError
from walk3d.model.calibrated import RATIO_NAMES, ratio_problem, rollover_problem

__all__ = ["CALIBRATION_VERSION", "read_calibration", "write_calibration"]

CALIBRATION_VERSION = 1


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


def read_calibration(path: str | PathLike[str]) -> dict[str, Any]:
    """Read and check a calibration file; returns the parsed dictionary.

    Raises:
        FileNotFoundError: No such file.
        DataFileError: Not JSON, another version, or a missing or malformed entry.
    """
    path = Path(path)
    data = read_json_object(path, "calibration file")
    text = read_input(path).decode("utf-8-sig")

    def fail(reason: str, key: str | None = None) -> DataFileError:
        return DataFileError(path, reason, _line_of(text, key) if key else None)

    version = data.get("walk3d_calibration")
    if version != CALIBRATION_VERSION:
        raise fail(f"not a walk3d calibration of version {CALIBRATION_VERSION} "
                   f"('walk3d_calibration' is {version!r})", "walk3d_calibration")  # fmt: skip
    ro = data.get("rollover")
    if not isinstance(ro, dict):
        raise fail("missing 'rollover' object", "rollover")
    found = rollover_problem(ro.get("s"), ro.get("ankle_m"))
    if found:
        raise fail(*found)
    tr = data.get("transition")
    if not isinstance(tr, dict):
        raise fail("missing 'transition' object", "transition")
    for key in RATIO_NAMES:
        found = ratio_problem(key, tr.get(key))
        if found:
            raise fail(found[0], key if key in tr else "transition")
    return data
