"""walk3d validate's readers: a degenerate cycle table (constant percent, two rows) and a
result.npz of random bytes are one line and exit code 2, and nothing is written."""

from __future__ import annotations

import shutil

import numpy as np
from helpers import cli, one_line_error, replace_result_file


def _falisse_rows(falisse) -> tuple[str, list[str]]:
    lines = (falisse / "cycle_right_leg_mean_sd.csv").read_text().splitlines()
    return lines[0], lines[1:]


def test_a_reference_with_a_constant_percent_column_is_refused(pred_dir, falisse, tmp_path,
                                                               capsys):  # fmt: skip
    head, rows = _falisse_rows(falisse)
    ref = tmp_path / "const.csv"
    ref.write_text("\n".join([head, *("50," + r.split(",", 1)[1] for r in rows)]) + "\n")
    out = tmp_path / "v"
    one_line_error(cli(capsys, "validate", pred_dir, "--reference", ref, "--out", out),
                    "const.csv", "not increasing")  # fmt: skip
    assert not out.exists()


def test_a_reference_of_two_rows_is_refused(pred_dir, falisse, tmp_path, capsys):
    head, rows = _falisse_rows(falisse)
    ref = tmp_path / "two.csv"
    ref.write_text("\n".join([head, rows[0], rows[-1]]) + "\n")
    out = tmp_path / "v"
    one_line_error(cli(capsys, "validate", pred_dir, "--reference", ref, "--out", out),
                    "two.csv", "2 data rows")  # fmt: skip
    assert not out.exists()


def test_the_same_table_with_its_rows_is_accepted_by_the_reader(falisse):
    """Negative control: the table the two refusals above damage is a valid reference."""
    from walk3d.io import read_cycle_table
    from walk3d.validation.reference import reference_from_table

    ref = reference_from_table(read_cycle_table(falisse / "cycle_right_leg_mean_sd.csv"))
    assert all(np.ptp(m) > 0 for m in ref.mean.values())


def test_random_bytes_in_result_npz_are_one_line(pred_dir, falisse, tmp_path, capsys):
    bad = shutil.copytree(pred_dir, tmp_path / "p")
    replace_result_file(bad, "result.npz", np.random.default_rng(2).bytes(4000))
    result = cli(capsys, "validate", bad, "--reference", falisse / "cycle_right_leg_mean_sd.csv",
                  "--out", tmp_path / "v")  # fmt: skip
    one_line_error(result, "result.npz", "not a walk3d result")
    assert "pickle" not in result[2]


def test_a_constant_reference_has_no_r_squared_of_minus_1e36():
    from walk3d.validation.compare import r_squared

    m = np.full(101, 0.3)
    assert np.isnan(r_squared(np.linspace(0, 1, 101), m))
    assert r_squared(m + np.sin(np.arange(101.0)), m + np.sin(np.arange(101.0))) == 1.0
