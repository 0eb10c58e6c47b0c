"""A sweep folder written by a walk3d before a setting existed resumes while the new setting is
at its default, and is refused when it is not."""

import json

import pytest

from walk3d.campaign.sweep_folder import SweepMismatch, check_folder
from walk3d.problem.settings import PredictionSettings


def test_a_sweep_written_before_a_setting_existed_resumes_at_its_default(tmp_path):
    ours = PredictionSettings(speed=1.2)
    check_folder(tmp_path, ours)
    path = tmp_path / "sweep.json"
    data = json.loads(path.read_text())
    del data["settings"]["solver"]["contact_checks"]  # as written before the setting
    path.write_text(json.dumps(data))
    check_folder(tmp_path, ours)  # resumes
    with pytest.raises(SweepMismatch, match="other settings"):  # the control: not the default
        check_folder(tmp_path, PredictionSettings(speed=1.2, contact_checks=1))
