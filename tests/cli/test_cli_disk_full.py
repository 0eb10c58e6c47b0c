"""A full disk and an unwritable folder: predict exits 3 with one line and leaves no folder; a
campaign start that failed on the disk runs again once space is freed; animate exits 3 with one
line and keeps the earlier video. The full disk is a small
tmpfs (needs root to mount); the permission check runs as a non-root user."""

import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile
from contextlib import contextmanager
from pathlib import Path

import pytest

FAST = ["--nodes", "6", "--max-iter", "3", "--criterion", "tor", "--period", "1.08",
        "--double-support", "0.16"]  # fmt: skip
"""A solve of a few seconds that does not converge (the result is still written); T and Td
given, so one problem is built and solved, not the free landing's as well."""


def _run(*args, timeout=300, **kwargs):
    cmd = [sys.executable, "-m", "walk3d.cli", *map(str, args)]
    env = os.environ | {"OPENBLAS_NUM_THREADS": "1", "COLUMNS": "200"}
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env, **kwargs)


@contextmanager
def tiny_disk(parent: Path, kib: int):
    """A tmpfs of ``kib`` KiB mounted in ``parent``; skips when it cannot be mounted."""
    mnt = parent / "disk"
    mnt.mkdir()
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={kib}k", "tmpfs", str(mnt)],
                       capture_output=True, text=True)  # fmt: skip
    if r.returncode != 0:
        pytest.skip(f"a small tmpfs cannot be mounted here (needs root): {r.stderr.strip()}")
    try:
        yield mnt
    finally:
        subprocess.run(["umount", "-l", str(mnt)], check=False)


def _grow(mnt: Path, kib: int) -> None:
    subprocess.run(["mount", "-o", f"remount,size={kib}k", str(mnt)], check=True)


@pytest.mark.solve
def test_predict_on_a_full_disk_exits_3_with_one_line_and_leaves_nothing(tmp_path):
    """300 KiB hold result.npz, summary.json and the .mot files but not summary.png."""
    with tiny_disk(tmp_path, 300) as disk:
        r = _run("predict", "--out", disk / "o", *FAST)
        assert r.returncode == 3, r.stderr[-800:]
        lines = r.stderr.strip().splitlines()
        assert len(lines) == 1 and "could not write" in lines[0], r.stderr
        assert "no space left on device" in lines[0] and "Traceback" not in r.stderr
        assert list(disk.iterdir()) == []  # no folder, no temporary
        _grow(disk, 4096)  # control: with room, the same command writes the folder
        r = _run("predict", "--out", disk / "o", *FAST)
        assert r.returncode == 1, r.stderr[-800:]  # written, labelled as not converged
        assert (disk / "o" / "manifest.json").is_file() and (disk / "o" / "summary.png").is_file()


@pytest.mark.campaign
def test_a_campaign_start_that_did_not_fit_on_the_disk_runs_on_resume(tmp_path):
    with tiny_disk(tmp_path, 200) as disk:
        out = disk / "c"
        args = ("campaign", "--starts", "1", "--out", out, "--workers", "1", "--restarts", "0",
                "--no-compile", *FAST)  # fmt: skip
        r = _run(*args)  # the start's folder does not fit: it stays pending, exit 3
        assert r.returncode == 3 and "Traceback" not in r.stderr, r.stderr[-800:]
        assert "could not be recorded" in r.stderr.strip().splitlines()[-1], r.stderr[-800:]
        assert not (out / "starts" / "seed_000000").exists()
        _grow(disk, 8192)
        r = _run(*args)
        assert r.returncode == 1, r.stderr[-800:]  # ran; three iterations do not converge
        assert "this run 1," in r.stdout
        record = json.loads((out / "starts" / "seed_000000" / "record.json").read_text())
        assert record["failure"] == "numerics" and record["iterations"] is not None
        with open(out / "ranking.csv", newline="") as f:
            assert next(csv.DictReader(f))["failure"] == "numerics"
        r = _run(*args)  # control: a start that failed in the numerics stays recorded
        assert "this run 0," in r.stdout and "retried" not in r.stdout


def _check_as_nobody(out: Path, log: Path) -> int:
    """Run the CLI's output-folder check in a forked child that has become user ``nobody``
    (the interpreter itself may not be executable by that user); returns its exit code."""
    import typer

    from walk3d.cli.common import check_output_folder

    pid = os.fork()
    if pid == 0:  # the child: drop root, send stderr to the log, run the check
        code = 70
        try:
            fd = os.open(log, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o666)
            os.dup2(fd, 2)
            sys.stderr = os.fdopen(2, "w", buffering=1)
            if os.geteuid() == 0:
                os.setgid(65534)
                os.setuid(65534)
            check_output_folder(str(out))
            code = 0
        except typer.Exit as exc:
            code = exc.exit_code
        finally:
            os._exit(code)
    return os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1])


@pytest.mark.skipif(not hasattr(os, "fork"), reason="POSIX users and fork")
def test_a_folder_without_write_permission_is_refused_as_a_non_root_user():
    base = Path(tempfile.mkdtemp(prefix="walk3d-perm-"))
    try:
        base.chmod(0o777)
        locked = base / "locked"
        locked.mkdir()
        locked.chmod(0o555)
        if os.geteuid() != 0 and os.access(locked, os.W_OK):
            pytest.skip("this user can write to a read-only folder")
        log = base / "stderr.txt"
        assert _check_as_nobody(locked / "o", log) == 2
        lines = log.read_text().strip().splitlines()
        assert len(lines) == 1 and "permission denied" in lines[0], lines
        assert _check_as_nobody(base / "writable" / "o", log) == 0  # control: writable passes
    finally:
        shutil.rmtree(base, ignore_errors=True)


def _fill(disk: Path, leave_kib: int) -> None:
    """Fill ``disk`` up to ``leave_kib`` KiB free."""
    free = shutil.disk_usage(disk).free - leave_kib * 1024
    (disk / "filler").write_bytes(bytes(max(free, 0)))


def _animate_here(capfd, *args) -> tuple[int, str]:
    """``walk3d animate ARGS`` in this process: exit code and everything written to stderr
    (ffmpeg's own messages included)."""
    from walk3d.cli import main

    with pytest.raises(SystemExit) as info:
        main(["animate", *map(str, args), "--cycles", "1", "--fps", "5"])
    return info.value.code, capfd.readouterr().err


def test_animate_on_a_full_disk_exits_3_with_one_line_and_changes_nothing(tmp_path, capfd):
    """A real full disk under ffmpeg: the earlier video and manifest stay, --out leaves no
    file, and ffmpeg's own messages are not printed."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "verify"))
    from verify_support import atlas_prediction

    from walk3d.plots.video import write_animation
    from walk3d.results.prediction import save_prediction
    from walk3d.results.views import write_view

    pred, body = atlas_prediction()
    with tiny_disk(tmp_path, 1024) as disk:
        folder = save_prediction(pred, disk / "r", body=body)
        write_view(folder, "animation.mp4", lambda p: write_animation(pred, p, cycles=1, fps=5,
                                                                      body=body))  # fmt: skip
        before = {p.name: p.read_bytes() for p in folder.iterdir()}
        _fill(disk, 40)
        for target, args in ((folder / "animation.mp4", ()),
                             (disk / "walk.mp4", ("--out", disk / "walk.mp4"))):  # fmt: skip
            code, err = _animate_here(capfd, folder, *args)
            assert code == 3, err[-800:]
            lines = err.strip().splitlines()
            assert lines == [f"walk3d: error: could not write {target}: no space left on device"]
            assert {p.name: p.read_bytes() for p in folder.iterdir()} == before
            assert sorted(p.name for p in disk.iterdir()) == ["filler", "r"]
        (disk / "filler").unlink()  # control: with room, the same command writes the video
        code, err = _animate_here(capfd, folder)
        assert code == 0 and err == "", err[-800:]
        assert (folder / "animation.mp4").read_bytes() != b""
