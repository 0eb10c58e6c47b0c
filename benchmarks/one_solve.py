"""Issue #42's targets: ``python benchmarks/one_solve.py [--parts timing realism] [--modes ...]``.

**timing**:

``walk3d predict`` end to end (a fresh process, ``/usr/bin/time``-like wall time from process
start to exit) on five descriptor sets of both sexes at 0.9-1.7 m/s, each with T and Td
predicted (``--descriptors-from atlas``, the default: one solve; ``solve``: the free landing
solved first, then the handover) and with T and Td given (one solve either way). The model
cache is warm (a first run fills it and is not counted), runs go one at a time, with
``OPENBLAS_NUM_THREADS=1``. Nothing is compiled (``WALK3D_COMPILE_LATER=0``), unless
``--compile``: then ``walk3d compile`` runs for both sexes after the cache is filled (timed),
and the runs use the compiled derivatives; or ``--compile-later``, ``walk3d predict``'s
default: each sex's cache-filling run starts the background compile, which is waited for
(timed from the end of that run). Records per run: wall time, exit code, convergence,
iterations, the predicted T and Td, ``looks_like_walking`` and whether the derivatives were
compiled; and the medians per mode.

**realism**: the shared sources of ``benchmarks/criteria_sweep.py`` (Falisse, Winter,
subject01; skipped when ``../shared/data`` is absent), each predicted with T and Td from the
atlas (one solve, the default) and from the free-landing solve (two solves), seed 0, and
``walk3d validate``'s rows side by side (the same figures as criteria_sweep.py), plus the
shared yardstick ``../shared/tools/realism.py`` on Falisse when present.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

_HERE = str(Path(__file__).resolve().parent)
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)
import environment  # noqa: E402

NAME = "one_solve"
SETS = {
    # name: (V m/s, mass kg, height m, sex, T s, Td s): T and Td given from published normative
    # cadence for the speed (not from walk3d)
    "f_0.9": (0.9, 55.0, 1.60, "female", 1.22, 0.17),
    "m_1.1": (1.1, 80.0, 1.85, "male", 1.18, 0.15),
    "f_1.3": (1.3, 65.0, 1.68, "female", 1.04, 0.12),
    "m_1.5": (1.5, 72.0, 1.78, "male", 1.02, 0.11),
    "f_1.7": (1.7, 60.0, 1.72, "female", 0.96, 0.10),
}


def run(out: Path, args: list[str], cache: Path, later: bool = False) -> dict:
    """``walk3d predict`` timed end to end; ``later``: with its background compile (off:
    ``WALK3D_COMPILE_LATER=0``, nothing compiled)."""
    env = dict(os.environ, WALK3D_CACHE_DIR=str(cache), OPENBLAS_NUM_THREADS="1",
               WALK3D_COMPILE_LATER="1" if later else "0")  # fmt: skip
    cmd = [sys.executable, "-m", "walk3d.cli", "predict", "--out", str(out), *args]
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
    row = {"wall_s": round(time.perf_counter() - t0, 2), "exit_code": proc.returncode}
    path = out / "summary.json"
    if path.is_file():
        s = json.loads(path.read_text())
        d = s["descriptors"]
        row.update(converged=s["converged"], iterations=s["iterations"],
                   period_s=round(d["period"], 4), double_support_s=round(d["double_support"], 4),
                   predicted_by=d.get("predicted_by"), solve_s=round(s["wall_time_s"], 2),
                   walks=s["gait_checks"].get("looks_like_walking"),
                   compiled=bool(s.get("compiled_derivatives")))  # fmt: skip
    else:
        row["stderr_tail"] = proc.stderr[-300:]
    return row


def compile_for(sex: str, cache: Path) -> dict:
    """``walk3d compile --sex sex`` into ``cache``: wall time and exit code."""
    env = dict(os.environ, WALK3D_CACHE_DIR=str(cache), OPENBLAS_NUM_THREADS="1")
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "walk3d.cli", "compile", "--sex", sex], env=env,
                          capture_output=True, text=True)  # fmt: skip
    return {"wall_s": round(time.perf_counter() - t0, 1), "exit_code": proc.returncode,
            "last_line": proc.stdout.strip().splitlines()[-1:]}  # fmt: skip


def realism(root: Path) -> list[dict]:
    """The realism rows of each shared source under both ways of predicting T and Td."""
    import criteria_sweep as cs

    rows = []
    if not cs.DATA.is_dir():
        print(f"realism: skipped, no shared data at {cs.DATA}")
        return rows
    tool = cs.DATA.parent / "tools" / "realism.py"
    for source, (args, refs, _) in cs.SOURCES.items():
        # the positions of the given T and Td, flags and values
        given = {i + d for i, a in enumerate(args) if a in ("--period", "--double-support")
                 for d in (0, 1)}  # fmt: skip
        predicted = [a for i, a in enumerate(args) if i not in given]
        for mode in ("atlas", "solve"):
            extra = ["--period", "auto", "--double-support", "auto", "--descriptors-from", mode]
            row = cs.run_one("natural", source, 0, root / mode, args=predicted + extra)
            summary = json.loads((root / mode / "natural" / source / "summary.json").read_text())
            d = summary["descriptors"]
            row.update(mode=mode, period_s=d["period"], double_support_s=d["double_support"],
                       predicted_by=d.get("predicted_by"))  # fmt: skip
            if source == "falisse" and tool.is_file():
                out = subprocess.run([sys.executable, str(tool), str(root / mode / "natural" /
                                      source), refs[0], "--json"], capture_output=True,
                                     text=True)  # fmt: skip
                row["yardstick"] = json.loads(out.stdout) if out.returncode == 0 else None
            rows.append(row)
            print(json.dumps({k: v for k, v in row.items() if k not in ("yardstick", "objective")}),
                  flush=True)  # fmt: skip
    return rows


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--modes",
        nargs="+",
        default=["atlas", "solve", "given"],
        help="atlas / solve: T and Td predicted that way; given: T and Td given",
    )
    ap.add_argument("--cache", help="model cache folder to use (default: a new one, filled first)")
    ap.add_argument("--parts", nargs="+", default=["timing", "realism"])
    ap.add_argument(
        "--compile",
        action="store_true",
        help="run `walk3d compile` for both sexes after filling the cache (timed)",
    )
    ap.add_argument(
        "--compile-later",
        action="store_true",
        help="the default path: the cache-filling runs start walk3d predict's background "
        "compile, which is waited for (timed) before the sets run",
    )
    environment.add_output_arguments(ap, NAME)
    args = ap.parse_args(argv)
    rows, real, compile_s = [], [], {}
    with tempfile.TemporaryDirectory(prefix="walk3d-one-solve-") as tmp:
        root = Path(tmp)
        if "realism" in args.parts:
            real = realism(root / "realism")
        cache = Path(args.cache) if args.cache else root / "cache"
        if "timing" not in args.parts:
            args.modes = []
        for sex in ("female", "male") if args.modes else ():  # fill the cache: not counted
            fill = run(root / f"fill-{sex}", ["--sex", sex], cache, args.compile_later)
            if args.compile_later:
                waited = environment.wait_for_background_compile(cache)
                compile_s[sex] = {"fill": fill, "background_compile_waited_s": waited}
                print(f"background compile, {sex}: {compile_s[sex]}", flush=True)
            if args.compile:
                compile_s[sex] = compile_for(sex, cache)
                print(f"walk3d compile --sex {sex}: {compile_s[sex]}", flush=True)
        for name, (v, m, h, sex, t, td) in SETS.items():
            common = ["--speed", str(v), "--mass", str(m), "--height", str(h), "--sex", sex]
            for mode in args.modes:
                extra = (["--period", str(t), "--double-support", str(td)] if mode == "given"
                         else ["--descriptors-from", mode])  # fmt: skip
                row = {"set": name, "mode": mode, **run(root / f"{name}-{mode}", common + extra,
                                                         cache, args.compile_later)}  # fmt: skip
                rows.append(row)
                print(json.dumps(row), flush=True)
    medians = {m: statistics.median(r["wall_s"] for r in rows if r["mode"] == m)
               for m in args.modes}  # fmt: skip
    print(f"median end-to-end wall time, s: {medians}")
    result = {environment.KEY: environment.environment(), "sets": SETS, "runs": rows,
              "median_wall_s": medians, "compile": compile_s, "realism": real}  # fmt: skip
    path = environment.output_path(args, NAME)
    environment.write(path, result)
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
