"""``walk3d calibrate`` writes the calibration file and its two figures together or not at
all: a full disk is exit 3 with the file in its one line and the earlier calibration intact,
Ctrl-C leaves nothing (tests/disk_support.py injects the full disk)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from disk_support import full_disk, snapshot  # noqa: E402


def _calibrate(capfd, falisse, out) -> tuple[int, str]:
    from walk3d.cli import main

    args = ["calibrate", "--ik", falisse / "gait_1_ik.mot", "--grf", falisse / "gait_1_grf.mot",
            "--out", out]  # fmt: skip
    with pytest.raises(SystemExit) as info:
        main([str(a) for a in args])
    return info.value.code, capfd.readouterr().err


def test_calibrate_on_a_full_disk_exits_3_and_keeps_the_earlier_calibration(
    falisse, tmp_path, capfd, monkeypatch
):
    out = tmp_path / "c.json"
    for name in ("c.json", "c_rollover.png", "c_transition.png"):  # an earlier calibration's
        (tmp_path / name).write_text(f'{{"walk3d_calibration": 1, "was": "the earlier {name}"}}')
    (tmp_path / "notes.txt").write_text("the user's")
    before = snapshot(tmp_path)
    synced = full_disk(monkeypatch, after=1)
    code, err = _calibrate(capfd, falisse, out)
    assert code == 3, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    assert lines[0] == f"walk3d: error: could not write {out}: no space left on device"
    assert len(synced) == 1  # control: the calibration file was made when the disk filled up
    assert snapshot(tmp_path) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(before)  # no temporary
    monkeypatch.undo()  # control: with room, all three are replaced and the rest kept
    code, err = _calibrate(capfd, falisse, out)
    assert code == 0, err
    after = snapshot(tmp_path)
    assert sorted(after) == sorted(before) and after["notes.txt"] == before["notes.txt"]
    assert all(after[n] != before[n] for n in ("c.json", "c_rollover.png", "c_transition.png"))


def test_calibrate_interrupted_while_writing_leaves_nothing(falisse, tmp_path, monkeypatch):
    from walk3d.body.model import build_body
    from walk3d.calibration.calibrate import calibrate_from_trial

    synced = full_disk(monkeypatch, after=2, error=KeyboardInterrupt)
    with pytest.raises(KeyboardInterrupt):
        calibrate_from_trial(falisse / "gait_1_ik.mot", falisse / "gait_1_grf.mot",
                             build_body(), tmp_path / "c.json")  # fmt: skip
    assert len(synced) == 2  # control: interrupted between the two figures
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("option", "value"),
    [("--speed", "nan"), ("--speed", "inf"), ("--speed", "-1"), ("--mass", "nan"),
     ("--mass", "inf"), ("--mass", "-68.8"), ("--height", "nan"), ("--height", "-1.77"),
     ("--threshold", "nan"), ("--threshold", "0")],
)  # fmt: skip
def test_calibrate_refuses_a_value_that_is_not_a_finite_positive_number_before_any_work(
    falisse, tmp_path, capfd, monkeypatch, option, value
):
    """--speed nan was fitted and then failed writing JSON ("Out of range float values are
    not JSON compliant: nan"); now it is the option's one line before the fit starts."""
    import walk3d.calibration.calibrate as calibrate

    def fit(*args, **kwargs):
        raise ValueError("the fit started")

    monkeypatch.setattr(calibrate, "calibrate_from_trial", fit)
    from walk3d.cli import main

    args = ["calibrate", "--ik", falisse / "gait_1_ik.mot", "--grf", falisse / "gait_1_grf.mot",
            "--out", tmp_path / "c.json"]  # fmt: skip
    with pytest.raises(SystemExit) as info:
        main([*map(str, args), option, value])
    lines = capfd.readouterr().err.strip().splitlines()
    assert info.value.code == 2 and len(lines) == 1, lines
    got = float(value)  # as typer parsed it: nan, inf, -1.0
    assert lines[0] == f"walk3d: error: {option} must be a finite positive number, got {got}"
    with pytest.raises(SystemExit) as info:  # control: a good value reaches the fit
        main([*map(str, args), option, "1.2" if option != "--mass" else "68.8"])
    err = capfd.readouterr().err
    assert info.value.code == 2 and "the fit started" in err and option not in err, err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("name", ["speed", "threshold"])
def test_calibrate_from_trial_refuses_a_non_finite_value_first(tmp_path, name):
    from walk3d.body.model import build_body
    from walk3d.calibration.calibrate import calibrate_from_trial

    with pytest.raises(ValueError, match=f"^{name} must be a finite positive number, got nan$"):
        calibrate_from_trial(tmp_path / "no.mot", tmp_path / "no.mot", build_body(),
                             tmp_path / "c.json", **{name: float("nan")})  # fmt: skip
    with pytest.raises(FileNotFoundError):  # control: a good value goes on to read the files
        calibrate_from_trial(tmp_path / "no.mot", tmp_path / "no.mot", build_body(),
                             tmp_path / "c.json", **{name: 1.2})  # fmt: skip
    assert list(tmp_path.iterdir()) == []
