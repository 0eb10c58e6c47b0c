"""A user's file in an earlier result folder is never taken for a walk3d temporary: only
``.<name>.<12 hex>.tmp`` of a file walk3d writes there, and a sub-folder's temporary beside
its owner file, are walk3d's (issue #60: ``.tmp_mine`` or ``.mine.0123456789ab.bak`` went with
the folder). No solve: the shipped atlas solution stands in."""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

import pytest

import walk3d

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "verify"))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from disk_support import snapshot  # noqa: E402

USERS = [
    ".tmp_mine", ".tmp_notes/", ".draft.0123456789ab.txt", ".mine.0123456789ab.bak",
    ".summary.json.0123456789ab.bak", ".tmp_report.html_x", ".notes.txt.0123456789ab.tmp",
    ".tmp_validation_0123456789ab/", ".report.html.0123456789AB.tmp",
]  # fmt: skip
"""Names of the user's that walk3d's old patterns took for its temporaries (a folder ends
with ``/``), and close variants: the ``.tmp`` form of a name walk3d does not write, a
validation temporary without its owner file, upper-case hex."""


@pytest.fixture(scope="module")
def prediction():
    """The atlas solution at 1.3 m/s as an API Prediction."""
    from verify_support import atlas_prediction

    from walk3d import api

    return api.Prediction.of(atlas_prediction()[0])


def _save(pred, folder):
    return pred.save(folder, figure=False, report=False)


def _add(folder: Path, name: str) -> None:
    """The user's file, or folder holding a file, ``name`` in ``folder``."""
    if name.endswith("/"):
        (folder / name).mkdir()
        (folder / name / "n.txt").write_text("the user's notes")
    else:
        (folder / name).write_text("the user's")


@pytest.mark.parametrize("name", USERS)
def test_an_earlier_result_holding_a_file_named_like_a_temporary_is_refused_and_kept(
    prediction, tmp_path, name
):
    folder = _save(prediction, tmp_path / "r")
    _add(folder, name)
    before = snapshot(tmp_path)
    with pytest.raises(ValueError, match="files walk3d did not write") as info:
        _save(prediction, folder)
    assert "\n" not in str(info.value) and f"({name})" in str(info.value)
    with pytest.raises(ValueError, match="did not write"):  # walk3d.predict: before a solve
        walk3d.predict(1.3, out=folder)
    assert snapshot(tmp_path) == before  # the user's content intact, nothing else written
    # negative control: without the user's entry the earlier result is replaced
    shutil.rmtree(folder / name) if name.endswith("/") else (folder / name).unlink()
    assert (_save(prediction, folder) / "manifest.json").is_file()


def test_cli_predict_keeps_the_reviewers_three_entries(prediction, tmp_path, capsys):
    from helpers import cli, one_line_error

    folder = _save(prediction, tmp_path / "d1")
    for name in (".tmp_mine", ".tmp_notes/", ".draft.0123456789ab.txt"):
        _add(folder, name)
    before = snapshot(tmp_path)
    one_line_error(cli(capsys, "predict", "--out", folder, "--nodes", "1"),
                   ".draft.0123456789ab.txt, .tmp_mine, .tmp_notes/")  # fmt: skip
    assert snapshot(tmp_path) == before


def test_a_killed_writers_temporaries_in_an_earlier_result_are_replaced(prediction, tmp_path):
    """Control: what a walk3d killed in a result folder leaves is its own, and goes with the
    folder: a report's file temporary, a view's files built aside (:func:`replace_files`), a
    validation's folder temporaries with their owner file."""
    from walk3d.io.atomic import file_temporary_of
    from walk3d.outputs import replace_files

    folder = _save(prediction, tmp_path / "r")
    with replace_files(folder, "manifest.json") as tmp:  # named after the file it ends with
        assert tmp.parent == folder and file_temporary_of(tmp.name) == "manifest.json"
    (folder / ".report.html.0123456789ab.tmp").write_text("<html")
    (folder / ".manifest.json.0123456789ab.tmp").mkdir()
    for name in (".tmp_validation_0123456789ab", ".tmp_old_validation_0123456789ab"):
        (folder / name).mkdir()
    (folder / ".tmp_validation_0123456789ab.owner").write_text("host 1 1\n")
    _save(prediction, folder)
    assert not [p.name for p in folder.iterdir() if p.name.startswith(".")]


def test_an_earlier_result_holding_a_fifo_is_refused_and_the_fifo_kept(
    prediction, tmp_path, capsys
):
    """A FIFO (as a device or socket) named like a file walk3d writes went with the earlier
    result it was in; now the folder is refused, naming it, before any solve."""
    import os
    import stat

    from helpers import cli, one_line_error

    folder = _save(prediction, tmp_path / "r")
    os.mkfifo(folder / "summary.png")
    with pytest.raises(ValueError, match=r"holds summary.png, not a regular file"):
        _save(prediction, folder)
    with pytest.raises(ValueError, match="not a regular file"):  # walk3d.predict: before a solve
        walk3d.predict(1.3, out=folder)
    one_line_error(cli(capsys, "predict", "--out", folder, "--nodes", "1"), "summary.png",
                   "not a regular file")  # fmt: skip
    assert stat.S_ISFIFO(os.lstat(folder / "summary.png").st_mode)
    # negative control: a regular summary.png there is replaced with the folder
    (folder / "summary.png").unlink()
    (folder / "summary.png").write_text("the earlier figure")
    _save(prediction, folder)
    assert not (folder / "summary.png").exists()  # saved without a figure this time


@pytest.mark.parametrize("kind", ["link to an earlier result", "dangling link"])
def test_an_out_that_is_a_symbolic_link_is_refused_and_the_link_kept(
    prediction, tmp_path, capsys, kind
):
    """save('link') turned the user's link to an earlier result into a real folder and left
    the link as .tmp_old_link_<hex> for ever; predict --out DANGLING solved, then failed with
    exit 3. Now refused in one line before any work (save, walk3d.predict, the command).
    Negative control: the folder the link points to is replaced."""
    from helpers import cli, one_line_error

    earlier = _save(prediction, tmp_path / "b3")
    link = tmp_path / "link"
    link.symlink_to(earlier if kind.startswith("link") else tmp_path / "nothing")
    before = snapshot(tmp_path)
    with pytest.raises(ValueError, match=f"out {link} is a symbolic link") as info:
        _save(prediction, link)
    assert "\n" not in str(info.value)
    with pytest.raises(ValueError, match="is a symbolic link"):  # walk3d.predict: before a solve
        walk3d.predict(1.3, out=link)
    one_line_error(cli(capsys, "predict", "--out", link, "--nodes", "1"), "symbolic link")
    assert snapshot(tmp_path) == before and link.is_symlink()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b3", "link"]  # no .tmp_old_link_*
    assert (_save(prediction, earlier) / "manifest.json").is_file()
