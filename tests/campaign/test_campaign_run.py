"""A real 6-start campaign on a local 2-worker Dask cluster (tiny settings: about a second per
start once a worker has built its model; convergence is not expected and not needed)."""

import csv
import json

import pytest

from walk3d.campaign import rank, run_campaign, store
from walk3d.campaign.task import FAIL_ENV
from walk3d.problem.settings import PredictionSettings

pytestmark = pytest.mark.campaign

TINY = PredictionSettings(nodes=6, max_iter=3, restarts=0)  # no start converges: no restarts
SEEDS = list(range(10, 16))
FAILING = 12


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    out = tmp_path_factory.mktemp("campaign") / "c"
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv(FAIL_ENV, str(FAILING))  # inherited by the spawned worker processes
        report = run_campaign(TINY, 6, SEEDS[0], out, workers=2, progress=False)
    return out, report


def test_every_start_is_stored_once(campaign):
    out, report = campaign
    folders = sorted(p.name for p in store.starts_dir(out).iterdir())
    assert folders == [store.start_name(s) for s in SEEDS]
    assert report.ran == 6 and report.skipped == 0
    assert sorted(r["seed"] for r in report.rows) == SEEDS
    for seed in SEEDS:
        rec = json.loads(
            (store.starts_dir(out) / store.start_name(seed) / "record.json").read_text()
        )
        assert rec["seed"] == seed
        if seed != FAILING:
            summary = json.loads(
                (store.starts_dir(out) / store.start_name(seed) / "summary.json").read_text()
            )
            assert summary["seed"] == seed
            folder = store.starts_dir(out) / store.start_name(seed)
            assert (folder / "summary.png").stat().st_size > 10_000  # a full predict folder
            assert rec["criterion_value"] == summary["objective"]["C_tor"]["total"]
    stored = json.loads((out / "campaign.json").read_text())
    assert stored["settings"] == store.clean_json(TINY.model_dump())  # JSON: tuples as lists
    assert stored["base_seed"] == SEEDS[0]


def test_raising_task_is_recorded_and_the_campaign_continues(campaign):
    out, report = campaign
    folder = store.starts_dir(out) / store.start_name(FAILING)
    rec = json.loads((folder / "record.json").read_text())
    assert rec["converged"] is False
    assert rec["status"].startswith("error: RuntimeError: injected failure")
    assert "\n" not in rec["status"]
    assert (folder / "traceback.txt").is_file() and not (folder / "summary.json").exists()
    assert report.errors == 1
    assert sum(1 for r in report.rows if not r["status"].startswith("error")) == 5


def test_each_worker_builds_the_model_once(campaign):
    _, report = campaign
    records = [store.read_record(store.starts_dir(report.out_dir) / store.start_name(s))
               for s in SEEDS if s != FAILING]  # fmt: skip
    # task time = model build (first start on a worker only) + solve + evaluation + writing
    overhead = [r["task_time_s"] - r["wall_time_s"] for r in records]
    assert sum(1 for o in overhead if o > 3.0) <= 2, overhead


def test_ranking_csv_is_ordered(campaign):
    out, report = campaign
    with open(out / "ranking.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [int(r["seed"]) for r in rows] == [r["seed"] for r in rank(out)]
    assert [int(r["rank"]) for r in rows] == list(range(1, 7))
    conv = [r["converged"] == "true" for r in rows]
    assert conv == sorted(conv, reverse=True)  # converged first
    for group in (True, False):
        values = [float(r["criterion_value"]) for r, c in zip(rows, conv, strict=True)
                  if c is group and r["criterion_value"]]  # fmt: skip
        assert values == sorted(values)
    assert rows[-1]["seed"] == str(FAILING)  # no criterion value: last
    assert (out / "best").exists() == any(conv)


def test_resume_of_a_finished_campaign_runs_nothing(campaign):
    out, _ = campaign
    before = {p: p.read_bytes() for p in store.starts_dir(out).rglob("*") if p.is_file()}
    report = run_campaign(TINY, 6, SEEDS[0], out, workers=2, progress=False)
    assert report.ran == 0 and report.skipped == 6
    after = {p: p.read_bytes() for p in store.starts_dir(out).rglob("*") if p.is_file()}
    assert after == before
