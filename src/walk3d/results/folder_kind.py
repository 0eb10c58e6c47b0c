"""Folders that hold predictions but are none: a ``walk3d sweep`` or ``walk3d campaign``
folder given where a prediction folder is expected gets a line saying which to give."""

from __future__ import annotations

from pathlib import Path

from walk3d.io.errors import DataFileError

__all__ = ["FOLDER_MARKERS", "INNER_FOLDERS", "not_a_prediction"]

FOLDER_MARKERS = {
    "sweep.json": ("a sweep folder", "one of its speed folders (speeds/v_*)"),
    "campaign.json": ("a campaign folder", "its best/ or one of its starts/seed_* folders"),
}
"""The file that marks a sweep's and a campaign's folder: what the folder is, and what to
give instead."""

INNER_FOLDERS = {
    "starts": ("campaign.json", "a campaign's starts folder", "seed_*"),
    "speeds": ("sweep.json", "a sweep's speeds folder", "v_*"),
}
"""The folders of a campaign (:mod:`walk3d.campaign.store`) and of a sweep
(:mod:`walk3d.campaign.sweep_folder`) that hold its predictions: the marker of its parent, what
the folder is, and the pattern of the prediction folders inside it."""


def not_a_prediction(out: Path) -> None:
    """Raise :class:`DataFileError` when ``out`` (a folder without a manifest) is a sweep's or a
    campaign's folder (:data:`FOLDER_MARKERS`) or the folder of its predictions
    (:data:`INNER_FOLDERS`), saying which prediction folders it holds."""
    for marker, (what, instead) in FOLDER_MARKERS.items():
        if (out / marker).is_file():
            raise DataFileError(out, f"is {what}, not a prediction: give {instead}")
    inner = INNER_FOLDERS.get(out.name)
    if inner is not None and (out.parent / inner[0]).is_file():
        found = sorted(out.glob(inner[2]))
        example = f" (e.g. {found[0]})" if found else ""
        raise DataFileError(
            out, f"is {inner[1]}, not a prediction: give one of its {inner[2]} folders{example}"
        )
