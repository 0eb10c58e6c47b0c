"""What :func:`walk3d.results.prediction.save_prediction` may write: only arrays that
:func:`~walk3d.results.prediction.load_result` reads back (finite, NaN centres of pressure
aside; a time axis of enough increasing samples), checked before anything is written."""

from __future__ import annotations

from os import PathLike

import numpy as np

from walk3d.io.checks import require_finite, time_samples
from walk3d.io.errors import DataFileError

__all__ = ["readable_arrays"]


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
