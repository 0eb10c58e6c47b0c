"""Criterion weights from TOML: both layouts read, bad files give one DataFileError line."""

import subprocess
import sys

import pytest

from walk3d.io.criterion import read_criterion
from walk3d.io.errors import DataFileError
from walk3d.model import terms


def test_top_level_and_table_layouts_give_the_same_criterion(tmp_path):
    a = tmp_path / "a.toml"
    a.write_text("tor = 1\naccel = 0.5\npelvis = 2\n")
    b = tmp_path / "b.toml"
    b.write_text("[criterion]\npelvis = 2.0\ntor = 1.0\naccel = 0.5\n")
    assert terms.canonical(read_criterion(a)) == terms.canonical(read_criterion(b))
    assert terms.parse(read_criterion(a)) == {"tor": 1.0, "accel": 0.5, "pelvis": 2.0}


@pytest.mark.parametrize(
    ("text", "words"),
    [("tor = ", "not a TOML file"), ("tor = 'one'", "must be a finite number"),
     ("tor = nan", "must be a finite number"), ("[other]\n", "weight of other"),
     ("", "no criterion weights"), ("tor = true", "must be a finite number"),
     ("tor = 1" + "0" * 400, "must be a finite number"),
     ('tor = 1\n"accel=5,head" = 0.5', "not a criterion term name")],
)  # fmt: skip
def test_bad_files_are_refused_naming_the_file(tmp_path, text, words):
    p = tmp_path / "w.toml"
    p.write_text(text)
    with pytest.raises(DataFileError, match=words) as info:
        read_criterion(p)
    assert str(info.value).startswith("w.toml")
    with pytest.raises(DataFileError, match="w2.toml"):
        read_criterion(tmp_path / "w2.toml")  # missing


def test_predict_reads_a_toml_criterion_and_refuses_a_bad_one(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("tor = 1\nwobble = 2\n")
    cmd = [sys.executable, "-m", "walk3d.cli", "predict", "--criterion", str(bad),
           "--out", str(tmp_path / "o")]  # fmt: skip
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and "wobble" in r.stderr and len(r.stderr.splitlines()) == 1
    assert not (tmp_path / "o").exists()


def test_a_model_table_is_read_beside_the_weights_in_either_layout(tmp_path):
    from walk3d.io.criterion import read_model_options, write_criterion

    a = tmp_path / "a.toml"
    a.write_text("tor = 1\nimpact = 2\n[model]\nheel_rise = 0.62\n")
    assert terms.parse(read_criterion(a)) == {"tor": 1.0, "impact": 2.0}
    assert read_model_options(a) == {"heel_rise": 0.62}
    b = write_criterion(tmp_path / "b.toml", {"tor": 1.0}, ["a note"], {"load_ramp": 1.5})
    assert read_model_options(b) == {"load_ramp": 1.5} and read_criterion(b) == "tor=1"
    plain = write_criterion(tmp_path / "c.toml", {"tor": 1.0}, [])  # the control: no table
    assert read_model_options(plain) == {} and "[model]" not in plain.read_text()


@pytest.mark.parametrize(("text", "words"), [
    ("tor = 1\n[model]\nsplit_terms = 2\n", "not a model option"),
    ("tor = 1\n[model]\nheel_rise = 'high'\n", "must be a finite number"),
    ("tor = 1\n[model]\nheel_rise = true\n", "must be a finite number"),
    ("tor = 1\nmodel = 3\n", "must be a table"),
])  # fmt: skip
def test_a_bad_model_table_is_one_line(tmp_path, text, words):
    from walk3d.io.criterion import read_model_options

    p = tmp_path / "m.toml"
    p.write_text(text)
    with pytest.raises(DataFileError, match=words):
        read_model_options(p)


def test_a_files_model_options_reach_the_settings_once(tmp_path):
    from walk3d.api import settings
    from walk3d.cli.common import settings_from_options

    p = tmp_path / "fitted.toml"
    p.write_text("tor = 1\nimpact = 2\n[model]\nheel_rise = 0.62\n")
    assert settings(1.3, criterion=str(p)).model.heel_rise == 0.62
    assert settings(1.3, criterion=str(p), heel_rise=0.62).model.heel_rise == 0.62
    with pytest.raises(ValueError, match="give it once"):
        settings(1.3, criterion=str(p), heel_rise=0.7)
    cli = settings_from_options(str(p), "ipopt", 0, speed=1.3, period=1.1, double_support=0.12)
    assert cli.model.heel_rise == 0.62 and terms.parse(cli.model.criterion)["impact"] == 2.0
    assert settings(1.3, criterion="natural").model.heel_rise is None  # the control
