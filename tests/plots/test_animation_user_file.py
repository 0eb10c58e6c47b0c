"""``walk3d animate --out FILE``: an existing FILE is replaced only if walk3d wrote it (the
comment in its metadata, or a view its folder's manifest lists); a user's file is refused
with one line, before the render."""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from helpers import cli, one_line_error  # noqa: E402

from walk3d.plots.video import encode_mp4, is_walk3d_video  # noqa: E402
from walk3d.results.views import is_listed_view  # noqa: E402


def test_a_users_video_is_refused_before_the_render(atlas_result, tmp_path, capsys):
    _, _, folder = atlas_result
    mine = tmp_path / "mine.mp4"
    mine.write_bytes(b"\x00\x00\x00\x20ftypisom my holiday video")
    refused = cli(capsys, "animate", folder, "--out", mine)
    one_line_error(refused, f"--out {mine} exists and is not a walk3d video")
    assert mine.read_bytes().endswith(b"my holiday video")


def test_walk3d_knows_its_own_videos(tmp_path):
    """The marker is in a video encode_mp4 wrote; control: a listed view without it (an
    earlier walk3d's) is known by the manifest, an unlisted one or a user's file is not."""
    video = tmp_path / "v.mp4"
    encode_mp4(video, [bytes(1280 * 480 * 3)] * 2, 5)
    assert is_walk3d_video(video)
    plain = tmp_path / "plain.mp4"
    plain.write_bytes(video.read_bytes().replace(b"walk3d animation", b"someone's video!"))
    assert not is_walk3d_video(plain) and not is_walk3d_video(tmp_path / "none.mp4")
    folder = tmp_path / "r"
    folder.mkdir()
    shutil.copy(plain, folder / "animation.mp4")
    assert not is_listed_view(folder / "animation.mp4")  # no manifest
    (folder / "manifest.json").write_text('{"files": {"animation.mp4": 1}}')
    assert is_listed_view(folder / "animation.mp4")
