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
