"""A ``walk3d sweep`` folder on resume: ``sweep.json`` and the finished speeds are checked
before any solve (:mod:`walk3d.campaign.sweep` has the layout).

* ``sweep.json`` that cannot be read, is not a sweep's, or holds other settings: refused
  (:class:`SweepMismatch`, one line and exit code 2 in the CLI);
* a speed folder that is damaged (incomplete, or a summary that cannot be read) or whose
  arrays are not tied to its summary (:func:`check_arrays`): solved again, with a warning.
  walk3d writes each speed atomically, so such a folder holds no usable work;
* a speed folder holding a readable prediction of another problem (another speed, subject or
  criterion...): refused, not replaced, since it may be someone's result put there by mistake;
* a speed path walk3d could not write its result to (a file, a folder of other files, a
  ``speeds`` that is a file): refused, so that no solve is run whose result would be lost.
"""

from __future__ import annotations

import json
import math
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np

from walk3d.io.atomic import atomic_write_text
from walk3d.io.checks import read_json_object, read_npz, time_samples
from walk3d.io.errors import DataFileError
from walk3d.problem.settings import ModelSettings, PredictionSettings, recorded_settings

__all__ = ["PROBLEM_FIELDS", "SweepMismatch", "check_arrays", "check_folder", "difference",
           "speed_folder", "stored"]  # fmt: skip


class SweepMismatch(ValueError):
    """The folder holds a sweep with other settings, a ``sweep.json`` that is not a sweep's,
    or a speed folder with another problem's prediction."""


def speed_folder(out: Path, speed: float) -> Path:
    """The folder of one speed (m/s), named to 0.001 m/s."""
    return out / "speeds" / f"v_{speed:.3f}"


def _sweep_key(settings: dict) -> dict:
    """``sweep.json``'s settings less ``solver.threads``, which does not change the iterates:
    a sweep resumes on a computer with another number of cores."""
    return {g: {k: v for k, v in (values.items() if isinstance(values, dict) else ())
                if (g, k) != ("solver", "threads")} for g, values in settings.items()}  # fmt: skip


def _with_defaults(stored_: dict, key: dict) -> dict:
    """``sweep.json``'s settings with each setting it lacks (one added to walk3d since it was
    written) at its default: a sweep resumes across such a walk3d update when the new setting
    keeps its default."""
    defaults = PredictionSettings().model_dump(mode="json")
    return {g: ({**{k: v for k, v in defaults.get(g, {}).items() if k in key.get(g, {})},
                 **values} if isinstance(values, dict) else values)
            for g, values in stored_.items()}  # fmt: skip


def check_folder(out: Path, settings: PredictionSettings) -> None:
    """Write ``sweep.json``, or refuse (:class:`SweepMismatch`) a folder whose ``sweep.json``
    cannot be read, is not a sweep's or holds other settings."""
    key = settings.model_dump(mode="json")
    for name in ("speed", "period", "double_support"):  # per speed (T, Td: first guesses)
        key["gait"].pop(name)
    path = out / "sweep.json"
    if path.is_file():
        try:  # one line for any damage, nesting too deep included
            stored_ = read_json_object(path, "walk3d sweep file")
        except (OSError, DataFileError) as exc:
            why = getattr(exc, "reason", None) or " ".join(str(exc).split())
            raise SweepMismatch(f"{path} cannot be read ({why}); use a new folder") from None
        if not isinstance(stored_.get("settings"), dict):
            raise SweepMismatch(f"{path} is not a walk3d sweep file; use a new folder")
        if _sweep_key(_with_defaults(stored_["settings"], key)) != _sweep_key(key):
            raise SweepMismatch(f"{out} holds a sweep with other settings; use a new folder "
                                "or the same options")  # fmt: skip
        return
    out.mkdir(parents=True, exist_ok=True)
    atomic_write_text(path, json.dumps({"settings": key}, indent=1) + "\n")


PROBLEM_FIELDS = (("gait", "sex"), ("gait", "mass"), ("gait", "height"), ("gait", "free"),
                  ("solver", "nodes"), ("solver", "heel_strike_nodes"),
                  ("solver", "contact_checks"), ("solver", "swing_checks"),
                  *(("model", name) for name in ModelSettings.model_fields))  # fmt: skip
"""``(group, setting)`` that, with the speed, define the problem a stored speed must have
solved to be resumed: the subject, the free descriptors, the grid and every model setting."""


def difference(summary: dict, settings: PredictionSettings, speed: float) -> str | None:
    """How a stored prediction's problem differs from the sweep's at ``speed`` (m/s), or None:
    its descriptors' speed and its settings' must both be ``speed``. Its handover may have
    fallen back to the free landing (:mod:`walk3d.solve.landing`). Raises ValueError for a speed
    that is not a finite number (a damaged summary)."""
    recorded = PredictionSettings(**recorded_settings(summary))
    got = summary["descriptors"]["speed"]
    if isinstance(got, bool) or not isinstance(got, (int, float)) or not math.isfinite(got):
        raise ValueError(f"its speed {got!r} is not a finite number")  # damaged: solved again
    for value in (got, recorded.gait.speed):  # the table's speed and the solved problem's
        if abs(value - speed) > 5e-7:
            return f"is at {value:g} m/s, not {speed:g} m/s"
    for group, name in PROBLEM_FIELDS:
        a = getattr(getattr(recorded, group), name)
        b = getattr(getattr(settings, group), name)
        if a != b and not (name == "handover" and b and not a):
            return f"was solved with {name} {a!r}, not {b!r}"
    return None


def check_arrays(folder: Path, summary: dict) -> None:
    """Raise ValueError unless ``folder``'s ``result.npz`` is its summary's: its manifest holds
    the arrays' digest (:func:`~walk3d.results.prediction.check_complete` checks it; folders
    written before digests have none), and their time runs from 0 to the summary's period, so
    that arrays swapped between speeds are caught even under a rewritten digest."""
    from walk3d.results.prediction import MANIFEST

    digests = read_json_object(folder / MANIFEST, "walk3d manifest").get("sha256")
    if not isinstance(digests, dict) or not isinstance(digests.get("result.npz"), str):
        raise ValueError("its manifest holds no digest of result.npz (a walk3d before digests "
                         "wrote it), so its arrays cannot be tied to its summary")  # fmt: skip
    period = summary["descriptors"]["period"]
    if isinstance(period, bool) or not isinstance(period, (int, float)):
        raise ValueError(f"its period {period!r:.40} is not a number")
    path = folder / "result.npz"
    time = time_samples(path, read_npz(path, "walk3d result").get("time", np.zeros(0)))
    if time[0] != 0 or not abs(time[-1] - period) <= 1e-9 * period:
        raise ValueError(f"its result.npz is not its summary's: the arrays' cycle runs "
                         f"{time[0]:g} to {time[-1]:.6g} s, the summary's period is "
                         f"{period:.6g} s")  # fmt: skip


def stored(
    out: Path, settings: PredictionSettings, speeds: np.ndarray, usable: Callable[[dict], object]
) -> dict[int, dict]:
    """The summaries of the speeds an earlier run finished, by index into ``speeds`` (module
    doc: damaged ones are left out with a warning, another problem's raise
    :class:`SweepMismatch`). ``usable(summary)`` raises KeyError, ValueError or TypeError for
    a summary the sweep cannot tabulate."""
    from walk3d.results.prediction import check_complete, check_result_folder

    for v in map(float, speeds):  # every path first: a refusal comes before any solve
        try:
            check_result_folder(speed_folder(out, v), "speed folder")
        except ValueError as exc:
            raise SweepMismatch(f"cannot write that speed's result: {exc}") from None
    found: dict[int, dict] = {}
    for i, v in enumerate(map(float, speeds)):
        folder = speed_folder(out, v)
        if not folder.exists():
            continue
        try:
            check_complete(folder)
            summary = read_json_object(folder / "summary.json", "walk3d summary")
            usable(summary)
            [float(x) for x in summary["coefficients"]["x"]]  # a warm start's coefficients
            why = difference(summary, settings, v)
            if why is None:  # another problem's prediction is refused, not solved over
                check_arrays(folder, summary)
        except (OSError, ValueError, KeyError, TypeError, AttributeError) as exc:
            warnings.warn(f"{folder} cannot be read ({' '.join(str(exc).split())}): solving "
                          f"{v:g} m/s again", RuntimeWarning, stacklevel=2)  # fmt: skip
            continue
        if why is not None:
            raise SweepMismatch(f"{folder} holds a prediction that {why}; remove that folder "
                                f"to solve {v:g} m/s again, or use a new folder")  # fmt: skip
        found[i] = summary
    return found
