"""The atomic writers replace regular files only: a device, FIFO or socket at the target (or a
link to one) is refused and left as it is."""

import os
import stat

import pytest
from helpers import cli, one_line_error

from walk3d.io.atomic import atomic_path, atomic_write_text
from walk3d.outputs import check_output_file


@pytest.fixture
def fifo(tmp_path):
    path = tmp_path / "pipe.json"
    os.mkfifo(path)
    return path


def test_a_fifo_is_refused_and_kept(fifo, tmp_path):
    with pytest.raises(FileExistsError, match="not a regular file"):
        atomic_write_text(fifo, "{}")
    with pytest.raises(FileExistsError), atomic_path(fifo):
        pass
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
    assert [p.name for p in tmp_path.iterdir()] == ["pipe.json"]  # no temporary left
    link = tmp_path / "to_null.json"
    link.symlink_to(os.devnull)
    with pytest.raises(FileExistsError):
        atomic_write_text(link, "{}")
    assert os.path.islink(link) and os.readlink(link) == os.devnull
    # negative control: a regular file is replaced
    plain = tmp_path / "plain.json"
    plain.write_text("old")
    atomic_write_text(plain, "new")
    assert plain.read_text() == "new"


def test_output_options_refuse_a_fifo_before_any_work(fifo, capsys):
    with pytest.raises(ValueError, match="not a regular file"):
        check_output_file(fifo)
    one_line_error(cli(capsys, "calibrate", "--ik", "none.mot", "--grf", "none.mot", "--out",
                       fifo), "pipe.json", "not a regular file")  # fmt: skip
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
    check_output_file(fifo.with_name("new.json"))  # control: a new file is fine


def test_new_folder_removes_only_the_folders_it_made_and_its_own_files(tmp_path):
    """A failed block: the new folders go with walk3d's files; a user's file keeps its folder,
    and an existing folder is never removed."""
    from walk3d.outputs import new_folder

    out = tmp_path / "new" / "deeper" / "cmp"
    with pytest.raises(OSError), new_folder(out, ["a.csv"]) as folder:
        folder.mkdir(parents=True)
        (folder / "a.csv").write_text("half")
        raise OSError("disk full")
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(OSError), new_folder(out, ["a.csv"]) as folder:
        folder.mkdir(parents=True)
        (folder / "a.csv").write_text("half")
        (folder.parent / "mine.txt").write_text("the user's")
        raise OSError("disk full")
    assert list(out.parent.iterdir()) == [out.parent / "mine.txt"]  # cmp went, "deeper" stays
    with pytest.raises(OSError), new_folder(out.parent, ["mine.txt"]):
        raise OSError("disk full")  # existing: kept, its file too
    assert (out.parent / "mine.txt").read_text() == "the user's"
    with new_folder(out, ["a.csv"]) as folder:  # control: a block that succeeds keeps all
        folder.mkdir()
        (folder / "a.csv").write_text("whole")
    assert (out / "a.csv").read_text() == "whole"
