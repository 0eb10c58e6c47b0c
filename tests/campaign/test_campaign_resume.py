"""A campaign's resume reads each start folder through the verified result loader, without a
solve: the starts are copies of the atlas's 1.3 m/s result folder (``result_support``)."""

import contextlib
import json
import shutil
import warnings

import pytest
from helpers import cli, replace_result_file
from result_support import result_folder

import walk3d.campaign.runner as runner
from walk3d.campaign import rank, run_campaign, store
from walk3d.campaign.task import record_from_summary
from walk3d.problem.settings import PredictionSettings


@pytest.fixture(scope="module")
def source(tmp_path_factory):
    """A result folder of seed 0 and its settings."""
    folder = result_folder(tmp_path_factory.mktemp("pred") / "p")
    summary = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
    return folder, PredictionSettings(**summary["settings"])


def set_summary(folder, **changes):
    """Change ``folder``'s summary.json and list its new size in the manifest (a readable
    prediction of another problem, not a damaged folder)."""
    summary = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
    for key, value in changes.items():
        if key in ("mass", "speed"):
            summary["settings"]["gait"][key] = value
        else:
            summary[key] = value
    replace_result_file(folder, "summary.json", json.dumps(summary).encode())


def campaign_folder(out, source, seeds=(0, 1)):
    """A campaign folder of ``seeds`` whose starts are the source folder with that seed."""
    folder, settings = source
    store.open_campaign(out, settings, 0, len(seeds), "ipopt")
    for seed in seeds:
        tmp = store.new_temporary(store.starts_dir(out), store.start_name(seed))
        shutil.copytree(folder, tmp, dirs_exist_ok=True)
        set_summary(tmp, seed=seed)
        summary = json.loads((tmp / "summary.json").read_text(encoding="utf-8"))
        store.commit_start(tmp, seed, record_from_summary(summary, settings.model.criterion, 1))
    return out


@pytest.fixture
def no_solve(monkeypatch):
    """Pending seeds are recorded here instead of being solved."""
    ran = []
    monkeypatch.setattr(runner, "dask_client", lambda *a: contextlib.nullcontext())
    monkeypatch.setattr(runner, "_run_pending", lambda c, s, pending, *a: ran.extend(pending))
    return ran


def start_path(out, seed):
    return store.starts_dir(out) / store.start_name(seed)


def test_a_verified_resume_runs_nothing_and_copies_the_best(tmp_path, source, no_solve):
    out = campaign_folder(tmp_path / "c", source)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # nothing damaged, nothing rewritten
        report = run_campaign(source[1], 2, 0, out, progress=False)
    assert no_solve == [] and report.skipped == 2 and report.best_seed == 0
    assert (out / "best" / "result.npz").read_bytes() == (
        start_path(out, 0) / "result.npz"
    ).read_bytes()


@pytest.mark.parametrize(
    ("changes", "words"),
    [({"mass": 80.0}, "solved with mass 80.0"), ({"seed": 7}, "solved with seed 7, not 1")],
)
def test_a_start_folder_of_another_prediction_is_refused(tmp_path, source, no_solve, changes,
                                                         words):  # fmt: skip
    out = campaign_folder(tmp_path / "c", source)
    set_summary(start_path(out, 1), **changes)  # its record.json kept
    with pytest.raises(store.CampaignMismatch, match=words):
        run_campaign(source[1], 2, 0, out, progress=False)
    assert no_solve == [] and not (out / "best").exists()
    assert (start_path(out, 1) / "summary.json").is_file()  # not deleted


def test_the_cli_refuses_a_foreign_start_in_one_line(tmp_path, source, capsys, no_solve):
    out = campaign_folder(tmp_path / "c", source)
    set_summary(start_path(out, 1), mass=80.0)
    gait = source[1].gait  # the options of the stored campaign (the atlas's free landing)
    code, _, err = cli(capsys, "campaign", "--starts", 2, "--out", out, "--no-compile",
                       "--free-landing", "--speed", gait.speed, "--period", repr(gait.period),
                       "--double-support", repr(gait.double_support))  # fmt: skip
    assert code == 2 and err.count("\n") == 1 and "walk3d: error:" in err, err
    assert "seed_000001 holds a prediction that was solved with mass 80.0" in err, err


def test_a_damaged_start_is_run_again_with_a_warning(tmp_path, source, no_solve):
    out = campaign_folder(tmp_path / "c", source)
    summary = start_path(out, 0) / "summary.json"
    summary.write_text(summary.read_text(encoding="utf-8") + " ", encoding="utf-8")  # size off
    with pytest.warns(RuntimeWarning, match="seed_000000 cannot be read.*running seed 0 again"):
        report = run_campaign(source[1], 2, 0, out, progress=False)
    assert no_solve == [0] and not start_path(out, 0).exists()
    assert report.best_seed == 1  # the damaged start is not ranked nor copied


def test_the_ranking_takes_the_verified_value_not_the_record(tmp_path, source, no_solve):
    out = campaign_folder(tmp_path / "c", source)
    path = start_path(out, 1) / "record.json"
    record = json.loads(path.read_text(encoding="utf-8"))
    true_value = record["criterion_value"]
    path.write_text(json.dumps(record | {"criterion_value": -100.0}), encoding="utf-8")
    with pytest.warns(RuntimeWarning, match="record.json did not match its result "
                      r"\(criterion_value\): rewritten"):  # fmt: skip
        report = run_campaign(source[1], 2, 0, out, progress=False)
    assert report.best_seed == 0  # a tie, broken by seed: the edit changes nothing
    assert [r["criterion_value"] for r in report.rows] == [true_value, true_value]
    assert json.loads(path.read_text(encoding="utf-8")) == record  # the report reads it
    assert [r["criterion_value"] for r in rank(out)] == [true_value, true_value]


def test_a_record_only_start_that_claims_convergence_is_run_again(tmp_path, source, no_solve):
    out = campaign_folder(tmp_path / "c", source, seeds=(0,))
    store.open_campaign(out, source[1], 0, 2, "ipopt")
    tmp = store.new_temporary(store.starts_dir(out), store.start_name(1))
    store.commit_start(tmp, 1, {"seed": 1, "status": "Solve_Succeeded", "converged": True,
                                "criterion_value": -1.0})  # fmt: skip
    with pytest.warns(RuntimeWarning, match="holds no result"):
        run_campaign(source[1], 2, 0, out, progress=False)
    assert no_solve == [1]
