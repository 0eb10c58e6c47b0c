"""What :func:`walk3d.results.prediction.save_prediction` may write: only arrays that
:func:`~walk3d.results.prediction.load_result` reads back (finite, NaN centres of pressure
aside; a time axis of enough increasing samples), checked before anything is written."""

from __future__ import annotations

from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np

from walk3d.io.checks import require_finite, time_samples
from walk3d.io.errors import DataFileError

__all__ = ["NAME_FIELDS", "read_field", "readable_arrays"]

NAME_FIELDS = ("segment_names", "dof_names", "joint_names")
"""The arrays of ``result.npz`` that hold names."""


def read_field(npz_path: Path, name: str, arr: np.ndarray | None) -> Any:
    """The value of :class:`~walk3d.results.prediction.PredictedCycle`'s field ``name`` from
    its ``result.npz`` array ``arr`` (joint angles back to radians), or one DataFileError line
    for a missing or unreadable array."""
    if arr is None:
        raise DataFileError(npz_path, f"not a walk3d result: no array {name!r}")
    if name in NAME_FIELDS:
        if arr.ndim != 1 or arr.dtype.kind != "U":
            raise DataFileError(npz_path, f"{name} is not a list of names")
        return tuple(arr.tolist())
    if name == "joint_axis_active":
        if arr.dtype.kind != "b":
            raise DataFileError(npz_path, f"{name} is not an array of booleans")
        return arr
    if name == "time":
        return time_samples(npz_path, arr)
    # the centres of pressure are NaN while a foot is in the air
    arr = require_finite(npz_path, name, arr, allow_nan=name == "grf_cop")
    return np.radians(arr) if name == "joint_angle" else arr


def readable_arrays(arrays: dict[str, np.ndarray],
                    out_dir: str | PathLike[str]) -> dict[str, np.ndarray]:  # fmt: skip
    """``arrays`` (``result.npz``'s, as saved) when walk3d reads them back, else one
    ValueError line naming the array and its first bad element."""
    for name, arr in arrays.items():
        if arr.dtype.kind != "f":  # names and joint_axis_active: checked by their types
            continue
        try:
            if name == "time":
                time_samples("result.npz", arr)
            else:  # the centres of pressure are NaN while a foot is in the air
                require_finite("result.npz", name, arr, allow_nan=name == "grf_cop")
        except DataFileError as exc:
            raise ValueError(f"cannot save the result to {out_dir}: {exc.reason}; walk3d could "
                             "not read it back") from None  # fmt: skip
    return arrays
