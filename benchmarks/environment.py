"""What every benchmark result records about where it ran, and where results go.

:func:`environment` returns the header that ``run.py``, ``campaign.py`` and ``physics.py`` put
under the key ``"environment"`` of their JSON result:

* ``commit``, ``dirty``: ``git rev-parse --short HEAD`` and whether ``git status --porcelain
  --untracked-files=no`` lists a change (None outside a git checkout);
* ``cpu``: ``model name`` in ``/proc/cpuinfo``, else :func:`platform.processor`; ``cores``:
  :func:`os.cpu_count`;
* ``python``, ``numpy``, ``scipy``, ``casadi``: the installed versions;
* ``ipopt``, ``mumps``: the banner IPOPT prints at ``print_level`` 5 ("This is Ipopt version
  3.14.19, running with linear solver MUMPS 5.8.2."), from a one-variable ``nlpsol`` solved in
  a child process. CasADi's solver stats do not report them, and
  ``casadi.CasadiMeta.feature_list()`` only names the IPOPT source CasADi was built from
  (``BUILD_IPOPT_VERSION=3.14.19.mod``) and a MUMPS repository branch; loading IPOPT in the
  benchmark's own process would keep walk3d from putting its BLAS under it
  (``walk3d.solve.blas``). If the child fails, the IPOPT version is taken from CasADi's build
  (that ``BUILD_IPOPT_VERSION``) and MUMPS's is None; ``solver_versions_from`` says which way
  they were read;
* ``blas``: ``walk3d`` BLAS status (``status().describe()``) in this process, or the one the
  caller passes (``campaign.py``: its workers');
* ``date``: ISO 8601, UTC; ``solve_revision``: ``walk3d.solve.SOLVE_REVISION``.

Raw runs go to ``benchmarks/runs/<name>-<UTC timestamp>.json`` (git-ignored); ``--reference``
writes or replaces the one committed reference ``benchmarks/reference/<name>.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import re
import subprocess
import sys
import time
from datetime import UTC, datetime
from importlib import metadata
from pathlib import Path

# a benchmark's walk3d predict runs start no background compile unless it asks for one
# (walk3d.cli.background): that would change what the later runs measure
os.environ["WALK3D_COMPILE_LATER"] = "0"

KEY = "environment"
HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
RUNS = HERE / "runs"
REFERENCE = HERE / "reference"
FIELDS = ("commit", "dirty", "cpu", "cores", "python", "numpy", "scipy", "casadi", "ipopt",
          "mumps", "blas", "date", "solve_revision")  # fmt: skip

_PROBE = """
import contextlib, io
import casadi as ca
x = ca.SX.sym("x")
solver = ca.nlpsol("probe", "ipopt", {"x": x, "f": (x - 1) ** 2},
                   {"ipopt.print_level": 5, "ipopt.sb": "yes", "print_time": False})
out = io.StringIO()
with contextlib.redirect_stdout(out):
    solver(x0=0)
print(out.getvalue())
"""
_BANNER = re.compile(r"Ipopt version (\d[\w.]*?)\.?,\s+running with linear solver (\w+) ([\d.]*\d)")


def git_commit(root: Path = ROOT) -> tuple[str | None, bool | None]:
    """The short hash of HEAD and whether tracked files differ from it."""

    def git(*args: str) -> str | None:
        try:
            run = subprocess.run(["git", "-C", str(root), *args], capture_output=True,
                                 text=True, timeout=30, check=False)  # fmt: skip
        except (OSError, subprocess.SubprocessError):
            return None
        return run.stdout if run.returncode == 0 else None

    commit = git("rev-parse", "--short", "HEAD")
    if commit is None:
        return None, None
    status = git("status", "--porcelain", "--untracked-files=no")
    return commit.strip(), None if status is None else bool(status.strip())


def cpu_model() -> str | None:
    """The CPU's model name (Linux), else whatever :func:`platform.processor` says."""
    try:
        for line in Path("/proc/cpuinfo").read_text(encoding="utf-8").splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or None


def parse_banner(text: str) -> tuple[str | None, str | None, str | None]:
    """IPOPT's version, linear solver and the solver's version from IPOPT's banner."""
    m = _BANNER.search(text)
    return (m.group(1), m.group(2), m.group(3)) if m else (None, None, None)


def solver_versions(timeout_s: float = 120.0) -> dict:
    """IPOPT's and MUMPS's versions (see the module docstring for how)."""
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    try:
        run = subprocess.run([sys.executable, "-c", _PROBE], capture_output=True, text=True,
                             timeout=timeout_s, env=env, check=False)  # fmt: skip
        ipopt, linear, version = parse_banner(run.stdout)
    except (OSError, subprocess.SubprocessError):
        ipopt = linear = version = None
    if ipopt is not None:
        return {"ipopt": ipopt, "mumps": version if linear == "MUMPS" else None,
                "solver_versions_from": "IPOPT's banner (print_level 5) in a child process"
                + ("" if linear == "MUMPS" else f"; its linear solver is {linear}")}  # fmt: skip
    try:
        import casadi as ca

        m = re.search(r"BUILD_IPOPT_VERSION=([\d.]*\d)", ca.CasadiMeta.feature_list())
        ipopt = m.group(1) if m else None
    except Exception:  # noqa: BLE001 - a header field, never a failed benchmark
        ipopt = None
    return {"ipopt": ipopt, "mumps": None,
            "solver_versions_from": "CasADi's build (CasadiMeta.feature_list); "
            "the IPOPT probe failed"}  # fmt: skip


def blas_status() -> str | None:
    """walk3d's BLAS under CasADi's IPOPT in this process."""
    try:
        from walk3d.solve import blas

        return blas.status().describe()
    except Exception:  # noqa: BLE001
        return None


def _version(dist: str) -> str | None:
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return None


def environment(blas: str | None = None) -> dict:
    """The header of a benchmark result (fields in :data:`FIELDS`, plus
    ``solver_versions_from``). ``blas`` replaces this process's BLAS status."""
    commit, dirty = git_commit()
    try:
        from walk3d.solve import SOLVE_REVISION as revision
    except ImportError:
        revision = None
    return {
        "commit": commit,
        "dirty": dirty,
        "cpu": cpu_model(),
        "cores": os.cpu_count(),
        "python": platform.python_version(),
        "numpy": _version("numpy"),
        "scipy": _version("scipy"),
        "casadi": _version("casadi"),
        **solver_versions(),
        "blas": blas if blas is not None else blas_status(),
        "date": now(),
        "solve_revision": revision,
    }


def now() -> str:
    """The current time, ISO 8601 UTC to the second."""
    return datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ")


def run_path(name: str, stamp: str | None = None, runs: Path | None = None) -> Path:
    """``benchmarks/runs/<name>-<UTC timestamp>.json``."""
    stamp = stamp or datetime.now(UTC).strftime("%Y%m%dT%H%M%SZ")
    return (runs or RUNS) / f"{name}-{stamp}.json"


def reference_path(name: str, reference: Path | None = None) -> Path:
    """``benchmarks/reference/<name>.json``, the committed reference result."""
    return (reference or REFERENCE) / f"{name}.json"


def newest_run(name: str, runs: Path | None = None) -> Path | None:
    """The newest raw run of benchmark ``name`` (the timestamps sort as text), or None."""
    found = sorted((runs or RUNS).glob(f"{name}-*.json"))
    return found[-1] if found else None


def add_output_arguments(ap: argparse.ArgumentParser, name: str) -> None:
    """``--out PATH`` and ``--reference`` for benchmark ``name``."""
    ap.add_argument(
        "--out", default=None, help=f"result file (default: benchmarks/runs/{name}-<UTC time>.json)"
    )
    ap.add_argument("--reference", action="store_true",
                    help=f"write the committed reference benchmarks/reference/{name}.json "
                    "instead of a raw run")  # fmt: skip


def output_path(args: argparse.Namespace, name: str) -> Path:
    """Where this run's result goes: ``--out``, else the reference or a new raw run."""
    if args.out and args.reference:
        raise SystemExit("--out and --reference exclude each other")
    if args.out:
        path = Path(args.out)
    else:
        path = reference_path(name) if args.reference else run_path(name)
    path.parent.mkdir(parents=True, exist_ok=True)
    return path


def write(path: Path, result: dict) -> None:
    """Write a result as indented JSON (whole file, replaced)."""
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(json.dumps(result, indent=2) + "\n", encoding="utf-8")
    tmp.replace(path)


def wait_for_background_compile(cache: Path, timeout_s: float = 1800.0) -> float | None:
    """Wait until no background compile (``walk3d.cli.background``) of the model cache
    ``cache`` is pending or running (no ``compile-*.json`` left, ``compile.lock`` free); the
    seconds waited, or None after ``timeout_s``."""
    from walk3d.cli.background import running

    t0 = time.perf_counter()
    while any(cache.glob("compile-*.json")) or running(cache / "compile.lock"):
        if time.perf_counter() - t0 > timeout_s:
            return None
        time.sleep(1.0)
    return round(time.perf_counter() - t0, 1)
