"""A campaign's start folders before a resume reads them: each ``starts/seed_*`` entry must be a
folder (not a file, not a symbolic link) holding only files walk3d writes there, with the
record of its own seed. Anything else is refused in one line, before any solve, and never
deleted (:class:`~walk3d.campaign.store.CampaignMismatch`): it may be someone's files."""

from __future__ import annotations

from pathlib import Path

from walk3d.campaign import store
from walk3d.io.atomic import TMP_PREFIX

__all__ = ["START_FILES", "foreign_files", "resumable_records"]

START_FILES = (store.RECORD_FILE, "traceback.txt")
"""What walk3d writes in a start folder beside a prediction's files."""


def _foreign_in(folder: Path, own: set[str]) -> list[str]:
    """The entries of ``folder`` that are not plain files named in ``own`` (nor temporaries of
    walk3d's atomic writes), by name."""
    found = []
    for p in sorted(folder.iterdir()):
        mine = p.name in own or p.name.startswith(TMP_PREFIX)
        if p.is_symlink() or not mine or not p.is_file():
            found.append(p.name)
    return found


def foreign_files(folder: Path) -> list[str]:
    """The paths in the start ``folder`` (relative, sorted) that walk3d does not write there:
    anything but a prediction's files (:func:`~walk3d.results.prediction.written_files`), its
    ``validation/`` files and :data:`START_FILES`; links and sub-folders included."""
    from walk3d.results.prediction import VALIDATION_FILES, VALIDATION_FOLDER, written_files

    own = {n for n in written_files(folder) if "/" not in n} | set(START_FILES)
    found = []
    for name in _foreign_in(folder, own):
        inner = folder / name
        if name == VALIDATION_FOLDER and inner.is_dir() and not inner.is_symlink():
            found += [f"{name}/{n}" for n in _foreign_in(inner, set(VALIDATION_FILES))]
        else:
            found.append(name)
    return found


def _refuse(path: Path, what: str, seed: int) -> None:
    """Raise the one-line refusal of the start entry ``path``."""
    raise store.CampaignMismatch(
        f"{path} {what}; remove it to run seed {seed} again, or use a new --out"
    )


def resumable_records(out_dir: str | Path) -> dict[int, dict]:
    """The records of the start folders of ``out_dir``, by seed, for the verified resume
    (:func:`walk3d.campaign.resume.verified_records`): an unreadable or missing record is
    ``{}`` (rebuilt from its result, or the start runs again).

    Raises:
        CampaignMismatch: a start entry is a file or a symbolic link, holds files walk3d did
            not write (:func:`foreign_files`) or the record of another seed.
    """
    root = store.starts_dir(out_dir)
    if root.exists() and (root.is_symlink() or not root.is_dir()):
        raise store.CampaignMismatch(f"{root} is not a folder of starts; use a new --out")
    records: dict[int, dict] = {}
    if not root.is_dir():
        return records
    for path in sorted(root.iterdir()):
        m = store.START_RE.match(path.name)
        if not m:
            continue
        seed = int(m.group(1))
        if path.is_symlink():
            _refuse(path, "is a symbolic link where a start folder belongs", seed)
        if not path.is_dir():
            _refuse(path, "is a file where a start folder belongs", seed)
        foreign = foreign_files(path)
        if foreign:
            more = f" and {len(foreign) - 3} more" if len(foreign) > 3 else ""
            names = ", ".join(foreign[:3]) + more
            _refuse(path, f"holds files walk3d did not write ({names})", seed)
        record = store.read_record(path)
        if record is not None and record.get("seed") != seed:
            _refuse(path, f"holds the record of seed {record.get('seed')!r:.20}, not {seed}", seed)
        records[seed] = record if record is not None else {}
    return records
