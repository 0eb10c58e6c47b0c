"""What :func:`walk3d.results.prediction.save_prediction` may write: only arrays that
:func:`~walk3d.results.prediction.load_result` reads back (finite, NaN centres of pressure
aside; within :data:`BOUNDS`; a time axis of enough increasing samples; positive segment
masses that sum to the summary's body mass), checked before anything is written; and how
``load_result`` reads each array (:func:`read_field`)."""

from __future__ import annotations

from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np

from walk3d.io.checks import require_finite, time_samples
from walk3d.io.errors import DataFileError

__all__ = [
    "BOUNDS",
    "MASS_TOLERANCE",
    "NAME_FIELDS",
    "check_bound",
    "check_masses",
    "read_field",
    "readable_arrays",
]

NAME_FIELDS = ("segment_names", "dof_names", "joint_names")
"""The arrays of ``result.npz`` that hold names."""

BOUNDS: dict[str, tuple[float, str]] = {
    "time": (1e4, "s"),
    "segment_mass": (1e4, "kg"),
    "segment_inertia": (1e4, "kg m²"),
    "segment_com_position": (1e5, "m"),
    "segment_orientation": (1.5, ""),
    "joint_angle": (1e5, "°"),
    "joint_moment": (1e6, "N m"),
    "grf_force": (1e7, "N"),
    "grf_cop": (1e5, "m"),
    "grf_free_moment": (1e6, "N m"),
    "pelvis_position": (1e5, "m"),
}
"""Largest magnitude of each array of ``result.npz`` (its stored unit: angles in degrees),
refused beyond it as damage, not a walk. Each is orders of magnitude above any human walk
(joint moments of about 200 N m, ground reactions of about 2 kN, a cycle of about 1 s and
1.5 m, angles within ±180°, unit quaternions) yet small enough that squares and products of
them (RMSE, r, joint power) stay far from overflow: no computation then warns of one."""


MASS_TOLERANCE = 1e-3
"""Largest relative difference between the segment masses' sum and the summary's
``body_mass_kg`` (which includes what-if added masses): de Leva's female mass fractions sum to
0.9999, so a walk3d result differs by 1e-4; a damaged array by far more."""


def check_masses(path: str | PathLike[str], segment_mass: np.ndarray, summary: dict) -> None:
    """One DataFileError line for a segment mass that is not positive, or segment masses whose sum
    is not the summary's ``body_mass_kg`` (when it records one) within :data:`MASS_TOLERANCE`."""
    mass = np.asarray(segment_mass, dtype=float).reshape(-1)
    if mass.size and not (mass > 0).all():
        k = int(np.flatnonzero(~(mass > 0))[0])
        raise DataFileError(path, f"segment_mass holds {mass[k]:.6g} kg at [{k}], not a positive "
                            "mass: not a walking result")  # fmt: skip
    body = summary.get("body_mass_kg")
    if isinstance(body, (int, float)) and not isinstance(body, bool):
        total = float(mass.sum())
        if not abs(total - body) <= MASS_TOLERANCE * abs(body):
            raise DataFileError(path, f"segment_mass sums to {total:.6g} kg, but summary.json's "
                                f"body_mass_kg is {body:.6g} kg: not its body")  # fmt: skip


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
    check_bound(npz_path, name, arr)
    return np.radians(arr) if name == "joint_angle" else arr


def check_bound(path: str | PathLike[str], name: str, arr: np.ndarray) -> None:
    """One DataFileError line naming the array and its first element beyond :data:`BOUNDS`
    (NaN ignored), if any."""
    if name not in BOUNDS or arr.size == 0:
        return
    bound, unit = BOUNDS[name]
    beyond = np.abs(np.nan_to_num(arr, nan=0.0)) > bound
    if beyond.any():
        flat = int(np.flatnonzero(beyond.reshape(-1))[0])
        at = ", ".join(str(int(i)) for i in np.unravel_index(flat, arr.shape))
        raise DataFileError(path, f"{name} holds {arr.reshape(-1)[flat]:.6g} at [{at}], beyond "
                            f"±{bound:g} {unit}".rstrip() + ": not a walking result")  # fmt: skip


def readable_arrays(arrays: dict[str, np.ndarray], out_dir: str | PathLike[str],
                    summary: dict | None = None) -> dict[str, np.ndarray]:  # fmt: skip
    """``arrays`` (``result.npz``'s, as saved) when walk3d reads them back with ``summary``
    (:func:`check_masses`), else one ValueError line naming the array and its first bad element."""
    for name, arr in arrays.items():
        if arr.dtype.kind != "f":  # names and joint_axis_active: checked by their types
            continue
        try:
            if name == "time":
                time_samples("result.npz", arr)
            else:  # the centres of pressure are NaN while a foot is in the air
                require_finite("result.npz", name, arr, allow_nan=name == "grf_cop")
                check_bound("result.npz", name, arr)
        except DataFileError as exc:
            raise ValueError(f"cannot save the result to {out_dir}: {exc.reason}; walk3d could "
                             "not read it back") from None  # fmt: skip
    try:
        if "segment_mass" in arrays:
            check_masses("result.npz", arrays["segment_mass"], summary or {})
    except DataFileError as exc:
        raise ValueError(
            f"cannot save the result to {out_dir}: {exc.reason}; walk3d could not read it back"
        ) from None
    return arrays
