"""``walk3d report DIR``: tell a prediction folder from a campaign folder and write its page.

A prediction folder has ``summary.json`` (its ``manifest.json`` is checked when it is read);
a campaign folder has ``campaign.json`` (and no ``summary.json``: its starts are sub-folders).
A page written into a prediction folder is listed in its manifest
(:func:`walk3d.results.prediction.record_file`); :func:`write_report_or_warn` adds it to a
folder just predicted. :mod:`walk3d.campaign` (and Dask with it) is imported only for a
campaign folder, which keeps a prediction's report quick to start.
"""

from __future__ import annotations

import warnings
from os import PathLike
from pathlib import Path

from walk3d.report.norms import Norms, find_data, load_norms
from walk3d.report.prediction_page import prediction_page
from walk3d.report.saving import remade_views, save_report
from walk3d.results.prediction import load_result

__all__ = ["ReportWarning", "build_report", "folder_kind", "save_report", "write_report",
           "write_report_or_warn"]  # fmt: skip


def folder_kind(folder: str | PathLike[str]) -> str | None:
    """``"campaign"``, ``"prediction"`` or None (neither)."""
    root = Path(folder)
    if (root / "summary.json").is_file():
        return "prediction"
    from walk3d.campaign.store import CAMPAIGN_FILE

    return "campaign" if (root / CAMPAIGN_FILE).is_file() else None


def build_report(
    folder: str | PathLike[str], norms: Norms, out: Path | None = None
) -> tuple[str, str]:
    """``(kind, page)`` of ``folder``, read but not written; ``out`` is where the page goes
    (default ``folder/report.html``, which may then be missing: it is made again).

    Raises:
        ValueError: ``folder`` is neither kind, or a file in it is malformed (DataFileError).
        OSError: a file cannot be read.
    """
    root = Path(folder)
    kind = folder_kind(root)
    if kind is None:
        raise ValueError(f"{root} is neither a prediction folder (summary.json, written by "
                         "walk3d predict) nor a campaign folder (campaign.json)")  # fmt: skip
    try:
        if kind == "campaign":
            from walk3d.report.campaign_page import campaign_page

            return kind, campaign_page(root, norms)
        pred = load_result(root, remade=remade_views(root, out))
        return kind, prediction_page(pred, root, norms)
    except (KeyError, TypeError, AttributeError, IndexError, StopIteration) as exc:
        raise ValueError(f"{root}: a file has unexpected content ({type(exc).__name__}: "
                         f"{' '.join(str(exc).split())})") from None  # fmt: skip


def write_report(
    folder: str | PathLike[str],
    out: str | PathLike[str] | None = None,
    data: str | PathLike[str] | None = None,
) -> tuple[str, Path]:
    """Build and save the page of ``folder`` (see :func:`build_report`, :func:`save_report`);
    ``data`` is the measured-data folder (default: :func:`walk3d.report.norms.find_data`).
    Returns ``(kind, path)``."""
    target = None if out is None else Path(out)
    kind, page = build_report(folder, load_norms(find_data(data)), target)
    return kind, save_report(folder, kind, page, target)


class ReportWarning(UserWarning):
    """``report.html`` could not be made; the result folder it was for is complete."""


def write_report_or_warn(folder: str | Path) -> Path | None:
    """Write ``folder/report.html`` (:mod:`walk3d.report.prediction_page`); on any failure
    warn (:class:`ReportWarning`, one line) and return None: a result stands without its page."""
    try:
        page = prediction_page(load_result(folder), folder, load_norms(find_data()))
        return save_report(folder, "prediction", page, None)
    except Exception as exc:  # noqa: BLE001 - the page is optional, the result is not
        warnings.warn(f"report.html not written in {folder}: {' '.join(str(exc).split())}",
                      ReportWarning, stacklevel=2)  # fmt: skip
        return None
