"""Where walk3d writes: one check of an output path, shared by the command line and the Python
API, and one way to write a group of files (build aside, then replace), so that an output is
either complete or as it was, and nothing walk3d did not write is ever deleted.

Single files go through :func:`walk3d.io.atomic.atomic_write` or ``atomic_path``, whole
folders through ``atomic_folder``; :func:`replace_files` puts several files into an existing
folder together. An :class:`OSError` while writing becomes one
:class:`~walk3d.io.errors.OutputWriteError` line (:func:`write_errors`).
"""

from __future__ import annotations

import errno
import os
import shutil
import stat
from collections.abc import Callable, Collection, Iterator, Mapping
from contextlib import contextmanager
from os import PathLike
from pathlib import Path

from walk3d.io.atomic import (
    check_replaceable,
    file_temporary_of,
    folder_temporary_of,
    fsync_dir,
    temporary_beside,
)
from walk3d.io.errors import OutputWriteError

__all__ = ["NAME_MAX_BYTES", "TEMPORARY_BYTES", "check_folder_of_folders", "check_output_file",
           "check_output_folder", "check_outside_results", "foreign_files", "is_result_folder",
           "json_holds", "new_folder", "replace_files", "result_folder_around",
           "same_path", "write_errors"]  # fmt: skip

NAME_MAX_BYTES = 255
"""Longest file or folder name, bytes, that common file systems hold (ext4, XFS, APFS)."""
TEMPORARY_BYTES = 24
"""Bytes that walk3d's temporary siblings add to an output's name (``.tmp_<name>_<12 hex>.owner``,
:mod:`walk3d.io.atomic`): the output's own name may have at most 255 - 24."""


def _check_name(path: str | PathLike[str], option: str) -> None:
    """Raise ValueError unless ``path`` is valid UTF-8 without NUL (walk3d writes its paths into
    UTF-8 files and messages) and each name fits a file system: at most
    :data:`NAME_MAX_BYTES`, the last one :data:`TEMPORARY_BYTES` less."""
    raw = os.fsencode(path)  # the bytes given, a shell's \xff included
    shown = raw.decode("utf-8", "backslashreplace")
    if b"\0" in raw:
        raise ValueError(f"{option} {shown!r} holds a NUL byte")
    try:
        raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ValueError(f"{option} {shown} is not valid UTF-8 (byte 0x{raw[exc.start]:02x}); "
                         "use a UTF-8 name") from None  # fmt: skip
    names = [n for n in raw.split(b"/") if n]
    for k, name in enumerate(names):
        limit = NAME_MAX_BYTES - (TEMPORARY_BYTES if k == len(names) - 1 else 0)
        if len(name) > limit:
            start = name[:24].decode("utf-8", "ignore")
            raise ValueError(
                f"{option}: the name {start}... is {len(name)} bytes long, at most "
                f"{limit} (file systems hold {NAME_MAX_BYTES}"
                f"{', less walk3d temporary names' if k == len(names) - 1 else ''})"
            )


def _writable_base(out: Path, option: str, path: str) -> None:
    """Raise ValueError unless the nearest existing ancestor of ``out`` is a writable folder."""
    base = out
    while not base.exists() and base != base.parent:
        base = base.parent
    if not base.is_dir():
        raise ValueError(f"{option} {path} cannot be created: {base} is a file")
    if not os.access(base, os.W_OK | os.X_OK):
        try:
            read_only = os.statvfs(base).f_flag & os.ST_RDONLY
        except OSError:
            read_only = False
        why = os.strerror(errno.EROFS if read_only else errno.EACCES).lower()
        raise ValueError(f"{option} {path} cannot be written ({base}: {why})")


def _listed(names: list[str]) -> str:
    """The first five of ``names`` for a one-line message, and how many more."""
    more = f" and {len(names) - 5} more" if len(names) > 5 else ""
    return ", ".join(names[:5]) + more


def foreign_files(folder: str | PathLike[str], own: Collection[str]) -> list[str]:
    """The entries of ``folder`` that walk3d did not write, as sorted relative paths (a folder
    ends with ``/``): neither a regular file in ``own`` (relative paths, ``/``-separated) nor
    the temporary an interrupted walk3d left of one (``.<name>.<12 hex>.tmp``, or for a
    sub-folder of ``own`` its ``.tmp_<name>_<12 hex>`` beside an owner file:
    :mod:`walk3d.io.atomic`). A sub-folder holding some of ``own`` is searched, any other is
    foreign."""
    parents = {"/".join(p.split("/")[:k]) for p in own for k in range(1, p.count("/") + 1)}
    found: list[str] = []

    def temporary(entry: os.DirEntry, prefix: str) -> bool:
        name = file_temporary_of(entry.name)
        if name is not None and prefix + name in own:
            return entry.is_file(follow_symlinks=False) or entry.is_dir(follow_symlinks=False)
        name = folder_temporary_of(Path(entry.path))
        return name is not None and prefix + name in parents

    def search(base: str, prefix: str) -> None:
        for entry in sorted(os.scandir(base), key=lambda e: e.name):
            rel, is_dir = prefix + entry.name, entry.is_dir(follow_symlinks=False)
            if temporary(entry, prefix):
                continue
            if is_dir and rel in parents:
                search(entry.path, rel + "/")
            elif is_dir or rel not in own or not entry.is_file(follow_symlinks=False):
                found.append(rel + "/" * is_dir)

    search(os.fspath(folder), "")
    return found


def _check_link(out: Path, option: str, shown: str, kind: str) -> None:
    """Raise ValueError if ``out`` (its last name) is a symbolic link, dangling or not: walk3d
    writes an output aside and renames it into place, which would replace the user's link (and
    a dangling one failed only after the work)."""
    if out.is_symlink():
        raise ValueError(f"{option} {shown} is a symbolic link: walk3d would replace the "
                         f"link with its {kind}; give the path it points to, or a new "
                         f"{kind}")  # fmt: skip


def _irregular(path: Path) -> bool:
    """Whether ``path`` is a device, FIFO, socket or link (lstat): what walk3d never writes."""
    try:
        kind = os.lstat(path).st_mode
    except OSError:
        return False
    return not (stat.S_ISREG(kind) or stat.S_ISDIR(kind))


def check_output_folder(
    path: str | PathLike[str],
    option: str = "--out",
    replaces: str | None = None,
    own: Collection[str] | Callable[[Path], Collection[str]] | None = None,
    *,
    home: str | PathLike[str] | None = None,
) -> Path:
    """Refuse, before any work starts, an output folder that is an existing file or cannot be
    created or written: ValueError with one line naming ``option``. With ``replaces`` (a file
    name), an existing non-empty folder must hold that file, so that only an earlier result is
    ever replaced, never a folder of other files; with ``own`` too (the paths walk3d writes
    there, or a function of the folder giving them), it must hold nothing else
    (:func:`foreign_files`). A path that is not UTF-8, has a name too long for a file system,
    is a symbolic link (:func:`_check_link`) or lies inside a walk3d result folder other than
    ``home`` (:func:`check_outside_results`) is refused too. Returns the folder."""
    _check_name(path, option)
    out = Path(path)
    shown = os.fspath(path)
    _check_link(out, option, shown, "folder")
    check_outside_results(out, option, home)
    if out.exists() and not out.is_dir():
        raise ValueError(f"{option} {shown} is an existing file, not a folder")
    if replaces and out.is_dir() and any(out.iterdir()):
        if not (out / replaces).is_file():
            raise ValueError(
                f"{option} {shown} is a folder of other files (no {replaces}); use a new folder"
            )
        foreign = [] if own is None else foreign_files(out, own(out) if callable(own) else own)
        odd = [name for name in foreign if _irregular(out / name)]
        if odd:
            raise ValueError(f"{option} {shown} holds {_listed(odd)}, not a regular file (a "
                             "device, FIFO, socket or link): walk3d replaces only regular "
                             "files; move it out or use a new folder")  # fmt: skip
        if foreign:
            raise ValueError(f"{option} {shown} holds an earlier result and files walk3d did not "
                             f"write ({_listed(foreign)}); move them out or use a new "
                             "folder")  # fmt: skip
    _writable_base(out, option, shown)
    return out


def check_folder_of_folders(path: str | PathLike[str], option: str, replaces: str) -> Path:
    """Refuse, before any work starts, a folder of output folders (``walk3d atlas build
    --work``: one sweep folder per sex and preset) that is an existing file or cannot be
    written, or holds an entry that is neither an empty folder nor a folder with ``replaces``
    (``sweep.json``): a prediction's files, a sweep's own, anyone's. ValueError with one line
    naming ``option``; returns the folder."""
    out = check_output_folder(path, option)
    if not out.is_dir():
        return out
    foreign = []
    for entry in sorted(os.scandir(out), key=lambda e: e.name):  # walk3d has no temporary here
        is_dir = entry.is_dir(follow_symlinks=False)
        if is_dir and (os.path.isfile(os.path.join(entry.path, replaces))
                       or not os.listdir(entry.path)):  # fmt: skip
            continue
        foreign.append(entry.name + "/" * is_dir)
    if foreign:
        raise ValueError(f"{option} {os.fspath(path)} holds files walk3d did not write "
                         f"({_listed(foreign)}), not only folders with {replaces}; "
                         "use a new folder")  # fmt: skip
    return out


def check_output_file(
    path: str | PathLike[str],
    option: str = "--out",
    suffix: str | None = None,
    *,
    home: str | PathLike[str] | None = None,
    inputs: Mapping[str, str | PathLike[str] | None] | None = None,
    existing: tuple[str, Callable[[Path], bool]] | None = None,
) -> Path:
    """Refuse, before any work starts, an output file that is a folder, lacks ``suffix``
    (``".mp4"``...), cannot be created, is not UTF-8, has a name too long for a file system,
    is a symbolic link (:func:`_check_link`), lies inside a walk3d result folder other than
    ``home`` (:func:`check_outside_results`), is one of the files ``inputs`` (option: path)
    the command reads, or, with ``existing`` (what walk3d writes there, a test of a file),
    exists and is not such a file: ValueError with one line. Returns the file's path."""
    _check_name(path, option)
    out = Path(path)
    shown = os.fspath(path)
    _check_link(out, option, shown, "file")
    if suffix is not None and out.suffix.lower() != suffix:
        raise ValueError(f"{option} must name a {suffix} file, got {shown}")
    if out.is_dir():
        raise ValueError(f"{option} {shown} is a folder")
    if out.exists() and not out.is_file():
        raise ValueError(f"{option} {shown} is not a regular file (a device, FIFO or socket): "
                         "walk3d writes only regular files")  # fmt: skip
    check_outside_results(out, option, home)
    for name, given in (inputs or {}).items():
        if given is not None and out.is_file() and same_path(out, given):
            raise ValueError(f"{option} {shown} is the {name} file, which walk3d reads: it "
                             "would be replaced; write to another file")  # fmt: skip
    if existing is not None and out.is_file() and not existing[1](out):
        raise ValueError(f"{option} {shown} exists and is not a {existing[0]}: walk3d "
                         "replaces only its own files; move it or name another file")  # fmt: skip
    _writable_base(out.parent, option, shown)
    return out


@contextmanager
def write_errors(path: str | PathLike[str]) -> Iterator[None]:
    """Turn an :class:`OSError` raised in the block into one :class:`OutputWriteError` line
    naming ``path`` (one already of that kind passes as it is)."""
    try:
        yield
    except OutputWriteError:
        raise
    except OSError as exc:
        raise OutputWriteError(path, exc) from exc


@contextmanager
def replace_files(folder: str | PathLike[str], last: str) -> Iterator[Path]:
    """Build files in a temporary folder inside ``folder`` (``.<last>.<12 hex>.tmp``: a result
    folder check knows it as walk3d's), then move each over its namesake in ``folder``, the one
    named ``last`` last (a manifest, or the file the others belong to). Nothing is moved if
    one would replace a device, FIFO, socket or folder. On any failure, Ctrl-C included, the
    temporary is deleted and ``folder`` is left as it was; other files are never touched."""
    target = Path(folder)
    target.mkdir(parents=True, exist_ok=True)
    tmp = temporary_beside(target / last)
    tmp.mkdir()
    try:
        yield tmp
        built = sorted((p.name for p in tmp.iterdir()), key=lambda n: (n == last, n))
        for name in built:  # all checked before the first is moved
            check_replaceable(target / name)
        for name in built:
            os.replace(tmp / name, target / name)
        fsync_dir(target)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


@contextmanager
def new_folder(folder: str | PathLike[str], own: Collection[str]) -> Iterator[Path]:
    """For a block that writes the files ``own`` into ``folder``: if it fails, the folders it
    created on the way (``folder`` and missing parents) are removed again with those files in
    them, so that a failed command leaves no half-written folder. A folder that existed before,
    and any file but ``own``, is never touched; a folder holding another file stays."""
    target = Path(folder)
    missing = [p for p in (target, *target.parents) if not p.exists()]
    try:
        yield target
    except BaseException:
        if missing:
            for name in own:
                (target / name).unlink(missing_ok=True)
            for path in missing:  # the deepest first
                try:
                    path.rmdir()
                except OSError:
                    break
        raise


def same_path(a: str | PathLike[str], b: str | PathLike[str]) -> bool:
    """Whether ``a`` and ``b`` name the same file or folder (links and hard links followed)."""
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.abspath(a) == os.path.abspath(b)


def json_holds(path: str | PathLike[str], *keys: str) -> bool:
    """Whether the file ``path`` is a JSON object holding every one of ``keys``: how walk3d
    knows a JSON file it wrote (a calibration, an audit) from a user's before replacing it."""
    from walk3d.io.checks import read_json_object

    try:
        data = read_json_object(path)
    except (OSError, ValueError):  # DataFileError is a ValueError
        return False
    return all(key in data for key in keys)


def is_result_folder(folder: str | PathLike[str]) -> bool:
    """Whether ``folder`` is a walk3d result folder (``walk3d predict`` or ``track``): its
    ``summary.json`` beside the ``manifest.json`` written last, or beside ``result.npz``."""
    base = Path(folder)
    return (base / "summary.json").is_file() and any(
        (base / name).is_file() for name in ("manifest.json", "result.npz")
    )


def result_folder_around(folder: str | PathLike[str]) -> Path | None:
    """The nearest walk3d result folder (:func:`is_result_folder`) that holds ``folder``
    somewhere below it, or None. The path's existing part is resolved first (links followed,
    then ``..``: ``link/../x`` lies beside the link's target, as the file system reads it)."""
    for parent in Path(os.path.realpath(folder)).parents:
        if is_result_folder(parent):
            return parent
    return None


def check_outside_results(
    path: str | PathLike[str], option: str, home: str | PathLike[str] | None = None
) -> None:
    """Raise ValueError (one line) if ``path`` lies inside a walk3d result folder other than
    ``home`` (the result a command reads and adds its own files to: its page, video, audit):
    written there, it would replace or stand among that result's files, and the next
    ``walk3d predict --out`` of the folder would be refused."""
    inside = result_folder_around(path)
    if inside is not None and not (home is not None and same_path(inside, home)):
        raise ValueError(f"{option} {os.fspath(path)} is inside the walk3d result folder "
                         f"{inside}; write outside it")  # fmt: skip
