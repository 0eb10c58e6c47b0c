"""walk3d verify's bad input: one line and exit code 2 (also without OpenSim)."""

from __future__ import annotations

import subprocess
import sys

import pytest

import walk3d.verify.run as run_module
from walk3d.cli import main


def test_a_missing_folder_is_one_line_and_exit_2(tmp_path):
    r = subprocess.run([sys.executable, "-m", "walk3d.cli", "verify", str(tmp_path / "none")],
                       capture_output=True, text=True, timeout=120)  # fmt: skip
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "not a result folder" in lines[0]


def test_without_opensim_it_says_how_to_install_it(saved_atlas_prediction, monkeypatch, capsys):
    """A complete result folder, and no OpenSim: the install hint (a folder that is not a
    result gets the message above first, with or without OpenSim)."""
    monkeypatch.setattr(run_module, "opensim_available", lambda: False)
    with pytest.raises(SystemExit) as exit_info:
        main(["verify", str(saved_atlas_prediction[2])])
    assert exit_info.value.code == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "pip install 'walk3d[opensim]'" in lines[0]
