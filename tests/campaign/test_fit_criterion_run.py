"""walk3d fit-criterion for real: one Winter trial, one weight, one generation of two
candidates on local Dask workers; every record is a scored prediction, the preset file is
read back by predict, and rerunning solves nothing."""

import json

import pytest
from helpers import shared_data_dir
from typer.testing import CliRunner

from walk3d.api import criterion_value
from walk3d.cli import app
from walk3d.model import terms

pytestmark = pytest.mark.campaign


@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    winter = shared_data_dir() / "winter" / "Winter_normal.csv"
    if not winter.is_file():
        pytest.skip(f"measured data not found at {winter} (set WALK3D_SHARED_DATA)")
    root = tmp_path_factory.mktemp("fit")
    (root / "trials.toml").write_text(
        f'[[trial]]\nname = "winter"\nspeed = 1.325\nperiod = 1.1396\n'
        f'double_support = 0.114\nreference = ["{winter}"]\n'
    )
    args = ["fit-criterion", str(root / "trials.toml"), "--parameter", "impact=1:25",
            "--generations", "1", "--popsize", "2", "--workers", "2",
            "--out", str(root / "f")]  # fmt: skip
    first = CliRunner().invoke(app, args)
    return root / "f", first, args


def test_every_candidate_is_a_scored_prediction(fitted):
    out, res, _ = fitted
    assert res.exit_code == 0, res.output
    records = [json.loads(p.read_text()) for p in (out / "evaluations").glob("*.json")]
    assert len(records) == 3  # the start and two candidates (the best is one of them)
    for r in records:
        assert r["converged"] and r["failed"] is None
        assert 0 < r["score"] < 5
        assert r["figures"]["angle:knee_flexion"] > 0
        assert terms.parse(r["criterion"])["tor"] == 1.0


def test_the_preset_file_is_the_best_and_predict_reads_it(fitted):
    out, _, _ = fitted
    result = json.loads((out / "result.json").read_text())
    assert result["best_score"] <= result["start_score"]
    assert terms.parse(criterion_value(str(out / "criterion.toml"))) == pytest.approx(
        terms.parse(result["best"])
    )


def test_rerun_solves_nothing(fitted):
    out, _, args = fitted
    before = {p.name: p.stat().st_mtime_ns for p in (out / "evaluations").iterdir()}
    again = CliRunner().invoke(app, args)
    assert again.exit_code == 0, again.output
    assert {p.name: p.stat().st_mtime_ns for p in (out / "evaluations").iterdir()} == before
