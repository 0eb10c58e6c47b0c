"""An optimized BLAS under CasADi's bundled IPOPT and MUMPS.

Why. CasADi's wheel ships its own OpenBLAS (``libcasadi-tp-openblas.so.0``, 0.3.24 in CasADi
3.7-3.8) built for the generic ``CORE2`` target: SSE2 kernels only, none for AVX, AVX2 or
AVX-512. MUMPS's dense frontal work (``dgemm``, ``dtrsm``, ...) and IPOPT's vector operations
run on it. ``scipy-openblas32``, the OpenBLAS build that NumPy's and SciPy's wheels use, picks
its kernels for the CPU at run time. On the default prediction it makes IPOPT's linear algebra
about a quarter cheaper per iteration (docs/solver.md).

How. CasADi loads its plugins with ``RTLD_DEEPBIND``, so ``LD_PRELOAD`` does not reach them.
But the dynamic linker satisfies a library's ``DT_NEEDED`` entry with an already loaded library
of that soname. So walk3d assembles a small library with the soname
``libcasadi-tp-openblas.so.0`` whose functions jump to ``scipy-openblas32``'s functions of the
same names (prefixed ``scipy_`` there; a tail jump passes every argument through, so no
signature is restated), and loads it before CasADi loads IPOPT (:func:`activate`, called by
:func:`walk3d.solve.solver.build_solver`). It exports exactly the functions that CasADi's
libraries take from their bundled OpenBLAS, found with ``nm``.

Falls back to CasADi's own OpenBLAS, with the reason in :func:`status` (and in
``summary.json``), when: ``$WALK3D_BLAS`` is ``casadi``; the system is not Linux; CasADi has no
bundled OpenBLAS; ``scipy-openblas32`` is missing or lacks a function; there is no C compiler
or ``nm``; or IPOPT was already loaded in this process. Results are the same up to rounding;
like the compiled derivatives, a different rounding can move IPOPT's path.

The library is built once per CasADi and ``scipy-openblas32`` version into the model cache
folder (:func:`walk3d.solve.model_cache.cache_dir`), atomically: well under a second (one
``nm`` call reads CasADi's libraries); later processes load it in milliseconds.
"""

from __future__ import annotations

import ctypes
import hashlib
import logging
import os
import shutil
import subprocess
import sys
import threading
from dataclasses import dataclass
from pathlib import Path

import casadi as ca

from walk3d.solve.compiled import CompileError, build_library, compiler, verified
from walk3d.solve.model_cache import cache_dir

__all__ = ["ENV", "SONAME", "BlasStatus", "activate", "bundled_library", "status"]

ENV = "WALK3D_BLAS"
"""``auto`` (default): use ``scipy-openblas32`` when possible; ``casadi``: keep CasADi's."""
SONAME = "libcasadi-tp-openblas.so.0"
_REVISION = 1  # raise when the generated library changes
_PREFIX = "scipy_"
_BUNDLED = "CasADi's bundled OpenBLAS"
_TOO_LATE = "IPOPT was loaded before walk3d could switch"
log = logging.getLogger(__name__)
_lock = threading.Lock()
_status: BlasStatus | None = None


@dataclass(frozen=True)
class BlasStatus:
    """Which BLAS CasADi's IPOPT uses in this process: ``active`` is True for
    ``scipy-openblas32``; ``name`` says which, and ``reason`` why not when not."""

    active: bool
    name: str
    reason: str = ""

    def describe(self) -> str:
        """One line for summaries: the BLAS, and why CasADi's own is kept if it is."""
        return self.name if self.active else f"{self.name} ({self.reason})"


def bundled_library() -> Path | None:
    """CasADi's bundled OpenBLAS, or None if this CasADi has none."""
    path = Path(ca.__file__).parent / SONAME
    return path if path.exists() else None


def _mapped(path: Path) -> bool:
    """Whether ``path`` is loaded in this process (Linux: ``/proc/self/maps``)."""
    try:
        maps = Path("/proc/self/maps").read_text(encoding="utf-8", errors="replace")
    except OSError:
        return False
    return str(path.resolve()) in maps


def _functions(nm: str, libs: Path | list[Path], undefined: bool) -> set[str]:
    """Dynamic function symbols that ``libs`` define (text) or take from elsewhere, read by one
    ``nm`` call for all of them (one call per library took seconds over CasADi's 200-odd)."""
    flag = "--undefined-only" if undefined else "--defined-only"
    files = [str(f) for f in (libs if isinstance(libs, list) else [libs])]
    run = subprocess.run([nm, "-D", flag, *files], capture_output=True, text=True, check=False)
    out = set()
    for line in run.stdout.splitlines():
        parts = line.split()
        if undefined and len(parts) >= 2 and parts[-2] == "U":
            out.add(parts[-1].split("@")[0])
        elif not undefined and len(parts) == 3 and parts[1] == "T":
            out.add(parts[2].split("@")[0])
    return out


def _needed(nm: str, bundled: Path) -> set[str]:
    """The functions CasADi's libraries take from their bundled OpenBLAS."""
    provided = _functions(nm, bundled, undefined=False)
    libs = sorted(
        lib
        for lib in bundled.parent.glob("*.so*")
        if lib.is_file() and not lib.is_symlink() and lib.resolve() != bundled.resolve()
    )
    return _functions(nm, libs, undefined=True) & provided if libs else set()


def _assembly(names: list[str]) -> str:
    lines = [".text"]
    for name in names:
        lines += [f".globl {name}", f".type {name},@function", f"{name}: jmp {_PREFIX}{name}@PLT"]
    lines.append('.section .note.GNU-stack,"",@progbits')
    return "\n".join(lines) + "\n"


def _openblas_file(lib_dir: Path, lib_name: str) -> Path | None:
    """``scipy-openblas32``'s shared library, or None."""
    return next(iter(sorted(lib_dir.glob(f"lib{lib_name}.so*"))), None)


def _build(path: Path, bundled: Path, lib_dir: Path, lib_name: str) -> str:
    """Build the forwarding library at ``path``; '' on success, else why not."""
    cc, nm = compiler(), shutil.which("nm")
    if cc is None or nm is None:
        return "no C compiler or nm to build the BLAS bridge"
    target = _openblas_file(lib_dir, lib_name)
    if target is None:
        return f"no lib{lib_name}.so in {lib_dir}"
    needed = sorted(_needed(nm, bundled))
    have = {s[len(_PREFIX) :] for s in _functions(nm, target, False) if s.startswith(_PREFIX)}
    missing = [s for s in needed if s not in have]
    if not needed or missing:
        return f"scipy-openblas32 lacks {', '.join(missing[:3])}" if missing else "nm found nothing"
    try:
        build_library(path, "blas_bridge.s", _assembly(needed), cc, [f"-Wl,-soname,{SONAME}"],
                      [f"-L{lib_dir}", f"-l{lib_name}", f"-Wl,-rpath,{lib_dir}"])  # fmt: skip
    except CompileError as exc:
        return f"building the BLAS bridge failed: {exc}"
    return ""


def _try() -> BlasStatus:
    if os.environ.get(ENV, "auto").strip().lower() == "casadi":
        return BlasStatus(False, _BUNDLED, f"${ENV}=casadi")
    if not sys.platform.startswith("linux"):
        return BlasStatus(False, _BUNDLED, "the BLAS bridge is built on Linux only")
    bundled = bundled_library()
    if bundled is None:
        return BlasStatus(False, "CasADi's BLAS", f"CasADi has no {SONAME}")
    if _mapped(bundled):
        return BlasStatus(False, _BUNDLED, _TOO_LATE)
    try:
        import scipy_openblas32 as sob
    except ImportError:
        return BlasStatus(False, _BUNDLED, "scipy-openblas32 is not installed")
    lib_dir, lib_name = Path(sob.get_lib_dir()), sob.get_library()
    key = hashlib.sha256(
        f"{_REVISION} {ca.__version__} {bundled.resolve()} {sob.__version__} {lib_dir}".encode()
    ).hexdigest()[:24]
    path = cache_dir() / f"blas-{key}.so"
    damage = verified(path) if path.is_file() else None
    if damage:  # a damaged bridge is built again, not loaded
        log.warning("ignoring the BLAS bridge %s: %s; building it again", path, damage)
    if not path.is_file() or damage:
        why = _build(path, bundled, lib_dir, lib_name)
        if why:
            return BlasStatus(False, _BUNDLED, why)
    try:
        # RTLD_LOCAL: the soname is what the dynamic linker matches; nothing else in the
        # process sees the bridge's BLAS names
        ctypes.CDLL(str(path), mode=ctypes.RTLD_LOCAL)
        blas = ctypes.CDLL(str(_openblas_file(lib_dir, lib_name)))
    except OSError as exc:
        return BlasStatus(False, _BUNDLED, f"the BLAS bridge did not load: {exc}")
    threads = os.environ.get("OPENBLAS_NUM_THREADS", "1")
    blas[f"{_PREFIX}openblas_set_num_threads"](int(threads) if threads.isdigit() else 1)
    corename = blas[f"{_PREFIX}openblas_get_corename"]
    corename.restype = ctypes.c_char_p
    return BlasStatus(True, f"scipy-openblas32 {sob.__version__} ({corename().decode()})")


def activate() -> BlasStatus:
    """Put ``scipy-openblas32`` under CasADi's IPOPT in this process if possible (once; later
    calls return the first outcome). Call it before any IPOPT solver is made."""
    global _status
    with _lock:
        if _status is None:
            try:
                _status = _try()
            except Exception as exc:  # noqa: BLE001 - never fail a solve over its BLAS
                _status = BlasStatus(False, _BUNDLED, f"the BLAS bridge failed: {exc}")
            if not _status.active:
                log.info("BLAS: %s", _status.describe())
        return _status


def status() -> BlasStatus:
    """The BLAS CasADi's IPOPT uses or will use in this process (after :func:`activate`, its
    outcome; before, whether CasADi's own has already been loaded)."""
    if _status is not None:
        return _status
    bundled = bundled_library()
    if bundled is not None and _mapped(bundled):
        return BlasStatus(False, _BUNDLED, _TOO_LATE)
    return BlasStatus(False, _BUNDLED, "not activated")
