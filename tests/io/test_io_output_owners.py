"""Whose place an output takes (walk3d.outputs): a path inside a walk3d result folder other than
the command's own, a file the command reads, or an existing file that is not the kind walk3d
writes there are refused with one line; a new file, walk3d's own earlier file and a folder that
only looks like a result are accepted (the negative controls)."""

import json
import os

import pytest
from result_support import bare_result_folder

from walk3d.outputs import (
    check_output_file,
    check_output_folder,
    is_result_folder,
    json_holds,
    result_folder_around,
)


@pytest.mark.parametrize("check", [check_output_file, check_output_folder])
@pytest.mark.parametrize("rel", ["out", "sub/out"], ids=["beside-its-files", "below"])
def test_a_path_inside_a_result_folder_is_refused(tmp_path, check, rel):
    """calibrate, audit, report --out and sweep, campaign, compare --out wrote into a result
    folder: its files replaced, or files beside them that made predict --out refuse it."""
    result = bare_result_folder(tmp_path / "p1")
    with pytest.raises(ValueError) as info:
        check(result / rel, "--out")
    message = str(info.value)
    assert "\n" not in message
    assert message == (f"--out {result / rel} is inside the walk3d result folder {result}; "
                       "write outside it")  # fmt: skip


@pytest.mark.parametrize("check", [check_output_file, check_output_folder])
def test_a_path_in_the_commands_own_result_folder_or_outside_is_accepted(tmp_path, check):
    """Negative control: the result a command reads (its page, video, validation), a sibling
    of a result folder, and a ``..`` that leaves it."""
    result = bare_result_folder(tmp_path / "p1")
    assert check(result / "out", "--out", home=result) == result / "out"
    assert check(result / "sub" / "out", "--out", home=tmp_path / "." / "p1")
    assert check(tmp_path / "p1-out", "--out")
    assert check(result / ".." / "elsewhere", "--out")


@pytest.mark.parametrize("names", [("summary.json",), ("manifest.json",), ()])
def test_a_folder_with_only_one_of_the_two_files_is_not_a_result(tmp_path, names):
    """Negative control: a user's folder with a summary.json or a manifest.json of its own."""
    for name in names:
        (tmp_path / name).write_text("{}")
    assert not is_result_folder(tmp_path)
    assert result_folder_around(tmp_path / "x") is None
    assert check_output_file(tmp_path / "x.json", "--out")


def test_an_output_that_is_an_input_is_refused(tmp_path):
    ik = tmp_path / "ik.json"
    ik.write_text("the trial")
    os.link(ik, tmp_path / "linked.json")
    for same in (ik, tmp_path / "." / "ik.json", tmp_path / "linked.json"):
        with pytest.raises(ValueError, match=r"^--out .* is the --ik file, which walk3d reads"):
            check_output_file(same, "--out", inputs={"--ik": ik, "--grf": None})
    other = tmp_path / "other.json"
    other.write_text("{}")  # control: another existing file, and a new one
    assert check_output_file(other, "--out", inputs={"--ik": ik})
    assert check_output_file(tmp_path / "new.json", "--out", inputs={"--ik": ik})
    assert ik.read_text() == "the trial"


def test_an_existing_file_must_be_walk3ds_own(tmp_path):
    kind = ("walk3d audit", lambda p: json_holds(p, "terms", "bursts"))
    mine = tmp_path / "mine.json"
    for text in ('{"terms": 1}', "[1, 2]", "not json", "\xff"):
        mine.write_text(text, encoding="latin-1")
        with pytest.raises(ValueError, match=r"exists and is not a walk3d audit: walk3d "):
            check_output_file(mine, "--out", existing=kind)
    ours = tmp_path / "audit.json"
    ours.write_text(json.dumps({"terms": [], "bursts": {}, "more": 1}))  # control: walk3d's
    assert check_output_file(ours, "--out", existing=kind) == ours
    assert check_output_file(tmp_path / "new.json", "--out", existing=kind)
