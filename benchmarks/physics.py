"""Kinematics + inverse dynamics for one cycle at 100 time nodes: ``python benchmarks/physics.py``.

Reports the median time of three implementations of the same physics (one gait evaluation with
the split ground reaction and all joint moments):

* NumPy, vectorized over the 100 nodes;
* the CasADi node function in CasADi's virtual machine, mapped over 100 nodes;
* the same node function compiled to C (gcc -O2, compiled once into a cache folder).

Results go to stdout and, as JSON, to ``benchmarks/runs/physics-<UTC time>.json``
(git-ignored), or with ``--reference`` to the committed ``benchmarks/reference/physics.json``;
the result's ``"environment"`` records where it ran (``benchmarks/environment.py``).
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import casadi as ca  # noqa: E402
import environment  # noqa: E402  (benchmarks/environment.py, next to this script)
import numpy as np  # noqa: E402

from walk3d.body.model import build_body  # noqa: E402
from walk3d.problem import nlp  # noqa: E402
from walk3d.problem.settings import PredictionSettings  # noqa: E402

N = 100
NAME = "physics"


def _median_ms(fn, repeat: int = 30) -> float:
    fn()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return 1000 * statistics.median(times)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=30, help="timed calls per implementation")
    environment.add_output_arguments(ap, NAME)
    args = ap.parse_args(argv)
    out = environment.output_path(args, NAME)
    header = environment.environment()
    s = PredictionSettings()
    body = build_body()
    rng = np.random.default_rng(0)
    y = rng.uniform(-0.1, 0.1, (nlp.N_Y, N))
    w0 = np.tile([[0.05], [1.0], [0.0], [0.0], [0.0], [0.02]], (1, N))
    hw = np.full((1, N), 0.08)
    omega = 2 * np.pi / s.gait.period
    p = np.vstack([np.linspace(1, 0, N), np.full(N, -0.7), np.full(N, omega)])
    t = np.zeros((nlp.N_T, N))  # the criterion's slacks (they do not change the work)

    def numpy_eval():
        st = nlp.state_at(body, list(y), list(w0), hw[0], p[0], p[1], omega)
        return nlp.node_outputs(body, s.model, st)

    node = nlp.node_function(body, s.model)
    mapped = node.map(N)
    numpy_ms = _median_ms(numpy_eval, args.repeat)
    vm_ms = _median_ms(lambda: mapped(y, w0, hw, p, t), args.repeat)
    print(f"NumPy, {N} nodes:                {numpy_ms:8.2f} ms")
    print(f"CasADi VM, {N} nodes:            {vm_ms:8.2f} ms")
    with tempfile.TemporaryDirectory() as tmp:
        cwd = os.getcwd()
        os.chdir(tmp)
        try:
            mapped_named = node.map("walk3d_node_map", "serial", N, [], [])
            mapped_named.generate("walk3d_node_map.c")
            t0 = time.perf_counter()
            subprocess.run(["gcc", "-O2", "-fPIC", "-shared", "walk3d_node_map.c", "-o",
                            "node.so", "-lm"], check=True)  # fmt: skip
            build = time.perf_counter() - t0
            compiled = ca.external("walk3d_node_map", str(Path(tmp) / "node.so"))
            ms = _median_ms(lambda: compiled(y, w0, hw, p, t), args.repeat)
        finally:
            os.chdir(cwd)
    print(f"compiled C (-O2), {N} nodes:     {ms:8.2f} ms   (compile once: {build:.1f} s)")
    result = {environment.KEY: header, "nodes": N, "repeat": args.repeat,
              "median_ms": {"numpy": numpy_ms, "casadi_vm": vm_ms, "compiled_c": ms},
              "compile_time_s": build}  # fmt: skip
    environment.write(out, result)
    print(f"written {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
