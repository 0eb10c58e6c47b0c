"""``walk3d calibrate --out``: a path that is the trial's own file, lies in a walk3d result
folder, is not ``.json``, is a user's file, or whose figures would replace files of no earlier
calibration is refused in one line, exit code 2, before the fit, and every file is kept; a new
file and an earlier calibration with its figures reach the fit (the negative controls)."""

from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from helpers import cli, one_line_error  # noqa: E402
from result_support import bare_result_folder  # noqa: E402

EARLIER = json.dumps({"walk3d_calibration": 1, "rollover": {}})
"""An earlier calibration as walk3d knows one (its format key), content aside."""


@pytest.fixture
def trial(falisse, tmp_path):
    """Copies of the trial's files; the IK also as ``ik.json`` (an input named like an out)."""
    for name in ("gait_1_ik.mot", "gait_1_grf.mot"):
        shutil.copy(falisse / name, tmp_path / name)
    shutil.copy(falisse / "gait_1_ik.mot", tmp_path / "ik.json")
    return tmp_path


@pytest.fixture
def no_fit(monkeypatch):
    import walk3d.calibration.calibrate as calibrate

    def fit(*args, **kwargs):
        raise ValueError("the fit started")

    monkeypatch.setattr(calibrate, "calibrate_from_trial", fit)


def _snapshot(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in folder.rglob("*") if p.is_file()}


CASES = {
    "the --ik file": (lambda t: t / "ik.json", "is the --ik file, which walk3d reads"),
    "a result's summary": (lambda t: bare_result_folder(t / "p1") / "summary.json",
                           "is inside the walk3d result folder"),
    "a new file in a result": (lambda t: bare_result_folder(t / "p1") / "cal.json",
                               "is inside the walk3d result folder"),
    "no .json": (lambda t: t / "noext", "--out must name a .json file, got"),
    "a user's json": (lambda t: _write(t / "user.json", '{"mine": 1}'),
                      "exists and is not a walk3d calibration"),
    "a user's figure": (lambda t: _write(t / "c_rollover.png", "mine").with_name("c.json"),
                        "the figure"),
}  # fmt: skip


def _write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


@pytest.mark.parametrize("case", CASES)
def test_an_out_walk3d_must_not_write_is_refused_before_the_fit(trial, capsys, no_fit, case):
    make, words = CASES[case]
    ik = "ik.json" if case == "the --ik file" else "gait_1_ik.mot"
    out = make(trial)
    before = _snapshot(trial)
    result = cli(capsys, "calibrate", "--ik", trial / ik, "--grf", trial / "gait_1_grf.mot",
                 "--out", out)  # fmt: skip
    one_line_error(result, "--out", words)
    assert _snapshot(trial) == before


@pytest.mark.parametrize("earlier", [False, True], ids=["new", "earlier-calibration"])
def test_a_new_out_or_an_earlier_calibration_reaches_the_fit(trial, capsys, no_fit, earlier):
    """Negative control: a new file, and an earlier calibration whose figures are beside it."""
    if earlier:
        _write(trial / "c.json", EARLIER)
        _write(trial / "c_rollover.png", "earlier figure")
        _write(trial / "c_transition.png", "earlier figure")
    result = cli(capsys, "calibrate", "--ik", trial / "gait_1_ik.mot", "--grf",
                 trial / "gait_1_grf.mot", "--out", trial / "c.json")  # fmt: skip
    one_line_error(result, "the fit started")


def test_the_api_refuses_an_out_that_is_its_input(trial):
    from walk3d.body.model import build_body
    from walk3d.calibration.calibrate import calibrate_from_trial

    with pytest.raises(ValueError, match=r"^out .*ik\.json is the ik file, which walk3d reads"):
        calibrate_from_trial(trial / "ik.json", trial / "gait_1_grf.mot", build_body(),
                             trial / "ik.json")  # fmt: skip
    with pytest.raises(ValueError, match="^out must name a .json file"):
        calibrate_from_trial(trial / "gait_1_ik.mot", trial / "gait_1_grf.mot", build_body(),
                             trial / "c.txt")  # fmt: skip
