"""The atomic writers replace regular files only: a device, FIFO or socket at the target (or a
link to one) is refused and left as it is; a folder's commit is never cut in half by a
signal."""

import contextlib
import os
import shutil
import stat
from pathlib import Path

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


def _ended_pid() -> int:
    import subprocess
    import sys

    p = subprocess.Popen([sys.executable, "-c", "pass"])
    p.wait()
    return p.pid


def test_the_next_run_removes_a_killed_runs_temporary_and_nothing_else(tmp_path):
    """A run killed while it built ``out`` left ``.tmp_out_<hex>`` and its owner file: the next
    build of ``out`` removes both. A temporary whose process still runs (this one), and a
    user's folder of the same shape without an owner file, stay (the controls)."""
    import socket

    from walk3d.io.atomic import atomic_folder

    host = socket.gethostname()
    stale, alive, users = (tmp_path / f".tmp_out_{h}" for h in ("0000aaaa1111", "bbbb", "mine"))
    for folder, pid in ((stale, _ended_pid()), (alive, os.getpid())):
        folder.mkdir()
        (folder / "summary.json").write_text("{}")
        (tmp_path / f"{folder.name}.owner").write_text(f"{host} {pid}\n")
    users.mkdir()
    (users / "notes.txt").write_text("mine")
    with atomic_folder(tmp_path / "out") as tmp:
        (tmp / "a.txt").write_text("a")
    assert not stale.exists() and not (tmp_path / f"{stale.name}.owner").exists()
    assert alive.is_dir() and (users / "notes.txt").read_text() == "mine"
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["a.txt"]
    left = sorted(p.name for p in tmp_path.iterdir())
    assert left == [".tmp_out_bbbb", ".tmp_out_bbbb.owner", ".tmp_out_mine", "out"]


def test_a_signal_between_the_two_renames_waits_for_the_commit(tmp_path, monkeypatch):
    """Ctrl-C as the old folder is moved aside: the new folder still takes its name, no
    ``.tmp_old_`` copy is left, and the KeyboardInterrupt comes after; without the deferral
    (the control) the old folder is left aside and the name is empty."""
    import signal

    import walk3d.io.atomic as atomic

    target = tmp_path / "out"
    real_rename = os.rename

    def rename_then_signal(src, dst):
        real_rename(src, dst)
        if Path(src) == target:  # the old folder has just been moved aside
            signal.raise_signal(signal.SIGINT)

    for deferred in (True, False):
        target.mkdir()
        (target / "old.txt").write_text("old")
        monkeypatch.setattr(atomic.os, "rename", rename_then_signal)
        if not deferred:
            monkeypatch.setattr(atomic, "signals_deferred", contextlib.nullcontext)
        with pytest.raises(KeyboardInterrupt):
            with atomic.atomic_folder(target) as tmp:
                (tmp / "new.txt").write_text("new")
        monkeypatch.undo()
        left = sorted(p.name for p in tmp_path.iterdir())
        if deferred:
            assert left == ["out"] and (target / "new.txt").is_file(), left
        else:
            assert not target.exists() and left[0].startswith(".tmp_old_out_"), left
        shutil.rmtree(tmp_path)
        tmp_path.mkdir()


@pytest.mark.parametrize("committed", [False, True])
def test_a_run_killed_while_it_committed_gets_the_old_folder_back(tmp_path, committed):
    """Killed (-9) between the two renames: the old result waits in ``.tmp_old_out_<hex>`` and
    ``out`` is missing; the next run puts it back before it builds. Killed after the second
    rename (the control): ``out`` is the new folder and the old copy is removed."""
    import socket

    from walk3d.io.atomic import remove_stale_temporaries

    tmp, old = tmp_path / ".tmp_out_0000aaaa1111", tmp_path / ".tmp_old_out_0000aaaa1111"
    (tmp_path / f"{tmp.name}.owner").write_text(f"{socket.gethostname()} {_ended_pid()}\n")
    old.mkdir()
    (old / "summary.json").write_text("old")
    new = tmp_path / "out" if committed else tmp
    new.mkdir()
    (new / "summary.json").write_text("new")
    remove_stale_temporaries(tmp_path, "out")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]
    assert (tmp_path / "out" / "summary.json").read_text() == ("new" if committed else "old")


def test_temporaries_are_known_by_their_exact_form(tmp_path):
    """Only the exact names walk3d gives its temporaries count as one: a file writer's
    ``.<name>.<12 hex>.tmp``, a folder's ``.tmp_<name>_<12 hex>`` beside its owner file."""
    from walk3d.io.atomic import file_temporary_of, folder_temporary_of

    assert file_temporary_of(".report.html.0123456789ab.tmp") == "report.html"
    for name in (".mine.0123456789ab.bak", ".tmp_mine", ".report.html.0123456789ab.tmp.c3d",
                 ".report.html.0123.tmp", "report.html.0123456789ab.tmp"):  # fmt: skip
        assert file_temporary_of(name) is None, name
    folder, old = (
        tmp_path / ".tmp_validation_0123456789ab",
        tmp_path / ".tmp_old_validation_0123456789ab",
    )
    folder.mkdir()
    old.mkdir()
    assert folder_temporary_of(folder) is None and folder_temporary_of(old) is None  # no owner
    owner = tmp_path / ".tmp_validation_0123456789ab.owner"
    owner.mkdir()
    assert folder_temporary_of(folder) is None  # an owner that is a folder is no owner file
    owner.rmdir()
    owner.write_text("host 1 1\n")
    assert [folder_temporary_of(p) for p in (folder, old, owner)] == ["validation"] * 3


@pytest.mark.parametrize("kind", ["link to a folder", "dangling link", "link made while built",
                                  "folder"])  # fmt: skip
def test_atomic_folder_never_replaces_a_symbolic_link(tmp_path, kind):
    """The link was renamed aside as .tmp_old_<name>_<hex> and never removed (rmtree does not
    follow it), and a real folder took its name. Now FileExistsError, before the build and at
    the commit, and the link stays. Negative control: a real folder is replaced."""
    from walk3d.io.atomic import atomic_folder

    real = tmp_path / "real"
    real.mkdir()
    (real / "old.txt").write_text("the earlier result")
    target = real if kind == "folder" else tmp_path / "out"
    if kind in ("link to a folder", "dangling link"):
        target.symlink_to(real if kind == "link to a folder" else tmp_path / "nothing")
    if kind == "folder":
        with atomic_folder(target) as tmp:
            (tmp / "new.txt").write_text("new")
        assert [p.name for p in target.iterdir()] == ["new.txt"]
        return
    with pytest.raises(FileExistsError, match="is a symbolic link"), atomic_folder(target) as tmp:
        if kind == "link made while built":
            target.symlink_to(real)
        (tmp / "new.txt").write_text("new")
    assert target.is_symlink() and (real / "old.txt").read_text() == "the earlier result"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out", "real"]  # no temporary left


@pytest.mark.parametrize("kind", ["link to a file", "dangling link", "file"])
def test_an_output_file_that_is_a_symbolic_link_is_refused(tmp_path, kind):
    """check_output_file (calibrate, report, animate, audit --out) let a link through, and the
    atomic writer replaced the link with a regular file. Negative control: a regular file."""
    real = tmp_path / "real.json"
    real.write_text("{}")
    out = real if kind == "file" else tmp_path / "link.json"
    if kind != "file":
        out.symlink_to(real if kind == "link to a file" else tmp_path / "nothing.json")
        with pytest.raises(ValueError, match=f"--out {out} is a symbolic link"):
            check_output_file(out)
        assert out.is_symlink()
        return
    assert check_output_file(out) == out
