"""Whether the process that left a temporary behind still runs (walk3d.io.processes): a pid that
another process has now, told by its start time, counts as ended, for the model cache's build
folders and for the owner files of the atomic folders."""

import os
import socket

import pytest

from walk3d.io import processes
from walk3d.io.atomic import remove_stale_temporaries
from walk3d.solve import compiled

needs_proc = pytest.mark.skipif(processes.start_time(os.getpid()) is None,
                                reason="no /proc: the pid alone decides")  # fmt: skip


def _ended_pid() -> int:
    import subprocess
    import sys

    p = subprocess.Popen([sys.executable, "-c", "pass"])
    p.wait()
    return p.pid


@needs_proc
def test_a_pid_runs_only_with_its_own_start_time():
    me, started = os.getpid(), processes.start_time(os.getpid())
    assert processes.running(me, started) and processes.running(me)  # the controls
    assert not processes.running(me, started + 1)
    assert not processes.running(_ended_pid()) and not processes.running(0)
    assert not processes.running(99_999_999_999)  # beyond any pid: no OverflowError


@needs_proc
def test_a_build_folder_of_a_reused_pid_is_left_over(tmp_path, monkeypatch):
    """A crashed compile's ``.build-<pid>-...`` stayed "in progress" for as long as another
    process had its pid; this test's own pid stands for the reused one."""
    monkeypatch.setenv("WALK3D_CACHE_DIR", str(tmp_path))
    me, started = os.getpid(), processes.start_time(os.getpid())
    reused = tmp_path / f".build-{me}-{started + 1}-abc_1234"
    mine = tmp_path / f".build-{me}-{started}-def_5678"  # control: the same pid, its start
    pid_only = tmp_path / f".build-{me}-ghi90123"  # control: an earlier walk3d's name
    for folder in (reused, mine, pid_only):
        folder.mkdir()
    assert compiled.leftover_builds() == [reused]


@needs_proc
def test_a_build_is_named_with_its_start_time(tmp_path, monkeypatch):
    monkeypatch.setenv("WALK3D_CACHE_DIR", str(tmp_path))
    seen = []
    monkeypatch.setattr(compiled.subprocess, "run", lambda cmd, **kw: seen.append(cmd[-3]))
    with pytest.raises(AttributeError):  # the stand-in compiler returns nothing
        compiled.build_library(tmp_path / "lib.so", "f.c", "", ["cc"], [], [])
    pid, started, _ = os.path.basename(os.path.dirname(seen[0])).split("-")[1:]
    assert (int(pid), int(started)) == (os.getpid(), processes.start_time(os.getpid()))


@needs_proc
def test_an_owner_file_of_a_reused_pid_is_ended(tmp_path):
    """The atomic folders' owner files record the start time too (``<host> <pid> <start>``);
    the two-field form of an earlier walk3d still counts by its pid."""
    host, me, started = socket.gethostname(), os.getpid(), processes.start_time(os.getpid())
    lines = {"aaaa": f"{host} {me} {started + 1}", "bbbb": f"{host} {me} {started}",
             "cccc": f"{host} {me}", "dddd": f"{host} {me} x"}  # fmt: skip
    for tag, line in lines.items():
        (tmp_path / f".tmp_out_{tag}").mkdir()
        (tmp_path / f".tmp_out_{tag}.owner").write_text(line + "\n")
    removed = remove_stale_temporaries(tmp_path, "out")
    assert [p.name for p in removed] == [".tmp_out_aaaa"]
    left = sorted(p.name for p in tmp_path.iterdir() if not p.name.endswith(".owner"))
    assert left == [".tmp_out_bbbb", ".tmp_out_cccc", ".tmp_out_dddd"]


def test_an_atomic_folder_records_its_start_time(tmp_path):
    from walk3d.io.atomic import atomic_folder

    with atomic_folder(tmp_path / "out") as tmp:
        words = tmp.with_name(tmp.name + ".owner").read_text().split()
    started = processes.start_time(os.getpid())
    tail = [] if started is None else [str(started)]
    assert words == [socket.gethostname(), str(os.getpid()), *tail]
