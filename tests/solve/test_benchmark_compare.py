"""benchmarks/compare.py separates the machine's speed (starts on the same path) from the code's
changes (starts whose iterations changed)."""

import importlib.util
import json
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "compare.py"


def _module():
    spec = importlib.util.spec_from_file_location("benchmark_compare", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _run(seed, iterations, time_s, converged=True):
    return {"seed": seed, "iterations": iterations, "wall_time_s": time_s,
            "converged": converged, "criterion": 1.0}  # fmt: skip


def test_the_same_path_measures_the_machine(tmp_path, capsys):
    old = [_run(0, 100, 20.0), _run(1, 200, 40.0), _run(2, 300, 60.0), _run(3, 900, 200.0)]
    # the machine 10 % faster; seed 3's path changed (fewer iterations)
    new = [_run(0, 100, 18.0), _run(1, 200, 36.0), _run(2, 300, 54.0), _run(3, 500, 90.0)]
    paths = []
    for name, runs in (("old", old), ("new", new)):
        paths.append(tmp_path / f"{name}.json")
        paths[-1].write_text(json.dumps({"runs": runs}))
    mod = _module()
    c = mod.compare(mod._runs(str(paths[0])), mod._runs(str(paths[1])))
    assert c["same_path"] == [0, 1, 2] and c["changed"] == [3]
    assert c["machine_ratio"] == pytest.approx(0.9)
    assert c["median_old_s"] == pytest.approx(50.0) and c["median_new_s"] == pytest.approx(45.0)
    assert c["median_old_scaled_s"] == pytest.approx(45.0)
    assert mod.main([str(p) for p in paths]) == 0
    assert "changed" in capsys.readouterr().out
