"""Folders that hold predictions but are none: a ``walk3d sweep`` or ``walk3d campaign``
folder given where a prediction folder is expected gets a line saying which to give."""

from __future__ import annotations

from pathlib import Path

from walk3d.io.errors import DataFileError

__all__ = ["FOLDER_MARKERS", "not_a_prediction"]

FOLDER_MARKERS = {
    "sweep.json": ("a sweep folder", "one of its speed folders (speeds/v_*)"),
    "campaign.json": ("a campaign folder", "its best/ or one of its starts/seed_* folders"),
}
"""The file that marks a sweep's and a campaign's folder: what the folder is, and what to
give instead."""


def not_a_prediction(out: Path) -> None:
    """Raise :class:`DataFileError` when ``out`` (a folder without a manifest) is a sweep's or a
    campaign's folder (:data:`FOLDER_MARKERS`), saying which prediction folders it holds."""
    for marker, (what, instead) in FOLDER_MARKERS.items():
        if (out / marker).is_file():
            raise DataFileError(out, f"is {what}, not a prediction: give {instead}")
