"""Writing a result folder from the Python API: the output check of ``walk3d predict --out``
(one function for both), nothing of the user's ever deleted, a full disk as one OSError line
with the earlier result intact. No solve: the shipped atlas solution stands in."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest

import walk3d

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "verify"))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from disk_support import full_disk, snapshot  # noqa: E402


@pytest.fixture(scope="module")
def prediction():
    """The atlas solution at 1.3 m/s as an API Prediction."""
    from verify_support import atlas_prediction

    from walk3d import api

    return api.Prediction.of(atlas_prediction()[0])


def _save(pred, folder):
    return pred.save(folder, figure=False, report=False)


def test_save_refuses_a_folder_of_other_files_and_an_existing_file(prediction, tmp_path):
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "thesis.txt").write_text("four years of work")
    with pytest.raises(ValueError, match="folder of other files") as info:
        _save(prediction, mine)
    assert "\n" not in str(info.value) and str(mine) in str(info.value)
    assert [p.name for p in mine.iterdir()] == ["thesis.txt"]
    assert (mine / "thesis.txt").read_text() == "four years of work"
    paper = tmp_path / "paper.pdf"
    paper.write_bytes(b"%PDF")
    with pytest.raises(ValueError, match="existing file"):
        _save(prediction, paper)
    assert paper.read_bytes() == b"%PDF"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mine", "paper.pdf"]  # no temporary
    # control: a new folder, an empty one and an earlier result are written
    empty = tmp_path / "empty"
    empty.mkdir()
    for folder in (tmp_path / "new", empty, tmp_path / "new"):
        assert (_save(prediction, folder) / "manifest.json").is_file()


def test_the_cli_and_the_api_share_one_output_check(monkeypatch, tmp_path):
    import walk3d.outputs
    from walk3d.cli import common
    from walk3d.pipeline import check_result_folder

    calls = []
    real = walk3d.outputs.check_output_folder

    def spy(path, option="--out", replaces=None, own=None):
        calls.append((option, replaces, own))
        return real(path, option, replaces, own)

    monkeypatch.setattr(walk3d.outputs, "check_output_folder", spy)
    from walk3d.cli import main
    from walk3d.results.prediction import written_files

    with pytest.raises(SystemExit):  # the check passes; --nodes 1 stops before any solve
        main(["predict", "--out", str(tmp_path / "a"), "--nodes", "1"])
    check_result_folder(tmp_path / "a")
    assert calls == [("--out", "summary.json", written_files), ("out", "summary.json",
                                                                written_files)]  # fmt: skip
    (tmp_path / "x.txt").write_text("x")  # the same refusal, one line each
    with pytest.raises(ValueError) as api_error:
        check_result_folder(tmp_path)
    with pytest.raises(common.typer.Exit) as cli_exit:
        common.check_output_folder(str(tmp_path), replaces="summary.json")
    assert cli_exit.value.exit_code == 2 and "folder of other files" in str(api_error.value)


def _earlier_result(prediction, folder):
    """An earlier result with all that walk3d adds to it later: a report, a validation and
    the temporaries of an interrupted walk3d (a view's files built aside, a file writer's, a
    validation's folder with its owner file)."""
    _save(prediction, folder)
    (folder / "report.html").write_text("<html></html>")
    (folder / "validation").mkdir()
    for name in ("table2.csv", "grf.png"):
        (folder / "validation" / name).write_text("walk3d's")
    (folder / ".manifest.json.0123456789ab.tmp").mkdir()
    (folder / ".summary.json.0123456789ab.tmp").write_text("{")
    (folder / ".tmp_validation_0123456789ab").mkdir()
    (folder / ".tmp_validation_0123456789ab.owner").write_text("host 1 1\n")
    return folder


@pytest.mark.parametrize("foreign", ["notes.txt", "validation/notes.txt", "figures/"])
def test_save_refuses_an_earlier_result_holding_files_walk3d_did_not_write(
    prediction, tmp_path, foreign
):
    """The user's notes beside (or inside the validation of) an earlier result were deleted
    with it; now the folder is refused, naming them, and nothing is touched."""
    folder = _earlier_result(prediction, tmp_path / "r")
    (folder / foreign).mkdir() if foreign.endswith("/") else (folder / foreign).write_text("mine")
    before = snapshot(tmp_path)
    with pytest.raises(ValueError, match="files walk3d did not write") as info:
        _save(prediction, folder)
    assert "\n" not in str(info.value) and f"({foreign})" in str(info.value)
    assert snapshot(tmp_path) == before
    with pytest.raises(ValueError, match=re.escape(foreign)):  # walk3d.predict: before a solve
        walk3d.predict(1.3, out=folder)
    # control: without the user's file the earlier result is replaced
    (folder / foreign).rmdir() if foreign.endswith("/") else (folder / foreign).unlink()
    _save(prediction, folder)
    assert not (folder / "validation").exists() and (folder / "manifest.json").is_file()


def test_cli_predict_refuses_an_earlier_result_holding_a_file_of_the_user(
    prediction, tmp_path, capsys
):
    from walk3d.cli import main

    folder = _earlier_result(prediction, tmp_path / "r")
    (folder / "notes.txt").write_text("mine")
    with pytest.raises(SystemExit) as info:
        main(["predict", "--out", str(folder), "--nodes", "1"])
    err = capsys.readouterr().err.strip().splitlines()
    assert info.value.code == 2 and len(err) == 1 and "(notes.txt)" in err[0], err
    assert (folder / "notes.txt").read_text() == "mine"
    (folder / "notes.txt").unlink()  # control: the check passes, --nodes 1 is refused next
    with pytest.raises(SystemExit) as info:
        main(["predict", "--out", str(folder), "--nodes", "1"])
    err = capsys.readouterr().err
    assert info.value.code == 2 and "nodes" in err and "did not write" not in err, err


@pytest.mark.parametrize("kind", ["file", "folder of other files"])
def test_predict_with_a_bad_out_raises_before_any_solve(monkeypatch, tmp_path, kind):
    import walk3d
    from walk3d import api

    def solve(*args, **kwargs):
        raise AssertionError("the settings were built: a solve would start")

    monkeypatch.setattr(api, "settings", solve)
    out = tmp_path / "out"
    if kind == "file":
        out.write_text("mine")
    else:
        out.mkdir()
        (out / "notes.txt").write_text("mine")
    with pytest.raises(ValueError, match=kind.split()[0]):
        walk3d.predict(1.3, out=out)
    # control: a good out reaches the settings (where the solve would begin)
    with pytest.raises(AssertionError, match="settings were built"):
        walk3d.predict(1.3, out=tmp_path / "new")


def test_save_on_a_full_disk_raises_one_line_and_keeps_the_earlier_result(
    prediction, tmp_path, monkeypatch
):
    folder = _save(prediction, tmp_path / "r")
    before = snapshot(tmp_path)
    synced = full_disk(monkeypatch, after=2)
    with pytest.raises(OSError, match="no space left on device") as info:
        prediction.save(folder, report=False)
    message = str(info.value)
    assert "\n" not in message and message.startswith(f"could not write {folder}")
    assert len(synced) == 2  # control: the disk filled up half way through
    assert snapshot(tmp_path) == before  # the old result, nothing half-written beside it
    monkeypatch.undo()
    _save(prediction, folder)  # control: with room, the same call writes
