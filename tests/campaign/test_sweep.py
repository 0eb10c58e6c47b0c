"""walk3d sweep: the speed range and its errors, the solving order, and a tiny real sweep that
writes its folder, table and figure and resumes (convergence is not expected)."""

import csv
import json
import subprocess
import sys

import numpy as np
import pytest

from walk3d.campaign.sweep import (
    COLUMNS,
    SweepMismatch,
    parse_speeds,
    run_sweep,
    speed_folder,
    sweep_order,
)
from walk3d.problem import descriptors
from walk3d.problem.settings import PredictionSettings


def test_speed_ranges_include_their_stop():
    np.testing.assert_allclose(parse_speeds("0.8:1.8:0.1"), np.arange(8, 19) / 10)
    np.testing.assert_allclose(parse_speeds("1.4,1.0,1.2"), [1.0, 1.2, 1.4])
    assert parse_speeds("1.3:1.3:0.1").tolist() == [1.3]


@pytest.mark.parametrize(
    ("text", "word"),
    [("1.8:0.8:0.1", "empty or reversed"), ("1:2:0", "empty or reversed"),
     ("0:1:0.5", "(0, 4]"), ("3:5:1", "(0, 4]"), ("fast", "expected start:stop:step"),
     ("1:2", "expected start:stop:step"), ("", "no speed"), ("1,1", "1 m/s is given twice"),
     ("1.0,1.2,1.0", "given twice"), ("1.2,1.2004", "closer than 0.001 m/s"),
     ("0.1:4:1e-10", "3.9e+10 speeds, at most 41"), ("1:3:0.048", "42 speeds, at most 41"),
     ("0.5:4:1e-300", "speeds, at most 41"), (",".join(["1.0"] * 50), "50 speeds"),
     ("1.2,,1.3", "an empty item"), ("1.2,1.3,", "an empty item"), (",1.2", "an empty item"),
     ("1.2, ,1.3", "an empty item"), (",", "an empty item"), ("  ", "no speed")],
)  # fmt: skip
def test_bad_speed_ranges_are_refused(text, word):
    with pytest.raises(ValueError, match="--speeds") as info:
        parse_speeds(text)
    assert word in str(info.value)


@pytest.mark.parametrize(
    "text", ["1.8:0.8:0.1", "0:1:0.5", "1,nan", "x", "0.1:4:1e-10", "1.0,1.0", "1.2,,1.3"]
)
def test_cli_refuses_a_bad_range_with_one_line_and_exit_2(tmp_path, text):
    cmd = [sys.executable, "-m", "walk3d.cli", "sweep", "--speeds", text, "--out",
           str(tmp_path / "s")]  # fmt: skip
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1 and "--speeds" in r.stderr
    assert not (tmp_path / "s").exists()


def test_the_largest_ranges_and_the_nearest_speeds_allowed_pass():
    """Negative control of the count and folder checks: 41 speeds, 0.001 m/s apart."""
    assert parse_speeds("1:3:0.05").size == 41 and parse_speeds("1:3:0.0499").size == 41
    assert parse_speeds("1.2,1.201").tolist() == [1.2, 1.201]
    assert parse_speeds(",".join(f"{v / 10:.1f}" for v in range(6, 21))).size == 15
    assert parse_speeds(" 1.2 , 1.3 ").tolist() == [1.2, 1.3]  # spaces around items


def test_order_starts_near_the_pivot_and_each_speed_follows_a_solved_neighbour():
    speeds = parse_speeds("0.8:1.8:0.1")
    order = sweep_order(speeds)
    assert speeds[order[0][0]] == pytest.approx(1.3) and order[0][1] is None
    assert sorted(i for i, _ in order) == list(range(len(speeds)))
    seen = set()
    for i, nb in order:
        assert nb is None or (nb in seen and abs(nb - i) == 1)
        seen.add(i)


@pytest.mark.campaign
def test_a_tiny_sweep_writes_its_table_figure_and_folders_and_resumes(tmp_path):
    t, td = descriptors.first_guess(1.2, 1.77)
    tiny = PredictionSettings(nodes=6, max_iter=3, restarts=0, criterion="tor", speed=1.2,
                              period=t, double_support=td, free=descriptors.NAMES)  # fmt: skip
    speeds = np.array([1.2, 1.4])
    report = run_sweep(tiny, speeds, tmp_path / "s")
    assert report.ran == 2 and report.skipped == 0
    for v in speeds:
        summary = json.loads((speed_folder(tmp_path / "s", v) / "summary.json").read_text())
        d = summary["descriptors"]
        assert d["speed"] == v and d["predicted"] == ["period", "double_support"]
        assert d["cadence"] == pytest.approx(120 / d["period"])
        assert d["stride_length"] == pytest.approx(v * d["period"])
        assert d["stance_fraction"] == pytest.approx(0.5 + d["double_support"] / d["period"])
    with open(tmp_path / "s" / "sweep.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert [float(r["speed"]) for r in rows] == [1.2, 1.4] and list(rows[0]) == list(COLUMNS)
    assert all(r["converged"] == "False" for r in rows)  # 3 iterations cannot converge
    assert (tmp_path / "s" / "sweep.png").stat().st_size > 10_000
    again = run_sweep(tiny, speeds, tmp_path / "s")
    assert again.ran == 0 and again.skipped == 2
    other = tiny.model_copy(update={"model": tiny.model.model_copy(update={"criterion": "en"})})
    with pytest.raises(SweepMismatch):
        run_sweep(other, speeds, tmp_path / "s")


def test_a_failed_warm_start_goes_through_the_speed_halfway(monkeypatch):
    """The continuation logic on scripted solves: a warm start walks only across steps of at
    most 0.05 m/s, so 1.1 -> 1.0 goes through 1.05, and 1.1 -> 0.9 with one halving left fails
    (the sweep then solves from standing)."""
    import walk3d.pipeline as predict_module
    from walk3d.campaign import sweep as sweep_module

    class Fake:
        def __init__(self, summary):
            self.summary = summary

    def summary(v, ok, iterations=10):
        return {"descriptors": {"speed": v, "period": 1.1, "double_support": 0.12},
                "coefficients": {"x": [v]}, "converged": ok, "iterations": iterations,
                "wall_time_s": 1.0, "gait_checks": {"looks_like_walking": ok}}  # fmt: skip

    calls = []

    def fake_predict(settings, seed, solver, on_stage=None, warm_from=None):
        v, v0 = settings.gait.speed, float(warm_from[0])
        calls.append((v0, v))
        return Fake(summary(v, abs(v - v0) <= 0.05 + 1e-9))

    monkeypatch.setattr(predict_module, "predict", fake_predict)
    settings = PredictionSettings(free=descriptors.NAMES)
    pred = sweep_module._warm(settings, summary(1.1, True), 1.0, 0, "ipopt", print, 2)
    assert pred is not None and calls == [(1.1, 1.0), (1.1, 1.05), (1.05, 1.0)]
    assert pred.summary["sweep"]["via"] == [1.05] and pred.summary["sweep"]["from_speed"] == 1.1
    assert pred.summary["sweep"]["extra_iterations"] == 10
    calls.clear()
    assert sweep_module._warm(settings, summary(1.1, True), 0.9, 0, "ipopt", print, 1) is None
    assert calls == [(1.1, 0.9), (1.1, 1.0)]  # 1.0 itself would need one halving more


def test_the_second_pass_keeps_the_better_of_two_neighbours_starts(tmp_path, monkeypatch):
    """Scripted: each speed solved once more from its other neighbour keeps the lower criterion
    per metre; what was tried is recorded, so a resumed sweep does not try it again."""
    import walk3d.pipeline as predict_module
    from walk3d.campaign import sweep as sweep_module

    def summary(v, value, stride=1.0):
        return {"descriptors": {"speed": v, "period": 1.1, "double_support": 0.12,
                                "stride_length": stride},
                "coefficients": {"x": [v]}, "converged": True, "iterations": 5,
                "wall_time_s": 1.0, "gait_checks": {"looks_like_walking": True},
                "objective": {"C_tor": {"total": value}}}  # fmt: skip

    class Fake:
        def __init__(self, s):
            self.summary = s

    better_from = {(1.0, 1.1): 0.5}  # 1.0 m/s from 1.1: better; every other try: worse

    def fake_predict(settings, seed, solver, on_stage=None, warm_from=None):
        v, v0 = settings.gait.speed, float(warm_from[0])
        return Fake(summary(v, better_from.get((v, v0), 9.0)))

    written = []
    monkeypatch.setattr(predict_module, "predict", fake_predict)
    monkeypatch.setattr(predict_module, "write_result", lambda p, f: written.append(f.name))
    speeds = np.array([1.0, 1.1, 1.2])
    sums = {0: summary(1.0, 2.0), 1: summary(1.1, 2.0), 2: summary(1.2, 2.0)}
    first_from = {1: None, 0: 1, 2: 1}  # 1.1 first, then 1.0 and 1.2 from it
    settings = PredictionSettings(free=descriptors.NAMES, criterion="tor")
    report = sweep_module.SweepReport()
    args = (settings, speeds, tmp_path, sums, first_from, 0, "ipopt", None, report)
    sweep_module._second_pass(*args)
    # 1.0 has no other neighbour; 1.1 is tried from 1.0 and 1.2; 1.2 from nothing new
    tried = json.loads((tmp_path / "second_pass.json").read_text())
    assert set(tried) == {"1.100<1.000", "1.100<1.200"}
    assert written == [] and sums[1]["objective"]["C_tor"]["total"] == 2.0  # both were worse
    better_from[(1.1, 1.2)] = 1.0
    sweep_module._second_pass(*args)  # resumed: nothing tried again
    assert written == []
    (tmp_path / "second_pass.json").unlink()
    sweep_module._second_pass(*args)
    assert written == ["v_1.100"] and sums[1]["objective"]["C_tor"]["total"] == 1.0
    assert report.ran == 1
