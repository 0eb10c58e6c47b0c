"""Criterion weights from a TOML file (``walk3d predict --criterion weights.toml``).

The file holds one number per term, at the top level or in a ``[criterion]`` table::

    [criterion]
    tor = 1.0
    accel = 0.5
    pelvis = 0.5

Term names are those of :mod:`walk3d.model.terms`; the weights are checked there.
"""

from __future__ import annotations

import math
import re
from os import PathLike
from pathlib import Path

from walk3d.io.checks import read_toml
from walk3d.io.errors import DataFileError

__all__ = ["read_criterion", "write_criterion"]


def read_criterion(path: str | PathLike[str]) -> str:
    """The weights in ``path`` as an inline criterion ``name=w,...``; DataFileError if the file
    is missing, not TOML, or holds anything but finite numbers."""
    p = Path(path)
    data = read_toml(p)
    table = data.get("criterion", data)
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


def write_criterion(path: str | PathLike[str], weights: dict[str, float], notes: list[str]) -> Path:
    """Write ``weights`` as a ``[criterion]`` table that :func:`read_criterion` reads back, with
    ``notes`` as comment lines above it; atomically."""
    from walk3d.io.atomic import atomic_write_text

    lines = [f"# {n}" for n in notes] + ["[criterion]"]
    lines += [f"{name} = {float(w)!r}" for name, w in weights.items()]
    return atomic_write_text(path, "\n".join(lines) + "\n")
