"""walk3d report's readers: a --data folder of malformed or non-finite tables is one line and
exit code 2, as an empty one is; NaN in result.npz's joint angles likewise."""

from __future__ import annotations

import io

import numpy as np
import pytest
from helpers import cli, one_line_error, replace_result_file
from report_support import DATA, needs_data

from walk3d.report.norms import load_norms

FALISSE = "falisse2019/cycle_right_leg_mean_sd.csv"


def _data(tmp_path, content: bytes):
    folder = tmp_path / "data"
    (folder / FALISSE).parent.mkdir(parents=True)
    (folder / FALISSE).write_bytes(content)
    return folder


def _nan_table() -> bytes:
    rows = ["percent_cycle,knee_angle_deg_mean,knee_angle_deg_sd"]
    rows += [f"{p},nan,nan" for p in range(101)]
    return ("\n".join(rows) + "\n").encode()


@pytest.mark.parametrize("content", [np.random.default_rng(5).bytes(3000), _nan_table(), b""],
                         ids=["random-bytes", "nan-table", "empty-file"])  # fmt: skip
def test_malformed_or_non_finite_data_is_one_line(result_folder, tmp_path, capsys, content):
    data = _data(tmp_path, content)
    out = tmp_path / "r.html"
    one_line_error(cli(capsys, "report", result_folder, "--out", out, "--data", data),
                    "--data", "cycle_right_leg_mean_sd.csv")  # fmt: skip
    assert not out.exists()
    assert load_norms(data).notes  # found by itself, the same data is skipped with a note


def test_an_empty_data_folder_is_one_line(result_folder, tmp_path, capsys):
    (tmp_path / "empty").mkdir()
    one_line_error(cli(capsys, "report", result_folder, "--out", tmp_path / "r.html",
                         "--data", tmp_path / "empty"), "--data")  # fmt: skip


@needs_data
def test_the_measured_data_gives_bands(result_folder, tmp_path, capsys):
    """Negative control: the real table is accepted and gives bands."""
    code, out, err = cli(capsys, "report", result_folder, "--out", tmp_path / "r.html",
                          "--data", DATA)  # fmt: skip
    assert code == 0 and "bands from" in " ".join(out.split()), err


def test_nan_joint_angles_in_result_npz_are_one_line(fresh_folder, tmp_path, capsys):
    with np.load(fresh_folder / "result.npz") as z:
        arrays = {k: z[k] for k in z.files}
    arrays["joint_angle"][5, 0] = np.nan
    buffer = io.BytesIO()
    np.savez(buffer, **arrays)
    replace_result_file(fresh_folder, "result.npz", buffer.getvalue())
    for command in ("report", "animate"):
        out = tmp_path / ("r.html" if command == "report" else "a.mp4")
        one_line_error(cli(capsys, command, fresh_folder, "--out", out),
                        "result.npz", "joint_angle", "non-finite")  # fmt: skip
        assert not out.exists()
