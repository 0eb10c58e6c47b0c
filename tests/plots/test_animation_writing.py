"""``walk3d animate`` when the video cannot be written: exit 3 and one line, the earlier
``animation.mp4`` and manifest intact, nothing half-written left; a deleted video is made again.

Two failures: ffmpeg's own writes failing part way (an ffmpeg limited to 8 KiB files by
``ulimit -f``, the way a full disk stops it) and the final sync failing with ENOSPC
(tests/disk_support.py). The CLI runs in this process, its output captured at the descriptors
so that anything ffmpeg prints itself is seen too."""

from __future__ import annotations

import os
import shutil
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from disk_support import full_disk, snapshot  # noqa: E402

ARGS = ("--cycles", "1", "--fps", "5")
LIMIT_BLOCKS = 16
"""The limited ffmpeg's largest file, 512-byte blocks (the video is some 70 KB)."""


@pytest.fixture(scope="module")
def animated(atlas_result, tmp_path_factory):
    """A result folder with a (short) animation.mp4 listed in its manifest."""
    from walk3d.plots.video import write_animation
    from walk3d.results.views import write_view

    pred, body, folder = atlas_result
    copy = Path(shutil.copytree(folder, tmp_path_factory.mktemp("animated") / folder.name))
    write_view(copy, "animation.mp4", lambda p: write_animation(pred, p, cycles=1, fps=5,
                                                                body=body))  # fmt: skip
    return copy


@pytest.fixture()
def small_ffmpeg(tmp_path, monkeypatch):
    """Make walk3d's ffmpeg one whose files cannot grow past 8 KiB (POSIX shells only)."""
    if os.name != "posix":
        pytest.skip("the limited ffmpeg is a POSIX shell script")
    import imageio_ffmpeg

    script = tmp_path / "ffmpeg_8k"
    real = imageio_ffmpeg.get_ffmpeg_exe()
    script.write_text(f'#!/bin/sh\ntrap "" XFSZ\nulimit -f {LIMIT_BLOCKS}\nexec "{real}" "$@"\n')
    script.chmod(0o755)
    monkeypatch.setattr(imageio_ffmpeg, "get_ffmpeg_exe", lambda: str(script))
    return script


def _animate(capfd, *args) -> tuple[int, str]:
    from walk3d.cli import main

    with pytest.raises(SystemExit) as info:
        main(["animate", *map(str, args)])
    return info.value.code, capfd.readouterr().err


def _one_write_error(code, err, path) -> None:
    assert code == 3, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith(f"walk3d: error: could not write {path}: "), err


@pytest.fixture(params=["ffmpeg writes", "final sync"])
def failing_disk(request, monkeypatch, tmp_path):
    if request.param == "ffmpeg writes":
        return request.getfixturevalue("small_ffmpeg")
    return full_disk(monkeypatch)


def test_animate_dir_that_cannot_be_written_keeps_the_old_video(animated, tmp_path, capfd,
                                                                failing_disk):  # fmt: skip
    folder = Path(shutil.copytree(animated, tmp_path / "r"))
    before = snapshot(folder)
    code, err = _animate(capfd, folder, *ARGS)
    _one_write_error(code, err, folder / "animation.mp4")
    assert snapshot(folder) == before  # video, manifest, no temporaries


def test_animate_out_that_cannot_be_written_leaves_nothing(animated, tmp_path, capfd,
                                                           failing_disk):  # fmt: skip
    out = tmp_path / "videos"
    out.mkdir()
    code, err = _animate(capfd, animated, "--out", out / "walk.mp4", *ARGS)
    _one_write_error(code, err, out / "walk.mp4")
    assert list(out.iterdir()) == []


def test_the_limited_ffmpeg_leaves_a_broken_video_that_is_caught(atlas_result, tmp_path,
                                                                  small_ffmpeg):  # fmt: skip
    """Control: the limited ffmpeg does cut the video short, so a writer that did not check
    ffmpeg's exit would keep a broken file (as walk3d did)."""
    from walk3d.plots.video import encode_mp4

    frames = [bytes(1280 * 480 * 3)] * 2 + [os.urandom(1280 * 480 * 3) for _ in range(4)]
    with pytest.raises(OSError, match="(?i)file too large"):
        encode_mp4(tmp_path / "raw.mp4", frames, 5)
    assert 0 < (tmp_path / "raw.mp4").stat().st_size <= LIMIT_BLOCKS * 512


def test_an_unwritable_out_is_one_line_without_ffmpeg_output(animated, capfd):
    code, err = _animate(capfd, animated, "--out", "/proc/walk3d_test.mp4", *ARGS)
    assert code in (2, 3), err  # 2 when refused before rendering (not root), 3 from ffmpeg
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("walk3d: error:"), err
    assert "/proc/walk3d_test.mp4" in lines[0] and "ffmpeg" not in err.lower()


def test_a_deleted_video_is_made_again(animated, tmp_path, capfd):
    import json

    from walk3d.results.prediction import check_complete

    folder = Path(shutil.copytree(animated, tmp_path / "r"))
    (folder / "animation.mp4").unlink()
    code, err = _animate(capfd, folder, *ARGS)
    assert code == 0, err
    files = json.loads((folder / "manifest.json").read_text())["files"]
    assert files["animation.mp4"] == (folder / "animation.mp4").stat().st_size > 10_000
    check_complete(folder)
    (folder / "motion.mot").unlink()  # control: a missing result file is still refused
    code, err = _animate(capfd, folder, *ARGS)
    assert code == 2 and "motion.mot is missing" in err, err
