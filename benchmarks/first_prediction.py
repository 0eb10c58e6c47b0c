"""The README's first command, timed end to end: ``python benchmarks/first_prediction.py
[--repeats 1] [--compile-later] [-- EXTRA walk3d predict OPTIONS]``.

Runs ``walk3d predict --out DIR`` as a new user does, in a fresh process, first with an empty
model cache (``WALK3D_CACHE_DIR`` a new folder: the model is built), then ``--repeats`` times
with that cache warm. Nothing is compiled (``WALK3D_COMPILE_LATER=0``), unless
``--compile-later`` (``walk3d predict``'s default): then the cold run starts the background
compile, and the warm runs wait for it (timed) and use it. It records, per run, the wall time
from process start to exit, the exit code, convergence, iterations, the predicted T and Td,
``looks_like_walking`` and whether the derivatives were compiled, from ``summary.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

_HERE = str(Path(__file__).resolve().parent)
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)
import environment  # noqa: E402

NAME = "first_prediction"


def one_run(out: Path, cache: Path, extra: list[str], later: bool = False) -> dict:
    """``walk3d predict --out out`` in a child process with the model cache at ``cache``;
    ``later``: with its background compile (else ``WALK3D_COMPILE_LATER=0``)."""
    env = dict(os.environ, WALK3D_CACHE_DIR=str(cache), OPENBLAS_NUM_THREADS="1",
               WALK3D_COMPILE_LATER="1" if later else "0")  # fmt: skip
    cmd = [sys.executable, "-m", "walk3d.cli", "predict", "--out", str(out), *extra]
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    row = {"wall_s": round(wall, 2), "exit_code": proc.returncode}
    summary = out / "summary.json"
    if summary.is_file():
        s = json.loads(summary.read_text())
        d = s.get("descriptors", {})
        row.update(
            converged=s.get("converged"),
            iterations=s.get("iterations"),
            compiled=bool(s.get("compiled_derivatives")),
            period_s=d.get("period"),
            double_support_s=d.get("double_support"),
            looks_like_walking=s.get("gait_checks", {}).get("looks_like_walking"),
        )
    else:
        row["stderr_tail"] = proc.stderr[-400:]
    return row


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=1, help="warm-cache runs after the cold one")
    ap.add_argument("--compile-later", action="store_true",
                    help="walk3d predict's default: the cold run starts the background compile, "
                    "which is waited for (timed) before the warm runs")  # fmt: skip
    ap.add_argument("extra", nargs="*", help="more walk3d predict options, after --")
    environment.add_output_arguments(ap, NAME)
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="walk3d-first-") as tmp:
        root = Path(tmp)
        cache = root / "cache"
        later = args.compile_later
        runs = [{"cache": "empty", **one_run(root / "cold", cache, args.extra, later)}]
        print(f"cold cache: {runs[0]}", flush=True)
        if later:
            runs[0]["background_compile_waited_s"] = environment.wait_for_background_compile(cache)
            print(f"background compile: {runs[0]['background_compile_waited_s']} s", flush=True)
        for k in range(args.repeats):
            runs.append({"cache": "warm", **one_run(root / f"warm{k}", cache, args.extra, later)})
            print(f"warm cache: {runs[-1]}", flush=True)
    result = {
        environment.KEY: environment.environment(),
        "command": ["walk3d", "predict", "--out", "DIR", *args.extra],
        "runs": runs,
    }
    path = environment.output_path(args, NAME)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(result, indent=2) + "\n")
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
