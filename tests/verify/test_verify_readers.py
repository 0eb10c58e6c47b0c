"""walk3d verify's readers: junk grf.xml, NaN in motion.mot, random bytes in result.npz and a
non-finite --timeout are one line and exit code 2 (OpenSim is never started for them)."""

from __future__ import annotations

import shutil

import numpy as np
import pytest
from helpers import cli, one_line_error, replace_result_file, storage_with_nan

import walk3d.verify.run as run_module
from walk3d.io.errors import DataFileError
from walk3d.verify.periodic import periodic_records


@pytest.fixture()
def folder(saved_atlas_prediction, tmp_path, monkeypatch):
    """A private copy of the saved prediction, OpenSim taken as installed (not run)."""
    monkeypatch.setattr(run_module, "opensim_available", lambda: True)
    return shutil.copytree(saved_atlas_prediction[2], tmp_path / "p")


def test_the_good_folder_extends_periodically(folder, tmp_path):
    """Negative control: the files the tests below damage are read."""
    motion, loads = periodic_records(folder / "motion.mot", folder / "grf.xml", tmp_path)
    assert motion.is_file() and loads.is_file()


def test_junk_grf_xml_is_one_line(folder, capsys):
    replace_result_file(folder, "grf.xml", b"<<<not xml")
    one_line_error(cli(capsys, "verify", folder), "grf.xml:1", "invalid XML")


def test_an_unknown_encoding_in_grf_xml_is_one_line(folder, capsys):
    """It was a LookupError traceback (the fuzz set, ``-m fuzz``)."""
    text = (folder / "grf.xml").read_text(encoding="utf-8")
    replace_result_file(folder, "grf.xml", text.replace("UTF-8", "UTF-Infinity", 1).encode())
    one_line_error(cli(capsys, "verify", folder), "grf.xml", "unknown encoding 'UTF-Infinity'")


def test_nan_in_motion_names_the_column_not_the_time_range(folder, tmp_path, capsys):
    bad = storage_with_nan(folder / "motion.mot", tmp_path / "m.mot", "knee_angle_r", range(4, 6))
    replace_result_file(folder, "motion.mot", bad.read_bytes())
    with pytest.raises(DataFileError, match="'knee_angle_r' is not finite in 2 rows"):
        periodic_records(folder / "motion.mot", folder / "grf.xml", tmp_path)
    result = cli(capsys, "verify", folder)
    one_line_error(result, "motion.mot", "knee_angle_r", "not finite")
    assert "time range" not in result[2]


def test_random_bytes_in_result_npz_say_it_is_not_a_walk3d_result(folder, capsys):
    replace_result_file(folder, "result.npz", np.random.default_rng(3).bytes(3000))
    result = cli(capsys, "verify", folder)
    one_line_error(result, "not a walk3d result")
    assert "allow_pickle" not in result[2]


@pytest.mark.parametrize("timeout", ["inf", "1e999", "3000000", "1e20", "1e308", "86401"])
def test_an_infinite_timeout_is_one_line(tmp_path, capsys, timeout):
    one_line_error(cli(capsys, "verify", tmp_path, "--timeout", timeout), "--timeout", "finite")


def test_a_finite_timeout_passes_its_check(tmp_path, capsys):
    """Negative control: a finite timeout gets as far as the folder."""
    for ok in ("5", "86400"):
        one_line_error(cli(capsys, "verify", tmp_path / "none", "--timeout", ok), "not a result")
    for bad in (float("inf"), 3e6, 1e308):
        with pytest.raises(ValueError, match="at most 86400"):
            run_module.verify_folder(tmp_path, timeout=bad)


def test_the_help_shows_the_opensim_extra(capsys):
    code, out, _ = cli(capsys, "verify", "--help")
    assert code == 0 and "walk3d[opensim]" in " ".join(out.split())
