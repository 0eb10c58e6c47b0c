"""walk3d atlas show on a folder with a stray or damaged file: the file is flagged in its row,
the other files are listed, exit code 0 and no traceback."""

from __future__ import annotations

import shutil

import pytest

import walk3d.solve.atlas as atlas_module
from walk3d.cli import main


@pytest.mark.parametrize("junk", [b"not json", b"[1, 2]", b'{"format": 3, "entries": [{}]}'])
def test_a_stray_json_file_is_flagged(tmp_path, monkeypatch, capsys, junk):
    shutil.copy(atlas_module.ATLAS_DIR / "male-natural.json", tmp_path / "male-natural.json")
    (tmp_path / "junk.json").write_bytes(junk)
    monkeypatch.setattr(atlas_module, "ATLAS_DIR", tmp_path)
    from walk3d.cli import common

    monkeypatch.setattr(common.console, "width", 250)  # one table row per file, unwrapped
    with pytest.raises(SystemExit) as info:
        main(["atlas", "show", "--no-check"])
    out, err = capsys.readouterr()
    assert info.value.code == 0 and err == "", err
    rows = {line.split("│")[1].strip(): line for line in out.splitlines() if "│" in line}
    assert "not a usable atlas" in rows["junk"] and "junk.json" in rows["junk"]
    assert "yes" in rows["male"]  # the control: the real file is listed as usable


def test_read_atlas_refuses_a_damaged_entry(tmp_path):
    import json

    data = json.loads((atlas_module.ATLAS_DIR / "male-natural.json").read_text())
    data["entries"][1]["period"] = float("nan")
    (tmp_path / "male-natural.json").write_text(json.dumps(data))
    with pytest.raises(ValueError, match="entry 1's period must be a finite number"):
        atlas_module.read_atlas(tmp_path / "male-natural.json")
    data["entries"][1]["period"] = 1.0
    data["entries"][2]["speed"] = data["entries"][1]["speed"]
    (tmp_path / "male-natural.json").write_text(json.dumps(data))
    with pytest.raises(ValueError, match="speeds is not increasing"):
        atlas_module.read_atlas(tmp_path / "male-natural.json")


@pytest.mark.parametrize("sex", ["male", "female"])
def test_every_shipped_entry_walks(monkeypatch, sex):
    """Each shipped entry's free-landing and handover optimum looks like walking by walk3d's
    own check, at its own speed, period and double support (issue #61); with the humps' bar
    raised to 0.3 body weight the slowest do not (the control)."""
    import numpy as np

    from walk3d.campaign.atlas_checks import walking_entries
    from walk3d.results import gait_checks

    a = atlas_module.read_atlas(atlas_module.ATLAS_DIR / f"{sex}-natural.json")
    assert walking_entries(a).all()
    has = np.isfinite(a.x_handover).all(axis=1)
    assert (walking_entries(a, handover=True) == has).all()
    monkeypatch.setattr(gait_checks, "SLOW_HUMPS", ((0.0, 0.3),))
    assert not walking_entries(a)[0]


def test_atlas_show_reports_td_fractions_and_walking_entries(monkeypatch, capsys):
    from walk3d.cli import common
    from walk3d.results import gait_checks

    monkeypatch.setattr(common.console, "width", 250)
    monkeypatch.setattr(gait_checks, "SLOW_HUMPS", ((0.0, 0.3),))  # the slowest do not walk
    with pytest.raises(SystemExit) as info:
        main(["atlas", "show"])
    out, _ = capsys.readouterr()
    assert info.value.code == 0
    male = next(line for line in out.splitlines() if "│ male" in line)
    assert "0.107-0.126" in male and "not: 0.4, 0.5, 0.6" in male
