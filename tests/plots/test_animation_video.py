"""animation.mp4: readable back, the right frame count and size, not blank, moving; walk3d
animate's bad input gives one line and exit code 2."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import imageio.v2 as imageio
import numpy as np
import pytest
from helpers import cli, one_line_error, replace_result_file

import walk3d
from walk3d.plots.video import FRAME_SIZE, write_animation

FPS = 10


def _frames(path):
    with imageio.get_reader(path) as reader:
        return np.array([np.asarray(f) for f in reader])


def _looks_animated(frames) -> bool:
    return bool(frames.std() > 0 and np.abs(np.diff(frames.astype(float), axis=0)).max() > 0)


def test_video_reads_back(atlas_result, tmp_path):
    pred, body, _ = atlas_result
    out = write_animation(pred, tmp_path / "walk.mp4", cycles=1, fps=FPS, body=body)
    assert [p.name for p in tmp_path.iterdir()] == ["walk.mp4"]  # no temporary left
    frames = _frames(out)
    period = float(pred.time[-1] - pred.time[0])
    assert abs(len(frames) - period * FPS) <= 1
    assert frames.shape[1:] == (FRAME_SIZE[1], FRAME_SIZE[0], 3)
    assert _looks_animated(frames)
    # negative controls: a blank video and a still one are told apart
    assert not _looks_animated(np.full_like(frames, 255))
    assert not _looks_animated(np.repeat(frames[:1], len(frames), axis=0))


def _animate(*args):
    env = os.environ | {"MPLBACKEND": "Agg"}
    cmd = [sys.executable, "-m", "walk3d.cli", "animate", *map(str, args)]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=120, env=env)


@pytest.mark.parametrize("case", ["missing", "no_manifest", "bad_out"])
def test_cli_bad_input_one_line_exit_2(atlas_result, tmp_path, case):
    _, _, folder = atlas_result
    if case == "missing":
        r = _animate(tmp_path / "none")
    elif case == "no_manifest":
        broken = tmp_path / "broken"
        broken.mkdir()
        (broken / "summary.json").write_text(json.dumps({}))
        r = _animate(broken)
    else:
        r = _animate(folder, "--out", tmp_path / "walk.avi")
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("walk3d: error:"), r.stderr
    assert not list(tmp_path.glob("**/*.mp4"))


def test_cli_writes_into_the_folder_and_its_manifest(atlas_result, tmp_path):
    from walk3d.results.prediction import check_complete

    folder = tmp_path / "result"
    shutil.copytree(atlas_result[2], folder)
    r = _animate(folder, "--cycles", 1, "--fps", 5)
    assert r.returncode == 0, r.stderr
    files = json.loads((folder / "manifest.json").read_text())["files"]
    assert files["animation.mp4"] == (folder / "animation.mp4").stat().st_size
    check_complete(folder)


def test_cached_background_frames_equal_full_redraws(atlas_result):
    """Each frame is the cached background plus the moving artists; it must look like a
    whole redraw of the figure (anti-aliased edges may differ in a few pixels)."""
    from walk3d.plots.video import _Scene

    pred, body, _ = atlas_result
    scene = _Scene(pred, body, cycles=1, fps=FPS)
    for i in (0, scene.frames.n_frames // 2):
        fast = scene.frame(i).astype(int)
        full = scene.frame(i, full=True).astype(int)
        differ = np.any(np.abs(fast - full) > 40, axis=-1)
        assert differ.mean() < 5e-4, differ.mean()
    # control: another frame's drawing differs from this frame's in many pixels
    other = scene.frame(1).astype(int)
    assert np.any(np.abs(other - full) > 40, axis=-1).mean() > 5e-3


def _period_folder(folder: Path, tmp_path: Path, period: object) -> Path:
    """A copy of ``folder`` whose summary's descriptors.period is ``period`` (manifest kept)."""
    copy = Path(shutil.copytree(folder, tmp_path / "r"))
    summary = json.loads((copy / "summary.json").read_text())
    summary["descriptors"] = {**summary.get("descriptors", {}), "period": period}
    replace_result_file(copy, "summary.json", json.dumps(summary).encode())
    return copy


@pytest.mark.parametrize("period", [1e7, 1e4, [1], 1e-6])
def test_cli_summary_period_not_the_time_span_one_line_exit_2(atlas_result, tmp_path, capsys,
                                                             period):  # fmt: skip
    """Was an OOM kill (1e7), a hang (1e4), a traceback ([1]), a wrong video (1e-6)."""
    folder = _period_folder(atlas_result[2], tmp_path, period)
    result = cli(capsys, "animate", folder, "--out", tmp_path / "a.mp4", "--fps", 5)
    one_line_error(result, "descriptors.period", "time span")
    assert not list(tmp_path.glob("**/*.mp4"))


def test_cli_summary_period_equal_to_the_span_is_animated(atlas_result, tmp_path, capsys):
    """Negative control: the span itself (as walk3d writes it) is accepted."""
    pred, _, folder = atlas_result
    folder = _period_folder(folder, tmp_path, float(pred.time[-1] - pred.time[0]))
    code, _, err = cli(capsys, "animate", folder, "--out", tmp_path / "a.mp4", "--cycles", 1,
                       "--fps", 5)  # fmt: skip
    assert code == 0 and (tmp_path / "a.mp4").is_file(), err


def test_save_animate_refuses_a_bad_period_before_writing(atlas_result, tmp_path):
    pred = walk3d.Prediction.of(atlas_result[0])
    bad = replace(pred, summary={**pred.summary, "descriptors": {"period": 1e7}})
    with pytest.raises(ValueError, match="descriptors.period"):
        bad.save(tmp_path / "s", animate=True, report=False)
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize(
    ("label", "reason", "frame_text"),
    [({"converged": False, "status": "Infeasible"},
      "the solve did not converge (Infeasible): not a valid prediction", "NOT CONVERGED"),
     ({"converged": True, "gait_checks": {"looks_like_walking": False}},
      "the gait does not look like walking (summary gait_checks)", "DOES NOT LOOK LIKE WALKING")],
)  # fmt: skip
def test_a_result_that_is_not_a_valid_prediction_is_labelled(atlas_result, tmp_path, capsys,
                                                            label, reason, frame_text):  # fmt: skip
    """Was exit 0 with nothing said, and an unlabelled video; the exit code stays 0."""
    from walk3d.plots.video import _Scene

    def frame_texts(summary: dict) -> list[str]:
        scene = _Scene(replace(pred, summary=summary), body, 1, 2)
        return [t.get_text() for t in scene.canvas.figure.texts]

    pred, body, folder = atlas_result
    copy = Path(shutil.copytree(folder, tmp_path / "r"))
    summary = json.loads((copy / "summary.json").read_text()) | label
    replace_result_file(copy, "summary.json", json.dumps(summary).encode())
    args = ("--cycles", 1, "--fps", 2)
    code, _, err = cli(capsys, "animate", copy, "--out", tmp_path / "a.mp4", *args)
    assert code == 0 and err.strip().splitlines() == [f"walk3d: warning: {copy}: {reason}"], err
    assert any(frame_text in t for t in frame_texts(summary))
    # negative control: a valid result is animated without a label or a warning
    valid = {**summary, "converged": True, "gait_checks": {"looks_like_walking": True}}
    assert not any("NOT" in t for t in frame_texts(valid))
    code, _, err = cli(capsys, "animate", folder, "--out", tmp_path / "b.mp4", *args)
    assert code == 0 and err == "", err
