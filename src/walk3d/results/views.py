"""Making a view of a result folder again (``summary.png``, ``animation.mp4``,
``report.html``): the view and the manifest that lists it are built aside, then replace the
old ones, the manifest last (:func:`walk3d.outputs.replace_files`)."""

from __future__ import annotations

import json
from collections.abc import Callable
from os import PathLike
from pathlib import Path

from walk3d.io.atomic import atomic_write_text
from walk3d.outputs import replace_files, write_errors
from walk3d.results.prediction import MANIFEST, VIEW_FILES

__all__ = ["is_listed_view", "write_view"]


def is_listed_view(path: str | PathLike[str]) -> bool:
    """Whether ``path`` is a view (:data:`VIEW_FILES`) that the manifest of the result folder
    holding it lists: one walk3d wrote, whatever version wrote it."""
    from walk3d.io.checks import read_json_object

    file = Path(path)
    if file.name not in VIEW_FILES or not file.is_file():
        return False
    try:
        listed = read_json_object(file.parent / MANIFEST, "walk3d manifest").get("files")
    except (OSError, ValueError):
        return False
    return isinstance(listed, dict) and file.name in listed


def write_view(folder: str | PathLike[str], name: str, write: Callable[[Path], object]) -> Path:
    """Call ``write(path)`` to make the view ``name`` of the result ``folder`` aside, then put
    it and the manifest listing its size in place; returns the view's path.

    Raises:
        ValueError: ``name`` is not a view (:data:`VIEW_FILES`).
        OutputWriteError: it could not be written; the folder is left as it was.
    """
    if name not in VIEW_FILES:
        raise ValueError(f"{name} is not a view of a result folder ({', '.join(VIEW_FILES)})")
    out = Path(folder)
    with write_errors(out / name), replace_files(out, last=MANIFEST) as tmp:
        write(tmp / name)
        manifest = json.loads((out / MANIFEST).read_text(encoding="utf-8"))
        manifest["files"][name] = (tmp / name).stat().st_size
        atomic_write_text(tmp / MANIFEST, json.dumps(manifest, indent=2, sort_keys=True) + "\n")
    return out / name
