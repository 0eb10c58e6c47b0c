"""Writing a finished page: atomically, and listed in the manifest of the prediction folder
it lands in (:func:`walk3d.results.views.write_view`)."""

from __future__ import annotations

from pathlib import Path

from walk3d.io.atomic import atomic_write_text
from walk3d.outputs import write_errors
from walk3d.report.prediction_page import REPORT
from walk3d.results.prediction import VIEW_FILES, record_file
from walk3d.results.views import write_view

__all__ = ["remade_views", "save_report"]


def remade_views(folder: str | Path, out: Path | None) -> tuple[str, ...]:
    """The view of the prediction ``folder`` that a page written to ``out`` (default
    ``folder/report.html``) makes again, so that it may be missing when the folder is read."""
    root = Path(folder)
    target = out if out is not None else root / REPORT
    inside = target.resolve().parent == root.resolve() and target.name in VIEW_FILES
    return (target.name,) if inside else ()


def save_report(folder: str | Path, kind: str, page: str, out: Path | None) -> Path:
    """Write ``page`` atomically to ``out`` (default ``folder/report.html``), listed in the
    manifest when it lands in a prediction folder, its folder made if missing; returns its
    path (OutputWriteError naming it when it cannot be written)."""
    root = Path(folder)
    target = out if out is not None else root / REPORT
    inside = kind == "prediction" and target.resolve().parent == root.resolve()
    if inside and target.name in VIEW_FILES:  # the page and its manifest entry together
        return write_view(root, target.name, lambda path: atomic_write_text(path, page))
    with write_errors(target):  # one line naming the page, not a temporary or an errno alone
        target.parent.mkdir(parents=True, exist_ok=True)  # as walk3d animate --out does
        atomic_write_text(target, page)
    if inside:
        record_file(root, target.name)
    return target
