"""benchmarks/compare.py separates the machine's speed (starts on the same path) from the code's
changes (starts whose iterations changed), and shows where both results ran
(benchmarks/environment.py's header)."""

import importlib.util
import json
import sys
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parents[2] / "benchmarks"


def _load(name):
    spec = importlib.util.spec_from_file_location(f"benchmark_{name}", BENCHMARKS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _module():
    return _load("compare")


@pytest.fixture
def env_module():
    if str(BENCHMARKS) not in sys.path:
        sys.path.insert(0, str(BENCHMARKS))
    import environment

    return environment


def _run(seed, iterations, time_s, converged=True):
    return {"seed": seed, "iterations": iterations, "wall_time_s": time_s,
            "converged": converged, "criterion": 1.0}  # fmt: skip


def _header(**changes):
    env = {"commit": "abc1234", "dirty": False, "cpu": "AMD EPYC", "cores": 2,
           "python": "3.11.7", "numpy": "2.4.6", "scipy": "1.17.1", "casadi": "3.8.2",
           "ipopt": "3.14.19", "mumps": "5.8.2", "blas": "scipy-openblas32 (Haswell)",
           "date": "2026-11-23T14:25:05Z", "solve_revision": 12}  # fmt: skip
    return {**env, **changes}


OLD = [_run(0, 100, 20.0), _run(1, 200, 40.0), _run(2, 300, 60.0), _run(3, 900, 200.0)]
# the machine 10 % faster; seed 3's path changed (fewer iterations)
NEW = [_run(0, 100, 18.0), _run(1, 200, 36.0), _run(2, 300, 54.0), _run(3, 500, 90.0)]


def _write(path, runs, env=None, **top):
    data = {"runs": runs, **top}
    if env is not None:
        data["environment"] = env
    path.write_text(json.dumps(data))
    return path


def test_the_same_path_measures_the_machine(tmp_path, capsys):
    paths = [_write(tmp_path / "old.json", OLD), _write(tmp_path / "new.json", NEW)]
    mod = _module()
    c = mod.compare(mod._runs(str(paths[0])), mod._runs(str(paths[1])))
    assert c["same_path"] == [0, 1, 2] and c["changed"] == [3]
    assert c["machine_ratio"] == pytest.approx(0.9)
    assert c["median_old_s"] == pytest.approx(50.0) and c["median_new_s"] == pytest.approx(45.0)
    assert c["median_old_scaled_s"] == pytest.approx(45.0)
    # old-format files (no environment header) are read: both say so, no header table
    assert mod.main([str(p) for p in paths]) == 0
    out = capsys.readouterr().out
    assert "changed" in out and out.count("written before the environment header") == 2
    assert "differs" not in out


def test_headers_side_by_side_mark_what_differs(tmp_path, capsys):
    old = _write(tmp_path / "old.json", OLD, _header())
    new = _write(tmp_path / "new.json", NEW, _header(commit="def5678", dirty=True))
    mod = _module()
    assert mod.main([str(old), str(new)]) == 0
    lines = capsys.readouterr().out.splitlines()
    by_field = {line.split()[0]: line for line in lines if line.split()}
    assert "abc1234" in by_field["commit"] and "def5678 (dirty)" in by_field["commit"]
    assert by_field["commit"].endswith("differs")
    for field in ("cpu", "casadi", "ipopt", "mumps", "blas", "solve_revision"):
        assert field in by_field and not by_field[field].endswith("differs")
    assert "3.14.19" in by_field["ipopt"] and "5.8.2" in by_field["mumps"]


def test_a_difference_in_a_field_is_not_missed():
    """Negative control: the header rows flag a changed field, and only that one."""
    mod = _module()
    same = mod.header_rows(_header(), _header())
    assert not any(differs for *_, differs in same)
    other = mod.header_rows(_header(), _header(ipopt="3.14.17", cpu="Intel Xeon"))
    assert {field for field, *_, differs in other if differs} == {"ipopt", "cpu"}


def test_an_old_result_shows_what_it_recorded(tmp_path):
    mod = _module()
    old = json.loads(_write(tmp_path / "o.json", OLD, solve_revision=11, blas="x").read_text())
    new = {"runs": NEW, "environment": _header()}
    rows = mod.header_rows(mod.header(old), mod.header(new))
    rows = {field: (a, b, d) for field, a, b, d in rows}
    assert rows["solve_revision"] == ("11", "12", True)
    assert rows["cpu"] == ("-", "AMD EPYC", False)  # not recorded: not a difference
    assert rows["blas"][0] == "x"


def test_defaults_compare_the_reference_with_the_newest_run(tmp_path, capsys, env_module):
    mod = _module()
    ref_dir, runs = tmp_path / "reference", tmp_path / "runs"
    ref_dir.mkdir()
    runs.mkdir()
    ref = _write(ref_dir / "run.json", OLD, _header())
    with pytest.raises(SystemExit, match="no raw run"):
        mod.resolve([], ref_dir, runs)
    _write(runs / "run-20261201T100000Z.json", OLD, _header())
    newest = _write(runs / "run-20261201T120000Z.json", NEW, _header(commit="def5678"))
    _write(runs / "campaign-20261201T130000Z.json", [], _header())  # another benchmark's
    assert mod.resolve([], ref_dir, runs) == [ref, newest]
    assert mod.resolve([str(tmp_path / "x.json")], ref_dir, runs) == [ref, tmp_path / "x.json"]
    assert mod.resolve(["a", "b"]) == [Path("a"), Path("b")]
    with pytest.raises(SystemExit, match="no reference"):
        mod.resolve([], tmp_path / "nowhere", runs)


def test_outputs_go_to_runs_or_the_reference(tmp_path, monkeypatch, env_module):
    import argparse

    monkeypatch.setattr(env_module, "RUNS", tmp_path / "runs")
    monkeypatch.setattr(env_module, "REFERENCE", tmp_path / "reference")
    ap = argparse.ArgumentParser()
    env_module.add_output_arguments(ap, "physics")
    raw = env_module.output_path(ap.parse_args([]), "physics")
    assert raw.parent == tmp_path / "runs" and raw.name.startswith("physics-")
    assert raw.name.endswith("Z.json") and raw.parent.is_dir()
    ref = env_module.output_path(ap.parse_args(["--reference"]), "physics")
    assert ref == tmp_path / "reference" / "physics.json"
    out = env_module.output_path(ap.parse_args(["--out", str(tmp_path / "o" / "x.json")]), "p")
    assert out == tmp_path / "o" / "x.json"
    env_module.write(ref, {"a": 1})
    assert json.loads(ref.read_text()) == {"a": 1}


def test_the_environment_header(env_module):
    assert env_module.parse_banner(
        "This is Ipopt version 3.14.19, running with linear solver MUMPS 5.8.2.\n"
    ) == ("3.14.19", "MUMPS", "5.8.2")
    assert env_module.parse_banner("no banner") == (None, None, None)
    env = env_module.environment(blas="test BLAS")
    assert set(env_module.FIELDS) <= set(env)
    assert env["blas"] == "test BLAS" and env["cores"] >= 1
    assert env["date"].endswith("Z") and env["date"][4] == "-"
    assert env["ipopt"] and env["ipopt"][0].isdigit()  # read from IPOPT itself or CasADi's build
    assert env["casadi"] and env["solve_revision"] is not None
    assert env["commit"] is None or len(env["commit"]) >= 7


def test_the_committed_references_carry_the_header():
    for name in ("run", "campaign"):
        data = json.loads((BENCHMARKS / "reference" / f"{name}.json").read_text())
        assert set(data["environment"]) >= set(_header()), name
        assert data["runs"]


def test_results_of_other_settings_are_named(tmp_path, capsys):
    """Two results that ran other settings compare other problems: the differing settings are
    printed (grouped settings against the flat ones of an older result)."""
    from walk3d.problem.settings import PredictionSettings

    old = PredictionSettings(nodes=20)
    new = old.replace(nodes=12)
    cmp = _module()
    assert cmp.settings_differences({"settings": old.flat()}, {"settings": new.model_dump()}) == [
        ("nodes", 20, 12)
    ]
    assert cmp.settings_differences({"settings": old.flat()}, {"settings": old.model_dump()}) == []
    a = _write(tmp_path / "a.json", OLD, _header(), settings=old.flat())
    b = _write(tmp_path / "b.json", NEW, _header(), settings=new.model_dump())
    cmp.main([str(a), str(b)])
    assert "settings differ: nodes: old 20, new 12" in capsys.readouterr().out
