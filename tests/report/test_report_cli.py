"""``walk3d report DIR``: writes the page and lists it in the manifest; bad input gives one line
and exit code 2. ``walk3d predict`` and ``walk3d campaign`` end with the page."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys

import pytest
from report_support import make_campaign, make_prediction

from walk3d.report.writer import write_report
from walk3d.results.prediction import check_complete


def _report(*args, env=None):
    env = os.environ | {"MPLBACKEND": "Agg", "COLUMNS": "200"} | (env or {})
    cmd = [sys.executable, "-m", "walk3d.cli", "report", *map(str, args)]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=120, env=env)


def test_cli_writes_the_page_into_the_folder_and_its_manifest(fresh_folder):
    r = _report(fresh_folder)
    assert r.returncode == 0, r.stderr
    assert "walk3d report ->" in r.stdout and "(prediction," in r.stdout
    files = json.loads((fresh_folder / "manifest.json").read_text())["files"]
    assert files["report.html"] == (fresh_folder / "report.html").stat().st_size


def test_cli_without_measured_data_still_writes_the_page(fresh_folder, tmp_path):
    r = _report(fresh_folder, "--out", tmp_path / "r.html", env={"WALK3D_SHARED_DATA": "/none"})
    assert r.returncode == 0, r.stderr
    assert "no measured bands found" in r.stdout
    assert "No measured normative data found" in (tmp_path / "r.html").read_text(encoding="utf-8")
    assert not (fresh_folder / "report.html").exists()  # --out elsewhere


def test_cli_makes_a_deleted_report_again(fresh_folder, tmp_path):
    """report.html listed in the manifest, then deleted: the folder was refused as incomplete;
    like walk3d animate for its video, report makes the view again. Control: another listed
    view deleted (animation.mp4) still makes the folder incomplete."""
    assert _report(fresh_folder).returncode == 0
    (fresh_folder / "report.html").unlink()
    r = _report(fresh_folder)
    assert r.returncode == 0, r.stderr
    check_complete(fresh_folder)  # listed in the manifest again, with its new size
    (fresh_folder / "report.html").unlink()
    assert write_report(fresh_folder, data="/none")[1] == fresh_folder / "report.html"  # API
    other = tmp_path / "other"
    shutil.copytree(fresh_folder, other)
    files = json.loads((other / "manifest.json").read_text())
    files["files"]["animation.mp4"] = 3
    (other / "manifest.json").write_text(json.dumps(files))
    r = _report(other)
    assert r.returncode == 2 and "animation.mp4 is missing" in r.stderr, r.stderr


def test_a_deleted_summary_png_is_accepted_by_every_reader(fresh_folder, tmp_path):
    """summary.png, listed then deleted, made the folder unusable (exit 2 'incomplete') though
    no command reads it; report, animate and validate read it now. Control above."""
    from walk3d.results.prediction import load_result

    folder = shutil.copytree(fresh_folder, tmp_path / "r")
    files = json.loads((folder / "manifest.json").read_text())
    files["files"]["summary.png"] = 3
    (folder / "manifest.json").write_text(json.dumps(files))
    check_complete(folder)
    assert load_result(folder).n_nodes > 10  # what validate, verify and animate read
    r = _report(folder, "--out", tmp_path / "x" / "new" / "r.html")  # F: a missing folder made
    assert r.returncode == 0 and (tmp_path / "x" / "new" / "r.html").is_file(), r.stderr
    assert not (folder / "summary.png").exists()


def test_report_out_that_cannot_be_written_names_the_page(fresh_folder, tmp_path):
    """It named a hidden temporary file, or gave '[Errno 2]' alone; now exit 3 naming --out."""
    (tmp_path / "ro").mkdir()
    (tmp_path / "ro" / "f").write_text("a file")
    r = _report(fresh_folder, "--out", tmp_path / "ro" / "f" / "r.html")
    lines = r.stderr.strip().splitlines()
    assert r.returncode in (2, 3) and len(lines) == 1 and "Traceback" not in r.stderr, r.stderr
    assert str(tmp_path / "ro" / "f" / "r.html") in lines[0] and ".tmp" not in lines[0], lines


@pytest.mark.parametrize("case", ["missing", "neither", "no_manifest", "bad_out", "bad_data"])
def test_cli_bad_input_one_line_exit_2(result_folder, tmp_path, case):
    args = {
        "missing": [tmp_path / "none"],
        "neither": [tmp_path],
        "no_manifest": [tmp_path / "broken"],
        "bad_out": [result_folder, "--out", tmp_path / "r.txt"],
        "bad_data": [result_folder, "--data", tmp_path],
    }[case]
    if case == "no_manifest":
        shutil.copytree(result_folder, tmp_path / "broken")
        (tmp_path / "broken" / "manifest.json").unlink()
    r = _report(*args)
    assert r.returncode == 2, (r.stdout, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("walk3d: error:"), r.stderr
    assert "Traceback" not in r.stderr
    assert not (result_folder / "report.html").exists()


def test_predict_writes_the_report_into_its_finished_folder(evaluated, tmp_path):
    import walk3d

    settings, body, ev = evaluated
    out = walk3d.Prediction.of(make_prediction(settings, ev, converged=True)).save(
        tmp_path / "o", figure=False
    )
    check_complete(out)
    assert "report.html" in json.loads((out / "manifest.json").read_text())["files"]
    page = (out / "report.html").read_text(encoding="utf-8")
    assert f"walk3d animate {out}" in page and ".tmp_" not in page  # named as the final folder


def test_campaign_command_ends_with_the_report(result_folder, tmp_path):
    from walk3d.cli.campaign_command import _write_report

    out = make_campaign(tmp_path / "c", result_folder, {0: True}, 1)
    _write_report(str(out))
    page = (out / "report.html").read_text(encoding="utf-8")
    assert page.startswith("<!DOCTYPE html>") and "Best converged start: seed 0" in page
    kind, path = write_report(out, out=tmp_path / "again.html")
    assert kind == "campaign" and path.read_text(encoding="utf-8") == page


def test_a_report_that_fails_leaves_the_result_and_warns(evaluated, tmp_path, monkeypatch):
    import walk3d.report.writer
    from walk3d.pipeline import write_result
    from walk3d.report.writer import ReportWarning, write_report_or_warn

    def broken(*args, **kwargs):
        raise RuntimeError("no page\ntoday")

    monkeypatch.setattr(walk3d.report.writer, "prediction_page", broken)
    settings, body, ev = evaluated
    out = write_result(make_prediction(settings, ev, converged=True), tmp_path / "o",
                       figure=False, body=body)  # fmt: skip
    with pytest.warns(ReportWarning, match="report.html not written in .*: no page today"):
        assert write_report_or_warn(out) is None
    check_complete(out)  # the solved result stands
    assert "report.html" not in json.loads((out / "manifest.json").read_text())["files"]


def test_odd_types_in_a_folder_are_one_line_exit_2_and_text_is_escaped(result_folder, tmp_path):
    from walk3d.results.prediction import record_file

    folder = tmp_path / "odd"
    shutil.copytree(result_folder, folder)
    summary = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
    (folder / "summary.json").write_text(json.dumps(summary | {"status": "<script>x</script>"}))
    record_file(folder, "summary.json")
    assert _report(folder).returncode == 0
    page = (folder / "report.html").read_text(encoding="utf-8")
    assert "<script>" not in page and "&lt;script&gt;" in page  # escaped, not run
    odd = summary | {"descriptors": {**summary["descriptors"], "predicted": 5}}
    (folder / "summary.json").write_text(json.dumps(odd))
    record_file(folder, "summary.json")
    r = _report(folder)
    assert r.returncode == 2, (r.stdout, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "unexpected content" in lines[0] and "Traceback" not in r.stderr


@pytest.mark.parametrize("rel", ["report.html", "sub/page.html"])
def test_a_page_inside_another_result_folder_is_refused(fresh_folder, tmp_path, capsys, rel):
    """report A --out B/report.html replaced B's page with A's, and B's manifest then listed
    the wrong size; the control writes A's page into A itself (its own, listed there)."""
    from helpers import cli, one_line_error

    other = shutil.copytree(fresh_folder, tmp_path / "other")
    refused = cli(capsys, "report", fresh_folder, "--out", other / rel)
    one_line_error(refused, f"--out {other / rel} is inside the walk3d result folder {other}")
    assert not (other / "report.html").exists() and not (other / "sub").exists()
    check_complete(other)
    code, _, err = cli(capsys, "report", fresh_folder, "--out", fresh_folder / "report.html")
    assert code == 0, err
    files = json.loads((fresh_folder / "manifest.json").read_text())["files"]
    assert files["report.html"] == (fresh_folder / "report.html").stat().st_size
