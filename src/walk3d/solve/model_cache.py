"""On-disk cache of the model's CasADi functions, so that a new process skips their construction.

What is kept: the SX functions of :func:`walk3d.problem.nlp.model_functions` (the node
functions of every stage and the loop function). Building them is Python-level symbolic work,
seconds at 20 nodes; CasADi reads them back in a few hundredths of a second. What is *not*
kept, because CasADi's serialization reads it back more slowly than it is built
(docs/solver.md):

* the per-node derivative functions (the full stage's Hessian alone has 1.7 million SX
  instructions, over 100 MB serialized);
* the ``nlpsol`` objects themselves (they serialize, custom ``grad_f``/``jac_g``/``hess_lag``
  options included, but to hundreds of MB).

Each function is built, and read or written, on first use (:class:`LazyFunctions`): a start
from the atlas needs only the full stage's node functions, three of the seven. An entry is one
ASCII file ``model-<key>-<name>.casadi`` per function: a header line ``walk3d-model-cache <schema>
<sha256 of the rest>``, then a :class:`casadi.StringSerializer` payload (the key, the names,
the functions). It is written through :func:`walk3d.io.atomic.atomic_write_text` (temporary
file, then ``os.replace``), so concurrent campaign workers never read half an entry; the
checksum catches any other damage. Every read failure counts as a miss (the caller rebuilds)
and every write failure is logged and ignored: the cache never makes a build fail.

Location: ``$WALK3D_CACHE_DIR``, else the user cache folder (``$XDG_CACHE_HOME/walk3d`` or
``~/.cache/walk3d``; ``~/Library/Caches/walk3d`` on macOS; ``%LOCALAPPDATA%\\walk3d\\Cache``
on Windows). ``WALK3D_CACHE=0`` (or ``false``, ``no``, ``off``) turns the cache off.
Entries are never pruned automatically; each takes a few MB (a compiled set of derivatives
about 50 MB), and deleting them is always safe: ``walk3d cache --clear``
(:func:`clear_entries`).
"""

from __future__ import annotations

import dataclasses
import errno
import hashlib
import logging
import os
import re
import shutil
import stat
import sys
import threading
from collections.abc import Callable, Iterator, Mapping
from functools import cache
from pathlib import Path

import casadi as ca
import numpy as np

from walk3d import constants
from walk3d.io.atomic import atomic_write_text

__all__ = ["SCHEMA", "LazyFunctions", "cache_dir", "cache_enabled", "cache_entries", "cache_usage",
           "clear_entries", "model_key", "not_a_folder", "read_functions", "read_regular",
           "write_functions"]  # fmt: skip

SCHEMA = 2
"""Raise when the entry format or the set of cached functions changes (2: one entry per
function)."""
ENV_DIR = "WALK3D_CACHE_DIR"
ENV_SWITCH = "WALK3D_CACHE"
_MAGIC = "walk3d-model-cache"
_OFF = {"0", "false", "no", "off"}
log = logging.getLogger(__name__)


def switched_on(name: str) -> bool:
    """Whether the environment switch ``$name`` is on: unset, or any value but 0, false, no, off."""
    return os.environ.get(name, "1").strip().lower() not in _OFF


def cache_enabled(flag: bool | None = None) -> bool:
    """``flag`` if given, else whether ``$WALK3D_CACHE`` leaves the cache on (the default)."""
    return flag if flag is not None else switched_on(ENV_SWITCH)


def cache_dir() -> Path:
    """The cache folder: ``$WALK3D_CACHE_DIR``, else the platform's user cache folder."""
    env = os.environ.get(ENV_DIR)
    if env:
        return Path(env).expanduser()
    home = Path.home()
    if sys.platform == "win32":
        local = os.environ.get("LOCALAPPDATA") or home / "AppData" / "Local"
        return Path(local) / "walk3d" / "Cache"
    if sys.platform == "darwin":
        return home / "Library" / "Caches" / "walk3d"
    return Path(os.environ.get("XDG_CACHE_HOME") or home / ".cache") / "walk3d"


def _feed(h, obj: object) -> None:
    """Feed a canonical byte form of ``obj`` (dataclasses, arrays, containers, scalars)."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        h.update(f"<{type(obj).__qualname__}".encode())
        for f in dataclasses.fields(obj):
            h.update(f.name.encode())
            _feed(h, getattr(obj, f.name))
        h.update(b">")
    elif isinstance(obj, np.ndarray):
        h.update(f"<nd {obj.dtype.str} {obj.shape}>".encode())
        h.update(np.ascontiguousarray(obj).tobytes())
    elif isinstance(obj, (tuple, list)):
        h.update(f"<seq {len(obj)}".encode())
        for item in obj:
            _feed(h, item)
        h.update(b">")
    elif isinstance(obj, dict):
        h.update(f"<map {len(obj)}".encode())
        for k in sorted(obj, key=repr):
            _feed(h, k)
            _feed(h, obj[k])
        h.update(b">")
    elif isinstance(obj, float):
        h.update(f"<f {obj.hex()}>".encode())
    else:  # str, int, bool, None; anything else by repr (at worst a needless miss)
        h.update(f"<{type(obj).__name__} {obj!r}>".encode())


@cache
def _source_digest() -> str:
    """SHA-256 of walk3d's own source and data files: the functions are built by this code,
    and a development checkout changes it without changing the version (a few ms)."""
    root = Path(constants.__file__).resolve().parent
    h = hashlib.sha256()
    for p in sorted(root.rglob("*")):
        if p.suffix in {".py", ".toml"} and p.is_file():
            h.update(p.relative_to(root).as_posix().encode())
            h.update(p.read_bytes())
    return h.hexdigest()


def model_key(model_settings: object, body: object) -> str:
    """Hex key of an entry: the settings that shape the functions, the body model, the schema,
    the casadi and walk3d versions and walk3d's source files."""
    h = hashlib.sha256()
    for part in (SCHEMA, ca.__version__, constants.__version__, _source_digest(), model_settings,
                 body):  # fmt: skip
        _feed(h, part)
    return h.hexdigest()[:32]


def read_regular(path: Path, limit: int | None = None) -> bytes:
    """The bytes of ``path``, at most ``limit`` of them; OSError unless it is a regular file:
    the cache is a folder anyone may put things in, and a FIFO there blocked the read for ever
    (opened without blocking, it is refused before any read)."""
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise OSError(errno.EINVAL, "not a regular file", str(path))
        with os.fdopen(os.dup(fd), "rb") as f:
            return f.read() if limit is None else f.read(limit)
    finally:
        os.close(fd)


def _entry(key: str) -> Path:
    return cache_dir() / f"model-{key}.casadi"


_REFUSED: set[Path] = set()
"""Cache folders found not to be folders, already reported (:func:`_folder_usable`)."""


def not_a_folder() -> str | None:
    """``the model cache X is not a folder`` when something other than a folder is in the
    cache folder's place, or in a parent's place (nearest existing one), else None (it is a
    folder, or can become one)."""
    folder = cache_dir()
    base = folder
    while not os.path.lexists(base) and base != base.parent:
        base = base.parent
    if base.is_dir():
        return None
    if base == folder:
        return f"the model cache {folder} is not a folder"
    return f"the model cache {folder} is not a folder ({base} is a file)"


def _folder_usable() -> bool:
    """Whether the cache folder is a folder or can become one. A file in its place is reported
    once per process (one line, not one per entry) and the cache is off for the process."""
    problem = not_a_folder()
    if problem is None:
        return True
    if cache_dir() not in _REFUSED:
        _REFUSED.add(cache_dir())
        log.warning("%s: running without the cache", problem)
    return False


def read_functions(key: str) -> dict[str, ca.Function] | None:
    """The functions stored under ``key``, or None if there is no entry or it is unreadable."""
    if not _folder_usable():
        return None
    path = _entry(key)
    try:
        text = read_regular(path).decode("ascii")
    except FileNotFoundError:
        return None
    except (OSError, ValueError) as exc:
        log.warning("ignoring unreadable model cache entry %s (%s); rebuilding", path, exc)
        return None
    try:
        header, payload = text.split("\n", 1)
        magic, schema, digest = header.split(" ")
        if magic != _MAGIC or schema != str(SCHEMA):
            raise ValueError(f"unexpected header {header[:80]!r}")
        if hashlib.sha256(payload.encode("ascii")).hexdigest() != digest:
            raise ValueError("checksum mismatch (truncated or damaged)")
        stream = ca.StringDeserializer(payload)
        stored_key, names, functions = stream.unpack(), stream.unpack(), stream.unpack()
        if stored_key != key or len(names) != len(functions):
            raise ValueError("entry does not match its key")
        return dict(zip(names, functions, strict=True))
    except Exception as exc:  # noqa: BLE001 - any damage means a rebuild, never a crash
        log.warning("ignoring damaged model cache entry %s (%s); rebuilding", path, exc)
        return None


def write_functions(key: str, functions: dict[str, ca.Function]) -> Path | None:
    """Store ``functions`` under ``key`` atomically; the path, or None if writing failed."""
    if not _folder_usable():
        return None
    path = _entry(key)
    try:
        stream = ca.StringSerializer()
        stream.pack(key)
        stream.pack(list(functions))
        stream.pack(list(functions.values()))
        payload = stream.encode()
        digest = hashlib.sha256(payload.encode("ascii")).hexdigest()
        path.parent.mkdir(parents=True, exist_ok=True)
        return atomic_write_text(path, f"{_MAGIC} {SCHEMA} {digest}\n{payload}")
    except Exception as exc:  # noqa: BLE001 - a cache that cannot be written is only slower
        log.warning("could not write the model cache entry %s (%s)", path, exc)
        return None


ENTRY_PATTERNS = {"models": "model-*.casadi", "libraries": "lib-*.so", "bridges": "blas-*.so",
                  "digests": "*.so.sha256"}  # fmt: skip
"""The cache folder's finished entries by kind: model functions (this module), compiled
derivatives (:mod:`walk3d.solve.compiled`), the BLAS bridge (:mod:`walk3d.solve.blas`) and the
libraries' digests. Temporaries of writes in progress are not entries."""


ENTRY_NAME = re.compile(r"(model-[0-9a-f]{32}-\w+\.casadi|lib-[0-9a-f]{32}-\w+\.so"
                        r"|blas-[0-9a-f]{24}\.so)(\.sha256)?")  # fmt: skip
"""The whole name of an entry walk3d writes (its key's hex digits, then the function's name):
a user's own ``lib-mine.so`` in a folder named by ``$WALK3D_CACHE_DIR`` is not one."""


def cache_entries() -> dict[str, list[Path]]:
    """The finished entries in :func:`cache_dir` by kind (:data:`ENTRY_PATTERNS`), named as
    walk3d names them (:data:`ENTRY_NAME`)."""
    folder = cache_dir()
    if not folder.is_dir():
        return {kind: [] for kind in ENTRY_PATTERNS}
    return {kind: sorted(p for p in folder.glob(pattern) if ENTRY_NAME.fullmatch(p.name))
            for kind, pattern in ENTRY_PATTERNS.items()}  # fmt: skip


def cache_usage() -> dict[str, int]:
    """Entries by kind (:data:`ENTRY_PATTERNS`) and their total size: ``{kind: count, ...,
    "bytes": size}``; an entry deleted meanwhile is not counted."""
    usage, size = {}, 0
    for kind, paths in cache_entries().items():
        usage[kind] = 0
        for path in paths:
            try:
                size += path.stat().st_size
            except FileNotFoundError:
                continue
            usage[kind] += 1
    return usage | {"bytes": size}


def clear_entries() -> tuple[int, int]:
    """Delete every finished entry of the cache folder: ``(files, bytes)`` deleted.

    Other files, and the temporaries of writes or compiles in progress, are left alone, so a
    running solve or compile is not disturbed (a process that has loaded an entry keeps it).
    """
    files = size = 0
    for paths in cache_entries().values():
        for path in paths:
            try:
                st = path.lstat()
                n = st.st_size
                if stat.S_ISDIR(st.st_mode):  # a damaged entry: a folder in its place
                    shutil.rmtree(path)
                else:
                    path.unlink()
            except FileNotFoundError:
                continue
            files, size = files + 1, size + n
    return files, size


class LazyFunctions(Mapping[str, ca.Function]):
    """The functions ``names`` by name, each made on first use: read from the entry
    ``<key>-<name>`` when ``key`` is given and the entry is good, else ``build(name)`` (then
    written there). Thread-safe; :attr:`hits` and :attr:`misses` name the entries read and
    rebuilt."""

    def __init__(self, names: tuple[str, ...], build: Callable[[str], ca.Function],
                 key: str | None) -> None:  # fmt: skip
        self._names, self._build, self._key = names, build, key
        self._made: dict[str, ca.Function] = {}
        self._lock = threading.Lock()
        self.hits: set[str] = set()
        self.misses: set[str] = set()

    def __getitem__(self, name: str) -> ca.Function:
        if name not in self._names:
            raise KeyError(name)
        with self._lock:
            if name not in self._made:
                entry = f"{self._key}-{name}"
                found = read_functions(entry) if self._key else None
                if found is not None and name in found:
                    self._made[name] = found[name]
                    self.hits.add(name)
                else:
                    self._made[name] = self._build(name)
                    self.misses.add(name)
                    if self._key:
                        write_functions(entry, {name: self._made[name]})
            return self._made[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._names)

    def __len__(self) -> int:
        return len(self._names)
