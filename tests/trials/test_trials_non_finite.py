"""NaN inside a measured trial's files is refused by the commands that read them: one line
naming the file and the column, exit code 2, before any solve (issue: no silent wrong answer)."""

import subprocess
import sys

import pytest
from helpers import storage_with_nan


def _run(*args: str) -> subprocess.CompletedProcess:
    cmd = [sys.executable, "-m", "walk3d.cli", *args]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize(
    ("kind", "column", "rows"),
    [("ik", "knee_angle_r", range(40, 60)), ("grf", "ground_force_vy", range(2000, 2051))],
)
def test_predict_from_a_trial_with_nan_is_refused(falisse, tmp_path, kind, column, rows):
    ik, grf = falisse / "gait_1_ik.mot", falisse / "gait_1_grf.mot"
    bad = storage_with_nan(ik if kind == "ik" else grf, tmp_path / f"bad_{kind}.mot", column, rows)
    files = (bad, grf) if kind == "ik" else (ik, bad)
    r = _run("predict", "--from-trial", str(files[0]), "--grf", str(files[1]),
             "--out", str(tmp_path / "out"))  # fmt: skip
    assert r.returncode == 2, r.stderr[-500:]
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and bad.name in lines[0] and column in lines[0], r.stderr
    assert "Traceback" not in r.stderr and "pydantic" not in r.stderr
    assert not (tmp_path / "out").exists()


def test_calibrate_with_nan_in_the_vertical_force_is_refused(falisse, tmp_path):
    grf = storage_with_nan(falisse / "gait_1_grf.mot", tmp_path / "bad_grf.mot", "ground_force_vy",
                    range(2000, 2051))  # fmt: skip
    r = _run("calibrate", "--ik", str(falisse / "gait_1_ik.mot"), "--grf", str(grf),
             "--out", str(tmp_path / "calib.json"))  # fmt: skip
    assert r.returncode == 2, r.stderr[-500:]
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "bad_grf.mot" in lines[0] and "ground_force_vy" in lines[0]
    assert not (tmp_path / "calib.json").exists()
    # negative control: the clean files calibrate
    ok = _run("calibrate", "--ik", str(falisse / "gait_1_ik.mot"), "--grf",
              str(falisse / "gait_1_grf.mot"), "--out", str(tmp_path / "ok.json"))  # fmt: skip
    assert ok.returncode == 0, ok.stderr[-500:]
