"""On-disk layout of a multi-start campaign: resumable, and atomic at the level of one start.

A campaign folder ``DIR`` holds:

* ``campaign.json``: what the campaign is (settings, base seed, start count, criterion, solver),
  written once at creation; only ``starts`` is rewritten, atomically, when a resume asks for
  more starts;
* ``starts/seed_<seed:06d>/``: one folder per finished start. A start is built in a temporary
  sibling ``starts/.tmp_seed_<seed:06d>_<random>/`` (the ``walk3d predict`` files plus
  ``record.json``) and then renamed to its final name with :func:`os.rename`, which is atomic:
  a final folder is always complete, and a folder that exists is a finished start. A start that
  raised (or whose worker died) gets a record-only folder (``record.json`` and, when known,
  ``traceback.txt``);
* ``ranking.csv`` and ``best/`` (see :mod:`walk3d.campaign.ranking`).

Leftover temporaries (``.tmp_*``) come from interrupted runs and are deleted on resume; a
``seed_*`` entry that is not such a folder is refused, never deleted
(:mod:`walk3d.campaign.start_folders`).
"""

from __future__ import annotations

import errno
import json
import math
import os
import re
import shutil
from pathlib import Path
from typing import Any

from walk3d.constants import __version__
from walk3d.io.atomic import (
    TMP_PREFIX,
    atomic_folder,
    atomic_write_text,
    fsync_dir,
    temporary_sibling,
)
from walk3d.io.checks import read_json_object
from walk3d.problem.settings import PredictionSettings, flat_settings
from walk3d.solve import SOLVE_REVISION
from walk3d.solve.starts import ATLAS_NOISE_FRACTION

__all__ = [
    "CAMPAIGN_FILE",
    "CampaignMismatch",
    "RECORD_FILE",
    "START_RE",
    "clean_temporaries",
    "commit_start",
    "finished_records",
    "forget_environment_failures",
    "new_temporary",
    "open_campaign",
    "read_campaign",
    "start_name",
]

CAMPAIGN_FILE = "campaign.json"
RECORD_FILE = "record.json"
STARTS_DIR = "starts"
START_RE = re.compile(r"^seed_(\d{6,})$")


class CampaignMismatch(ValueError):
    """The folder holds a campaign whose settings differ from the requested ones."""


def start_name(seed: int) -> str:
    """Final folder name of the start with ``seed``."""
    return f"seed_{seed:06d}"


def starts_dir(out_dir: str | Path) -> Path:
    """The folder holding one sub-folder per finished start."""
    return Path(out_dir) / STARTS_DIR


def clean_json(value: Any) -> Any:
    """``value`` with non-finite floats replaced by ``None`` (strict JSON)."""
    if isinstance(value, dict):
        return {str(k): clean_json(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [clean_json(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if hasattr(value, "item") and callable(value.item):  # numpy scalars
        return clean_json(value.item())
    return value


def write_json(path: Path, data: dict) -> None:
    """Write ``data`` atomically as indented, key-sorted strict JSON."""
    text = json.dumps(clean_json(data), indent=2, sort_keys=True, allow_nan=False)
    atomic_write_text(path, text + "\n")


def _describe(value: Any) -> str:
    return repr(value) if isinstance(value, str) else str(value)


def read_campaign(out_dir: str | Path) -> dict:
    """The stored ``campaign.json`` of ``out_dir`` (one DataFileError line when damaged)."""
    return read_json_object(Path(out_dir) / CAMPAIGN_FILE, "walk3d campaign file")


def _mismatch(stored: dict, requested: dict) -> str | None:
    """The first difference between two campaign descriptions, as a phrase, or None."""
    s_set = flat_settings(stored.get("settings", {}))
    r_set = flat_settings(requested["settings"])
    for key in sorted(set(s_set) | set(r_set)):
        if s_set.get(key) != r_set.get(key):
            return (f"{key}: stored {_describe(s_set.get(key))}, "
                    f"requested {_describe(r_set.get(key))}")  # fmt: skip
    for key in ("solver", "base_seed"):
        if stored.get(key) != requested[key]:
            return f"{key}: stored {_describe(stored.get(key))}, requested {requested[key]}"
    return None


def open_campaign(
    out_dir: str | Path,
    settings: PredictionSettings,
    base_seed: int,
    starts: int,
    solver: str,
) -> dict:
    """Create the campaign folder, or check that an existing one matches this request.

    A resume may ask for more starts (``campaign.json`` then records the larger count) or
    fewer (only the first ``starts`` are run; finished ones are kept and ranked).

    Raises:
        CampaignMismatch: the folder holds a campaign with other settings, criterion, solver
            or base seed, or one made by an earlier walk3d without a setting added since
            (e.g. ``restarts``) or under another solver revision
            (:data:`walk3d.solve.SOLVE_REVISION`), or is a non-empty folder that is not a
            campaign.
    """
    out = Path(out_dir)
    requested = {
        "walk3d_version": __version__,
        "solve_revision": SOLVE_REVISION,
        "atlas_noise_fraction": ATLAS_NOISE_FRACTION,
        "settings": clean_json(settings.model_dump()),
        "criterion": settings.model.criterion,
        "solver": solver,
        "base_seed": base_seed,
        "starts": starts,
    }
    path = out / CAMPAIGN_FILE
    if path.is_file():
        try:
            stored = read_campaign(out)
        except (OSError, ValueError) as exc:
            why = getattr(exc, "reason", None) or " ".join(str(exc).split())
            raise CampaignMismatch(f"{path} is unreadable ({why}); use a new --out") from None
        if not isinstance(stored.get("settings"), dict) or type(stored.get("starts")) is not int:
            raise CampaignMismatch(f"{path} is not a walk3d campaign file; use a new --out")
        added = sorted(set(flat_settings(requested["settings"]))
                       - set(flat_settings(stored.get("settings", {}))))  # fmt: skip
        if added:  # settings introduced since: its starts may have run otherwise
            raise CampaignMismatch(f"{out} holds a campaign made by an earlier walk3d, without "
                                   f"the setting {', '.join(added)}; use a new --out")  # fmt: skip
        if stored.get("solve_revision") != SOLVE_REVISION:  # its starts ran otherwise
            raise CampaignMismatch(
                f"{out} holds a campaign solved by another walk3d (solver revision "
                f"{stored.get('solve_revision', 'before 11')}, now {SOLVE_REVISION}), whose starts "
                "would not be comparable; use a new --out"
            )
        noise = stored.get("atlas_noise_fraction", 0.2)  # 0.2 before it was recorded
        if settings.solver.start == "atlas" and noise != ATLAS_NOISE_FRACTION:
            raise CampaignMismatch(
                f"{out} holds a campaign whose atlas starts had other noise ({noise:g} of "
                f"--perturbation, now {ATLAS_NOISE_FRACTION:g}); use a new --out"
            )
        diff = _mismatch(stored, requested)
        if diff is not None:
            raise CampaignMismatch(
                f"{out} holds a campaign with different settings ({diff}); "
                "rerun with the stored options or use a new --out"
            )
        if starts > int(stored.get("starts", 0)):
            write_json(path, stored | {"starts": starts})
            stored = read_campaign(out)
        return stored
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        raise CampaignMismatch(f"{out} exists and is not a campaign folder; use a new --out")
    starts_dir(out).mkdir(parents=True, exist_ok=True)
    write_json(path, requested)
    return requested


def clean_temporaries(out_dir: str | Path) -> list[Path]:
    """Delete the ``.tmp_*`` leftovers of interrupted runs (folders, and the owner files beside
    them); returns what was removed. Called when no local worker runs."""
    removed = []
    for parent in (Path(out_dir), starts_dir(out_dir)):
        if not parent.is_dir():
            continue
        for p in parent.iterdir():
            if not p.name.startswith(TMP_PREFIX):
                continue
            if p.is_dir() and not p.is_symlink():
                shutil.rmtree(p, ignore_errors=True)
            else:  # an owner file or a file's temporary, left by a worker killed mid-write
                p.unlink(missing_ok=True)
            removed.append(p)
    return removed


def read_record(folder: Path) -> dict | None:
    """The record of a start folder, or None when missing or unreadable."""
    try:
        return read_json_object(folder / RECORD_FILE, "walk3d start record")
    except (OSError, ValueError):
        return None


def finished_records(out_dir: str | Path) -> dict[int, dict]:
    """Records of the finished starts, by seed (a start folder without a readable record of its
    own seed, or that is a link, is skipped; a resume refuses it:
    :func:`walk3d.campaign.start_folders.resumable_records`)."""
    records: dict[int, dict] = {}
    root = starts_dir(out_dir)
    if not root.is_dir():
        return records
    for folder in sorted(root.iterdir()):
        m = START_RE.match(folder.name)
        if not m or folder.is_symlink() or not folder.is_dir():
            continue
        record = read_record(folder)
        if record is not None and record.get("seed") == int(m.group(1)):
            records[int(m.group(1))] = record
    return records


def forget_environment_failures(
    out_dir: str | Path, records: dict[int, dict], seeds: list[int]
) -> list[int]:
    """Delete the folders of the ``seeds`` whose record says they failed on the environment
    (disk, memory, a lost worker), and drop them from ``records``, so that they run again."""
    retried = []
    for seed in seeds:
        if (records.get(seed) or {}).get("failure") == "environment":
            shutil.rmtree(starts_dir(out_dir) / start_name(seed))
            del records[seed]
            retried.append(seed)
    return retried


def new_temporary(parent: Path, name: str) -> Path:
    """Create and return an empty temporary folder ``parent/.tmp_<name>_<random>``."""
    tmp = temporary_sibling(parent, name)
    tmp.mkdir()
    return tmp


def commit_start(tmp: Path, seed: int, record: dict) -> dict:
    """Write ``record.json`` into ``tmp`` and rename ``tmp`` to the start's final folder.

    If the final folder already exists (the same start finished elsewhere first), ``tmp`` is
    discarded and the stored record is returned; otherwise ``record`` is.
    """
    final = tmp.parent / start_name(seed)
    try:
        write_json(tmp / RECORD_FILE, record)
        fsync_dir(tmp)
        try:
            os.rename(tmp, final)
        except OSError:
            existing = read_record(final)
            if existing is None:
                raise
            shutil.rmtree(tmp, ignore_errors=True)
            return existing
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    fsync_dir(tmp.parent)
    return clean_json(record)


def replace_folder(source: Path, target: Path) -> None:
    """Make ``target`` a copy of ``source`` without ever leaving a partial ``target``."""
    with atomic_folder(target) as tmp:
        try:
            shutil.copytree(source, tmp, dirs_exist_ok=True)
        except shutil.Error as exc:  # a list of (source, destination, reason), one per file
            errors = exc.args[0] if exc.args and isinstance(exc.args[0], list) else []
            reason = str(errors[0][2]) if errors else str(exc)
            number = re.match(r"\[Errno (\d+)\] ([^:]*)", reason)
            if number:
                raise OSError(int(number[1]), number[2], str(target)) from None
            raise OSError(errno.EIO, reason[:200], str(target)) from None
