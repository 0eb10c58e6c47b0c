"""A campaign resume refuses, in one line and before any solve, a start entry that is not
walk3d's own (a file, a link, a folder with a user's files or another seed's record) and never
deletes it; walk3d's own partial writes still run again, with a warning. No solve: the starts
are copies of the atlas's result folder (``test_campaign_resume``)."""

import json
import shutil

import pytest
import test_campaign_resume as resume_tests
from helpers import cli, one_line_error
from test_campaign_resume import campaign_folder, set_summary, start_path

from walk3d.campaign import run_campaign, store

source = resume_tests.source
no_solve = resume_tests.no_solve


def _prediction_with_notes(start):
    """A prediction folder of this start put there by hand, with a user's notes.txt."""
    (start / "record.json").unlink()
    (start / "notes.txt").write_text("my notes\n", encoding="utf-8")


def _other_seeds_record(start):
    record = json.loads((start / "record.json").read_text(encoding="utf-8"))
    (start / "record.json").write_text(json.dumps(record | {"seed": 5}), encoding="utf-8")


def _a_file(start):
    shutil.rmtree(start)
    start.write_text("x\n", encoding="utf-8")


def _a_link(start):
    target = start.parent.parent / "elsewhere"
    start.rename(target)
    start.symlink_to(target, target_is_directory=True)


def _a_sub_folder(start):
    (start / "plots").mkdir()


def _a_foreign_validation_file(start):
    (start / "validation").mkdir()
    (start / "validation" / "mine.csv").write_text("1\n", encoding="utf-8")


def _a_damaged_prediction_of_another_problem(start):
    set_summary(start, mass=80.0)
    (start / "result.npz").write_bytes(b"cut")


@pytest.mark.parametrize(("damage", "words"), [
    (_prediction_with_notes, "holds files walk3d did not write (notes.txt)"),
    (_other_seeds_record, "holds the record of seed 5, not 0"),
    (_a_file, "is a file where a start folder belongs"),
    (_a_link, "is a symbolic link where a start folder belongs"),
    (_a_sub_folder, "holds files walk3d did not write (plots)"),
    (_a_foreign_validation_file, "(validation/mine.csv)"),
    (_a_damaged_prediction_of_another_problem, "solved with mass 80.0"),
])  # fmt: skip
def test_a_start_entry_that_is_not_walk3ds_own_is_refused_not_deleted(
    tmp_path,
    source,
    capsys,
    no_solve,
    damage,
    words,
):
    """Resume deleted the folder (notes.txt included) and solved it again, exit 0; a file or a
    link cost a solve, then exit 3."""
    out = campaign_folder(tmp_path / "c", source)
    start = start_path(out, 0)
    damage(start)
    before = sorted(p.name for p in start.iterdir()) if start.is_dir() else start.read_bytes()
    with pytest.raises(store.CampaignMismatch, match=words.replace("(", r"\(").replace(")", r"\)")):
        run_campaign(source[1], 2, 0, out, progress=False)
    gait = source[1].gait
    one_line_error(cli(capsys, "campaign", "--starts", 2, "--out", out, "--no-compile",
                       "--free-landing", "--speed", gait.speed, "--period", repr(gait.period),
                       "--double-support", repr(gait.double_support)),
                   str(start), words, "remove")  # fmt: skip
    assert no_solve == []
    after = sorted(p.name for p in start.iterdir()) if start.is_dir() else start.read_bytes()
    assert after == before  # nothing deleted


def test_walk3ds_own_files_are_resumed_without_a_solve(tmp_path, source, no_solve):
    """Control: a prediction of this start without its record (rebuilt, with a warning), and
    a start with validate's files and an atomic write's temporary, are resumed as they are."""
    out = campaign_folder(tmp_path / "c", source)
    (start_path(out, 0) / "record.json").unlink()
    (start_path(out, 1) / "validation").mkdir()
    (start_path(out, 1) / "validation" / "score.json").write_text("{}\n", encoding="utf-8")
    (start_path(out, 1) / ".tmp_record.json_ab12").write_text("{", encoding="utf-8")
    with pytest.warns(RuntimeWarning, match="record.json was missing or unreadable: rewritten"):
        report = run_campaign(source[1], 2, 0, out, progress=False)
    assert no_solve == [] and report.skipped == 2
    assert json.loads((start_path(out, 0) / "record.json").read_text(encoding="utf-8"))["seed"] == 0


def test_a_record_only_start_with_a_damaged_record_runs_again(tmp_path, source, no_solve):
    """Control: walk3d's own partial write (a record-only folder whose record is damaged) is
    deleted and run again, with a warning."""
    out = campaign_folder(tmp_path / "c", source, seeds=(0,))
    store.open_campaign(out, source[1], 0, 2, "ipopt")
    start = start_path(out, 1)
    start.mkdir()
    (start / "record.json").write_text("{not json", encoding="utf-8")
    (start / "traceback.txt").write_text("Traceback\n", encoding="utf-8")
    with pytest.warns(RuntimeWarning, match="no readable record.json and no result.*seed 1 again"):
        run_campaign(source[1], 2, 0, out, progress=False)
    assert no_solve == [1] and not start.exists()
