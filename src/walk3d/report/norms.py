"""Normative bands for the report's figures, from the measured walking data in ``shared/data``.

Sources, in order of priority (docs/report.md; the folder layout is that of
``../shared/data/README.md``):

* ``falisse2019/cycle_right_leg_mean_sd.csv``: Falisse et al. (2019), one adult, mean ± SD
  over 11 overground trials at about 1.3 m/s, whole body (no neck);
* ``winter/Winter_normal.csv``: Winter's normal-cadence adult averages (1.325 m/s), sagittal
  legs and GRF, means only.

A quantity's band is mean ± SD of the first source with an SD for it; without any SD it is the
min–max of the sources' means (with two or more), else just the one mean. Every other source's
mean is kept as a further line. Both tables are per kg, so the subject's mass plays no part.
Columns are mapped by :func:`walk3d.validation.reference.reference_from_table`.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path

import numpy as np

from walk3d.io.cycle_table import read_cycle_table
from walk3d.io.errors import DataFileError
from walk3d.validation.reference import Reference, reference_from_table

__all__ = ["DATA_ENV", "SOURCES", "Band", "Norms", "data_candidates", "find_data", "load_norms"]

DATA_ENV = "WALK3D_SHARED_DATA"
"""Environment variable naming the measured-data folder (as the benchmarks use it)."""

SOURCES = (
    ("falisse2019/cycle_right_leg_mean_sd.csv",
     "Falisse et al. 2019, mean ± SD of 11 overground trials, one adult, about 1.3 m/s"),
    ("winter/Winter_normal.csv", "Winter, normal-cadence adult averages, 1.325 m/s"),
)  # fmt: skip
"""(path under the data folder, description), in order of priority."""


@dataclass(frozen=True)
class Band:
    """The normative curves of one quantity (101 samples, display units)."""

    low: np.ndarray
    high: np.ndarray
    mean: np.ndarray | None
    kind: str
    """``mean ± SD (<source>)``, ``min–max of N means`` or ``mean (<source>)``."""
    others: tuple[tuple[str, np.ndarray], ...] = ()


@dataclass(frozen=True)
class Norms:
    """Bands by quantity key (:data:`walk3d.validation.quantities.QUANTITIES`)."""

    folder: Path | None
    bands: dict[str, Band]
    sources: tuple[str, ...]
    """Descriptions of the sources read."""
    notes: tuple[str, ...] = field(default_factory=tuple)

    def has(self, key: str) -> bool:
        return key in self.bands


def data_candidates(explicit: str | PathLike[str] | None = None) -> list[Path]:
    """Folders to look in: ``explicit``, else ``$WALK3D_SHARED_DATA`` alone when set, else
    ``../shared/data`` beside the source checkout, then beside the working folder."""
    if explicit is not None:
        return [Path(explicit)]
    if os.environ.get(DATA_ENV):
        return [Path(os.environ[DATA_ENV])]
    root = Path(__file__).resolve().parents[3]  # src/walk3d/report/norms.py -> project root
    return [root.parent / "shared" / "data", Path.cwd().parent / "shared" / "data"]


def find_data(explicit: str | PathLike[str] | None = None) -> Path | None:
    """The first candidate folder holding at least one of :data:`SOURCES`, or None."""
    for folder in data_candidates(explicit):
        if any((folder / rel).is_file() for rel, _ in SOURCES):
            return folder
    return None


def _short(description: str) -> str:
    return description.split(",")[0]


def _band(key: str, refs: list[tuple[str, Reference]]) -> Band | None:
    have = [(d, r) for d, r in refs if r.has(key)]
    if not have:
        return None
    with_sd = [(d, r) for d, r in have if np.isfinite(r.sd[key]).any()]
    if with_sd:
        d, r = with_sd[0]
        m, s = r.mean[key], np.nan_to_num(r.sd[key])
        others = tuple((_short(o), q.mean[key]) for o, q in have if q is not r)
        return Band(m - s, m + s, m, f"mean ± SD ({_short(d)})", others)
    means = np.array([r.mean[key] for _, r in have])
    if len(have) == 1:
        return Band(means[0], means[0], means[0], f"mean ({_short(have[0][0])})")
    return Band(means.min(axis=0), means.max(axis=0), None, f"min–max of {len(have)} means")


def load_norms(folder: str | PathLike[str] | None, strict: bool = False) -> Norms:
    """Read the sources present in ``folder`` (module doc). An unreadable one (malformed, NaN
    or infinite values, no gait cycle) is skipped with a note, so that a report never fails on
    data it found by itself; with ``strict`` (a folder the user named) it raises ValueError."""
    if folder is None:
        return Norms(None, {}, (), ("no measured data folder found",))
    root = Path(folder)
    refs, notes = [], []
    for rel, description in SOURCES:
        path = root / rel
        if not path.is_file():
            continue
        try:
            ref = reference_from_table(read_cycle_table(path), name=description)
            if not ref.mean:
                raise DataFileError(path, "no column of a quantity the report shows")
        except (OSError, DataFileError, ValueError, KeyError) as exc:
            if strict and isinstance(exc, DataFileError):
                raise
            if strict:
                raise DataFileError(path, str(exc)) from None
            notes.append(f"{rel} skipped: {' '.join(str(exc).split())}")
            continue
        refs.append((description, ref))
    keys = {k for _, r in refs for k in r.mean}
    bands = {k: b for k in sorted(keys) if (b := _band(k, refs)) is not None}
    return Norms(root, bands, tuple(d for d, _ in refs), tuple(notes))
