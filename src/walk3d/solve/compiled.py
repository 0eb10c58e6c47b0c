"""Compiled C versions of CasADi functions, kept in the model cache folder.

CasADi generates C for an SX function (``Function.generate``); a C compiler turns it into a
shared library, and ``casadi.external`` loads it back as a Function with the same inputs and
outputs. Evaluated that way, the node derivative blocks of :func:`walk3d.problem.derivatives.
derivative_chunks` run about 9 times faster than in CasADi's SX virtual machine at -O1 (5 times
at -O0), with equal values (docs/solver.md, "Compiled derivatives").

An entry is one library per function, ``lib-<key>-<function name>.so`` in
:func:`walk3d.solve.model_cache.cache_dir`. It is compiled in a temporary folder next to it,
``.build-<pid>-<start time>-<random>`` (:data:`BUILD_PREFIX`, the building process's pid and
start time, :mod:`walk3d.io.processes`; the pid alone without ``/proc``), and moved into
place with ``os.replace``, so a concurrent reader sees either no library or a whole one. A
killed compile leaves its folders: the next compile start and ``walk3d cache --clear`` remove
them (:func:`remove_leftover_builds`). A library that does not load counts as missing.
Compiling is never implicit: it takes minutes (:func:`compile_functions`), and only
:func:`walk3d.solve.solver.compile_solver` (``walk3d compile``, campaigns) asks for it.

The compiler is ``$CC``, else ``cc`` or ``gcc`` on the ``PATH``; its flags are ``$WALK3D_CFLAGS``,
else ``-O0``: the default problem's derivatives compile in about 4 minutes on 2 cores, where
-O1 takes over 4 times as long for a faster block but a solve only slightly faster (IPOPT's
linear algebra stays); -O2 does not finish on these large functions in reasonable time, and
``-O1 -march=native`` runs on one CPU only (keyed to the CPU; docs/solver.md).
Without a compiler the solver keeps CasADi's virtual machine (same results).
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import logging
import os
import platform
import shlex
import shutil
import subprocess
import tempfile
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path

import casadi as ca

from walk3d.io import processes
from walk3d.io.atomic import atomic_write_text
from walk3d.io.elf import elf_problem
from walk3d.solve import compiler_group
from walk3d.solve.model_cache import cache_dir, read_regular

__all__ = ["BUILD_PREFIX", "CompileError", "build_folders", "build_library", "compile_functions",
           "compiler", "flags", "leftover_builds", "load_functions", "remove_leftover_builds",
           "require_compiler"]  # fmt: skip

ENV_CC = "CC"
ENV_FLAGS = "WALK3D_CFLAGS"
DEFAULT_FLAGS = ("-O0",)
BUILD_PREFIX = ".build-"
"""Name prefix of :func:`build_library`'s temporary folders in the cache folder."""
log = logging.getLogger(__name__)


class CompileError(RuntimeError):
    """The C compiler failed or is missing."""


def compiler() -> list[str] | None:
    """The C compiler command (``$CC``, else ``cc`` or ``gcc`` on the PATH), or None."""
    env = os.environ.get(ENV_CC, "").strip()
    if env:
        cmd = shlex.split(env)
        return cmd if shutil.which(cmd[0]) else None
    for name in ("cc", "gcc"):
        path = shutil.which(name)
        if path:
            return [path]
    return None


def require_compiler() -> list[str]:
    """:func:`compiler`, or :class:`CompileError` if there is none."""
    cc = compiler()
    if cc is None:
        raise CompileError("no C compiler found (set $CC, or install gcc)")
    return cc


def flags() -> tuple[str, ...]:
    """Optimization flags: ``$WALK3D_CFLAGS`` if set, else ``-O0``."""
    env = os.environ.get(ENV_FLAGS)
    return tuple(shlex.split(env)) if env is not None else DEFAULT_FLAGS


def cpu_fingerprint() -> str:
    """The CPU's model and instruction-set flags (Linux ``/proc/cpuinfo``; else the machine
    type), for libraries compiled for this CPU only."""
    try:
        info = Path("/proc/cpuinfo").read_text(encoding="utf-8", errors="replace")
    except OSError:
        return platform.machine()
    keep = ("model name", "flags")
    lines = [ln for ln in info.splitlines() if ln.split(":")[0].strip() in keep]
    return "\n".join(dict.fromkeys(lines))  # first of each, in order


def library_key(key: str, cflags: tuple[str, ...]) -> str:
    """Entry key from ``key`` (what the functions are made of) and the compiler flags. Flags
    that tune for the compiling machine (``-march=native``, ``-mtune=native``) add the CPU's
    fingerprint: such a library may crash another CPU with an illegal instruction, and a cache
    folder can be shared by a cluster's machines."""
    native = any("native" in f for f in cflags)
    cpu = f" cpu:{cpu_fingerprint()}" if native else ""
    return hashlib.sha256(f"{key} {' '.join(cflags)}{cpu}".encode()).hexdigest()[:32]


def _library(key: str, name: str) -> Path:
    return cache_dir() / f"lib-{key}-{name}.so"


def any_libraries() -> bool:
    """Whether the cache folder holds any compiled library (none: nothing to look up)."""
    try:
        return any(cache_dir().glob("lib-*.so"))
    except OSError:
        return False


def digest_path(path: Path) -> Path:
    """Where the SHA-256 of the library ``path`` is kept (``<library>.sha256``)."""
    return path.with_name(path.name + ".sha256")


def _sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def verified(path: Path) -> str | None:
    """Why the library ``path`` must not be loaded, or None: it must match the digest written
    when it was built (:func:`build_library`), and be a whole ELF file
    (:func:`walk3d.io.elf.elf_problem`). A truncated or altered library could take the process
    down in the dynamic loader, so it counts as missing and is built again."""
    try:
        expected = read_regular(digest_path(path), limit=256).decode("ascii").strip()
    except FileNotFoundError:
        return "it has no digest (an unfinished build, or one of an earlier walk3d)"
    except (OSError, UnicodeDecodeError) as exc:
        return f"its digest cannot be read ({exc})"
    try:
        if _sha256(path) != expected:
            return "it does not match its digest (damaged)"
    except OSError as exc:
        return f"it cannot be read ({exc})"
    whole = elf_problem(path)  # cut short before its digest was written
    return None if whole is None else f"it is {whole}"


def load_functions(key: str, names: list[str]) -> dict[str, ca.Function] | None:
    """The compiled functions ``names`` stored under ``key``, or None unless all are there,
    match their digests (:func:`verified`) and load."""
    out = {}
    for name in names:
        path = _library(key, name)
        if not path.is_file():
            if path.exists() or path.is_symlink():  # a folder or FIFO in its place
                log.warning("ignoring compiled function %s: not a regular file; `walk3d cache "
                            "--clear` removes it", path)  # fmt: skip
            return None
        why = verified(path)
        if why:
            log.warning("ignoring compiled function %s: %s; walk3d compile builds it again",
                        path, why)  # fmt: skip
            return None
        try:
            out[name] = ca.external(name, str(path))
        except Exception as exc:  # noqa: BLE001 - an unloadable library is a missing one
            log.warning("ignoring unloadable compiled function %s (%s)", path, exc)
            return None
    return out


def build_library(
    path: Path,
    name: str,
    source: str,
    cc: list[str],
    before: list[str],
    after: list[str],
    group: int | None = None,
) -> None:
    """Build the shared library ``path`` from ``source`` (the file name ``name`` tells the
    compiler its language: ``.c``, ``.s``): ``cc *before -shared SOURCE -o LIB *after`` in a
    temporary folder next to ``path``, the compiler in the process group ``group`` if given,
    then moved into place (atomic) after its SHA-256 (:func:`digest_path`). Raises
    :class:`CompileError` with the compiler's last line of output (or its line that reports a
    full disk: ``ld``'s last line only says that it failed) if it fails."""
    path.parent.mkdir(parents=True, exist_ok=True)
    started = processes.start_time(os.getpid())
    owner = os.getpid() if started is None else f"{os.getpid()}-{started}"
    prefix = f"{BUILD_PREFIX}{owner}-"  # whose it is: :func:`leftover_builds`
    with tempfile.TemporaryDirectory(dir=path.parent, prefix=prefix) as tmp:
        src, lib = Path(tmp) / name, Path(tmp) / "lib.so"
        src.write_text(source, encoding="utf-8")
        cmd = [*cc, *before, "-shared", str(src), "-o", str(lib), *after]
        env = os.environ | {"LC_ALL": "C"}  # the compiler's messages in English, as matched
        run = subprocess.run(cmd, stdin=subprocess.DEVNULL, capture_output=True, text=True,
                             check=False, env=env, process_group=group)  # fmt: skip
        if run.returncode != 0:  # the last line, or the one that says the disk is full
            lines = run.stderr.strip().splitlines()
            full = [ln for ln in lines if os.strerror(errno.ENOSPC) in ln]
            tail = (full or lines)[-1:] or ["no output"]
            raise CompileError(f"{shlex.join(cmd[:1])} failed on {Path(name).stem}: {tail[0]}")
        # the digest first: until the library is in place, a reader finds a mismatch, not a
        # library without its digest's protection
        atomic_write_text(digest_path(path), _sha256(lib) + "\n")
        if path.is_dir() and not path.is_symlink():  # damage in the library's place: repaired
            shutil.rmtree(path)
        os.replace(lib, path)


def build_folders() -> list[Path]:
    """The build folders in the cache folder, named as walk3d names them
    (``.build-<pid>-[<start time>-]<random>``): builds in progress, and those of builds killed
    before they could remove theirs. A folder not named so is not walk3d's: it is left alone."""
    try:
        found = cache_dir().glob(f"{BUILD_PREFIX}*")
        return sorted(p for p in found if _owner(p) is not None and p.is_dir())
    except OSError:
        return []


def _owner(folder: Path) -> tuple[int, int | None] | None:
    """The pid and start time (None if not recorded) in a build folder's name, or None."""
    pid, *rest = folder.name[len(BUILD_PREFIX) :].split("-")  # the random part has no "-"
    started = rest[:-1]  # [] or [start time]
    if not (pid.isdigit() and 1 <= len(rest) <= 2 and rest[-1] and all(map(str.isdigit, started))):
        return None
    return int(pid), int(started[0]) if started else None


def leftover_builds() -> list[Path]:
    """The build folders whose process no longer runs here: a killed compile's. A folder of a
    running build, on this machine, is not one; one whose pid another process has now is (its
    start time differs)."""
    return [f for f in build_folders() if not processes.running(*_owner(f))]


def folder_bytes(folder: Path) -> int:
    """Total size of the files under ``folder``, bytes (files deleted meanwhile not counted)."""
    total = 0
    for root, _dirs, files in os.walk(folder):
        for name in files:
            with contextlib.suppress(OSError):
                total += os.lstat(os.path.join(root, name)).st_size
    return total


def remove_leftover_builds() -> tuple[int, int]:
    """Delete :func:`leftover_builds`: ``(folders, bytes)`` deleted. Call it holding the compile
    lock (:func:`walk3d.cli.background.hold`): a compile on another machine sharing the cache
    folder holds it while it builds."""
    count = size = 0
    for folder in leftover_builds():
        n = folder_bytes(folder)
        shutil.rmtree(folder, ignore_errors=True)
        if not folder.exists():
            count, size = count + 1, size + n
    return count, size


def _c_source(fn: ca.Function) -> str:
    """The C of ``fn`` (CasADi's code generator; in the calling thread, as every symbolic step)."""
    gen = ca.CodeGenerator(f"{fn.name()}.c", {"with_header": False})
    gen.add(fn)
    return gen.dump()


def compile_functions(
    key: str,
    functions: dict[str, ca.Function],
    jobs: int | None = None,
    on_done: Callable[[str, int, int], None] | None = None,
) -> dict[str, ca.Function]:
    """Compile the functions not yet stored under ``key`` (``jobs`` compilers at a time,
    default one per core) and load all of them. ``on_done(name, done, total)`` after each
    compile. The C is generated here, one function at a time while the compilers run: CasADi's
    symbolic operations are not thread-safe. The compilers run in a guarded process group
    (:mod:`walk3d.solve.compiler_group`): they end with this process, or when the compile stops
    on an exception. Raises :class:`CompileError` without a compiler or when one fails."""
    cc = require_compiler()
    cflags = (*flags(), "-fPIC")
    todo = [n for n in functions if load_functions(key, [n]) is None]
    width = jobs or os.cpu_count() or 1
    pending: dict[str, Future] = {}
    finished = 0

    def collect(name: str) -> None:
        nonlocal finished
        pending.pop(name).result()
        finished += 1
        if on_done:
            on_done(name, finished, len(todo))

    guard = compiler_group.guarded_group() if todo else contextlib.nullcontext()
    with ThreadPoolExecutor(width) as pool, guard as group:  # the guard ends before the pool
        for name in todo:
            while len(pending) >= width:  # at most ``width`` sources in memory at once
                collect(next(iter(pending)))
            source = _c_source(functions[name])
            pending[name] = pool.submit(build_library, _library(key, name), f"{name}.c", source,
                                        cc, list(cflags), ["-lm"], group)  # fmt: skip
        while pending:
            collect(next(iter(pending)))
    loaded = load_functions(key, list(functions))
    if loaded is None:
        raise CompileError(f"compiled functions for {key} did not load")
    return loaded
