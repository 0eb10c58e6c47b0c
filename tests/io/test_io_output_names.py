"""The output checks' names (walk3d.outputs): a path that is not UTF-8 or holds NUL, and a name
longer than a file system takes (less walk3d's temporary names for the last one), are refused
with one line; the longest name accepted can be written, and replaced, atomically."""

import os

import pytest

from walk3d.io.atomic import atomic_folder, atomic_write_text
from walk3d.outputs import (
    NAME_MAX_BYTES,
    TEMPORARY_BYTES,
    check_output_file,
    check_output_folder,
)

LONGEST = NAME_MAX_BYTES - TEMPORARY_BYTES


@pytest.mark.parametrize("check", [check_output_folder, check_output_file])
@pytest.mark.parametrize(
    ("name", "words"),
    [(os.fsdecode(b"r\xe9sultat"), "out {dir}/r\\xe9sultat is not valid UTF-8 (byte 0xe9)"),
     ("a\0b", "holds a NUL byte"),
     ("a" * (LONGEST + 1), f"is {LONGEST + 1} bytes long, at most {LONGEST}"),
     ("a" * 256 + "/x", "is 256 bytes long, at most 255")],
    ids=["byte-e9", "nul", "longest+1", "256-bytes-parent"],
)  # fmt: skip
def test_names_a_file_system_cannot_hold_are_refused(tmp_path, check, name, words):
    with pytest.raises(ValueError) as info:
        check(tmp_path / name, "out")
    message = str(info.value)
    assert "\n" not in message and words.format(dir=tmp_path) in message, message
    assert message.encode("utf-8")  # printable as it is


@pytest.mark.parametrize("name", ["a" * LONGEST, "résultat-歩行"], ids=["longest", "utf8"])
def test_the_longest_name_accepted_is_written_and_replaced(tmp_path, name):
    """Negative control, and the reason for TEMPORARY_BYTES: walk3d's temporary siblings of
    the longest name accepted fit the file system."""
    folder, file = tmp_path / name, tmp_path / "f" / name
    assert check_output_folder(folder, "out") == folder
    assert check_output_file(file, "out") == file
    for _ in range(2):  # made, then replaced (the old one moved aside first)
        with atomic_folder(folder) as tmp:
            (tmp / "summary.json").write_text("{}")
        file.parent.mkdir(exist_ok=True)
        atomic_write_text(file, "{}")
    assert (folder / "summary.json").is_file() and file.read_text() == "{}"
