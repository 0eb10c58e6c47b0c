"""Writing a result folder from the Python API: the output check of ``walk3d predict --out``
(one function for both), nothing of the user's ever deleted, a full disk as one OSError line
with the earlier result intact. No solve: the shipped atlas solution stands in."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

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

    def spy(path, option="--out", replaces=None):
        calls.append((option, replaces))
        return real(path, option, replaces)

    monkeypatch.setattr(walk3d.outputs, "check_output_folder", spy)
    common.check_output_folder(str(tmp_path / "a"), replaces="summary.json")
    check_result_folder(tmp_path / "a")
    assert calls == [("--out", "summary.json"), ("out", "summary.json")]
    (tmp_path / "x.txt").write_text("x")  # the same refusal, one line each
    with pytest.raises(ValueError) as api_error:
        check_result_folder(tmp_path)
    with pytest.raises(common.typer.Exit) as cli_exit:
        common.check_output_folder(str(tmp_path), replaces="summary.json")
    assert cli_exit.value.exit_code == 2 and "folder of other files" in str(api_error.value)


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
