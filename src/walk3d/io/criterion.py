"""Criterion weights from a TOML file (``walk3d predict --criterion weights.toml``).

The file holds one number per term, at the top level or in a ``[criterion]`` table::

    [criterion]
    tor = 1.0
    accel = 0.5
    pelvis = 0.5

Term names are those of :mod:`walk3d.model.terms`; the weights are checked there. A
``[model]`` table may add the model options a fit chose (:data:`MODEL_OPTIONS`, ``walk3d
fit-criterion``), which every prediction with the file takes::

    [model]
    heel_rise = 0.62
"""

from __future__ import annotations

import math
import re
from os import PathLike
from pathlib import Path

from walk3d.io.checks import read_toml
from walk3d.io.errors import DataFileError

__all__ = [
    "MODEL_OPTIONS",
    "read_criterion",
    "read_model_options",
    "with_file_options",
    "write_criterion",
]

MODEL_OPTIONS = ("heel_rise", "load_ramp")
"""Model settings a criterion file may hold (``[model]``): the continuous stance options a fit
can choose (:mod:`walk3d.model.settings` checks their ranges)."""


def read_criterion(path: str | PathLike[str]) -> str:
    """The weights in ``path`` as an inline criterion ``name=w,...``; DataFileError if the file
    is missing, not TOML, or holds anything but finite numbers."""
    p = Path(path)
    data = read_toml(p)
    table = data.get("criterion", {k: v for k, v in data.items() if k != "model"})
    if not isinstance(table, dict) or not table:
        raise DataFileError(p, "no criterion weights (expected e.g. 'tor = 1' lines)")
    parts = []
    for name, value in table.items():
        if not re.fullmatch(r"[a-z][a-z0-9_]*", name):  # pasted into name=w,...: a term name
            raise DataFileError(p, f"{name!r:.40} is not a criterion term name")
        ok = isinstance(value, int | float) and not isinstance(value, bool)
        if not ok or abs(value) > 1e300 or not math.isfinite(value):
            raise DataFileError(p, f"the weight of {name} must be a finite number, "
                                   f"got {value!r:.40}")  # fmt: skip
        parts.append(f"{name}={float(value):.17g}")
    return ",".join(parts)


def read_model_options(path: str | PathLike[str]) -> dict[str, float]:
    """The ``[model]`` table of a criterion file (empty without one); DataFileError for a name
    not in :data:`MODEL_OPTIONS` or a value that is not a finite number."""
    p = Path(path)
    table = read_toml(p).get("model", {})
    if not isinstance(table, dict):
        raise DataFileError(p, "[model] must be a table of model options")
    for name, value in table.items():
        if name not in MODEL_OPTIONS:
            raise DataFileError(p, f"[model] {name!r:.40} is not a model option a criterion "
                                   f"file sets ({', '.join(MODEL_OPTIONS)})")  # fmt: skip
        ok = isinstance(value, int | float) and not isinstance(value, bool)
        if not ok or not math.isfinite(value):
            raise DataFileError(p, f"[model] {name} must be a finite number, got {value!r:.40}")
    return {name: float(value) for name, value in table.items()}


def with_file_options(criterion: str, options: dict) -> dict:
    """``options`` (settings fields) with the ``[model]`` options of the criterion file
    ``criterion`` (when it names a ``.toml`` file); ValueError (one line) when an option is
    also given with another value, DataFileError for a bad table."""
    if not (isinstance(criterion, str) and criterion.lower().endswith(".toml")):
        return options
    out = dict(options)
    for name, value in read_model_options(criterion).items():
        if out.get(name) is not None and out[name] != value:
            raise ValueError(f"{name} is {out[name]!r:.40} here and {value:g} in {criterion}'s "
                             "[model] table: give it once")  # fmt: skip
        out[name] = value
    return out


def write_criterion(
    path: str | PathLike[str],
    weights: dict[str, float],
    notes: list[str],
    model: dict[str, float] | None = None,
) -> Path:
    """Write ``weights`` as a ``[criterion]`` table (and ``model`` options as a ``[model]``
    table) that :func:`read_criterion` and :func:`read_model_options` read back, with ``notes``
    as comment lines above; atomically."""
    from walk3d.io.atomic import atomic_write_text

    lines = [f"# {n}" for n in notes] + ["[criterion]"]
    lines += [f"{name} = {float(w)!r}" for name, w in weights.items()]
    if model:
        lines += ["", "[model]"] + [f"{name} = {float(v)!r}" for name, v in model.items()]
    return atomic_write_text(path, "\n".join(lines) + "\n")
