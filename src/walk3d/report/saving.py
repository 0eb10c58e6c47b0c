"""Writing a finished page: atomically, and listed in the manifest of the prediction folder
it lands in (:func:`walk3d.results.prediction.record_file`)."""

from __future__ import annotations

from pathlib import Path

from walk3d.io._atomic import atomic_write_text
from walk3d.report.prediction_page import REPORT
from walk3d.results.prediction import record_file

__all__ = ["save_report"]


def save_report(folder: str | Path, kind: str, page: str, out: Path | None) -> Path:
    """Write ``page`` atomically to ``out`` (default ``folder/report.html``), listed in the
    manifest when it lands in a prediction folder; returns its path."""
    root = Path(folder)
    target = out if out is not None else root / REPORT
    atomic_write_text(target, page)
    if kind == "prediction" and target.resolve().parent == root.resolve():
        record_file(root, target.name)
    return target
