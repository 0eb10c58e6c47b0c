"""A campaign folder's finished starts on resume: each is read back through the verified
result loader before any solve, as ``walk3d sweep`` reads its speeds
(:mod:`walk3d.campaign.sweep_folder`), and its record is rebuilt from the verified result.

* a start folder that is damaged (incomplete against its manifest, an unreadable summary, arrays
  not tied to it, a record that says converged without a result): run again, with a warning;
* a start folder holding a readable prediction of another problem or another seed (its summary
  read even when the rest is damaged): refused
  (:class:`~walk3d.campaign.store.CampaignMismatch`), not replaced, since it may be someone's
  result put there by mistake; so is one holding files walk3d did not write
  (:mod:`walk3d.campaign.start_folders`, checked first);
* the ranking values (criterion value, convergence, status) come from the result's summary,
  not from ``record.json``, which a hand edit could change.
"""

from __future__ import annotations

import shutil
import warnings
from pathlib import Path

from walk3d.campaign import store, task
from walk3d.campaign.sweep_folder import check_arrays
from walk3d.campaign.sweep_folder import difference as problem_difference
from walk3d.io.checks import read_json_object
from walk3d.problem.settings import PredictionSettings, flat_settings, recorded_settings

__all__ = ["start_difference", "verified_records"]

UNCHECKED = ("threads", "handover", "period", "double_support")
"""Settings not compared by name: ``threads`` does not change the iterates, and
:func:`~walk3d.campaign.sweep_folder.difference` checks the handover (which may fall back to
the free landing); ``period`` and ``double_support`` are compared only when not free."""


RANKED = (
    "status",
    "converged",
    "failure",
    "criterion_value",
    "C_tor",
    "C_en",
    "iterations",
    "looks_like_walking",
)
"""Record fields the ranking and the report read: a record whose fields differ from its
verified result's is rewritten."""


def start_difference(summary: dict, settings: PredictionSettings, seed: int) -> str | None:
    """How a stored prediction differs from the campaign's start ``seed``, as a phrase, or None:
    its problem (:func:`~walk3d.campaign.sweep_folder.difference`), every other setting and
    its seed must be the campaign's. Raises ValueError, KeyError or TypeError for a damaged
    summary."""
    why = problem_difference(summary, settings, settings.gait.speed)
    if why is not None:
        return why
    recorded = flat_settings(PredictionSettings(**recorded_settings(summary)).model_dump())
    requested = flat_settings(settings.model_dump())
    free = set(settings.gait.free)
    for key, value in sorted(requested.items()):
        if key in UNCHECKED and (key not in ("period", "double_support") or key in free):
            continue
        if recorded.get(key) != value:
            return f"was solved with {key} {recorded.get(key)!r}, not {value!r}"
    got = summary["seed"]
    return None if got == seed else f"was solved with seed {got!r}, not {seed}"


def _verified(folder: Path, seed: int, settings: PredictionSettings, record: dict) -> dict:
    """The record of the start folder rebuilt from its verified result; raises
    :class:`~walk3d.campaign.store.CampaignMismatch` for another problem's prediction and
    OSError, ValueError, KeyError, TypeError or AttributeError for a damaged folder."""
    from walk3d.results.prediction import MANIFEST, check_complete

    criterion = settings.model.criterion
    if not (folder / MANIFEST).exists() and not (folder / "summary.json").exists():
        if not record:
            raise ValueError(f"no readable {store.RECORD_FILE} and no result")
        status = record.get("status")  # a start that raised: a record-only folder
        if record.get("converged") or not str(status).startswith("error: "):
            raise ValueError("its record says it finished, but it holds no result")
        return record | {"converged": False, "criterion_value": None}
    try:  # a readable summary of another problem is refused even when the folder is damaged
        summary = read_json_object(folder / "summary.json", "walk3d summary")
    except (OSError, ValueError):
        summary = None
    why = None if summary is None else start_difference(summary, settings, seed)
    if why is not None:
        raise store.CampaignMismatch(
            f"{folder} holds a prediction that {why}; remove that folder to run seed {seed} "
            "again, or use a new --out"
        )
    check_complete(folder)
    summary = summary or read_json_object(folder / "summary.json", "walk3d summary")
    check_arrays(folder, summary)
    spent = record.get("task_time_s")
    spent = float(spent) if isinstance(spent, (int, float)) and not isinstance(spent, bool) else 0
    return task.record_from_summary(summary, criterion, spent)


def verified_records(
    out: Path, settings: PredictionSettings, records: dict[int, dict], seeds: list[int]
) -> list[int]:
    """Replace each record of ``records`` (by seed) by the one its verified result gives, and
    rewrite a ``record.json`` that differs from it in a :data:`RANKED` field (with a warning).

    A damaged start among ``seeds`` is deleted, so that it runs again; one outside them (a
    larger earlier ``--starts``) is left out of ``records``. Each gets a warning. Returns the
    seeds deleted. Raises :class:`~walk3d.campaign.store.CampaignMismatch` (before any solve)
    for a start folder holding another problem's or another seed's prediction.
    """
    again = []
    for seed in sorted(records):
        folder = store.starts_dir(out) / store.start_name(seed)
        try:
            verified = _verified(folder, seed, settings, records[seed])
        except store.CampaignMismatch:
            raise
        except (OSError, ValueError, KeyError, TypeError, AttributeError) as exc:
            why = " ".join(str(exc).split())
            del records[seed]
            if seed in seeds:
                shutil.rmtree(folder)
                again.append(seed)
                action = f"running seed {seed} again"
            else:
                action = "left out of the ranking"
            warnings.warn(f"{folder} cannot be read ({why}): {action}", RuntimeWarning,
                          stacklevel=2)  # fmt: skip
            continue
        changed = [k for k in RANKED if verified.get(k) != records[seed].get(k)]
        if changed:  # ranking.csv and report.html read the records: they agree with the result
            store.write_json(folder / store.RECORD_FILE, verified)
            how = f"did not match its result ({', '.join(changed)})" if records[seed] else (
                "was missing or unreadable")  # fmt: skip
            warnings.warn(f"{folder / store.RECORD_FILE} {how}: rewritten from its result",
                          RuntimeWarning, stacklevel=2)  # fmt: skip
        records[seed] = verified
    return again
