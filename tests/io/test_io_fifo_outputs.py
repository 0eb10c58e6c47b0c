"""Every file a command will write is checked before any work: a FIFO (as a device or socket)
at a calibration's figure, at a report's or an audit's default path or at a sweep's table is
refused with one line and left as it is (issue #60: it was replaced by a regular file)."""

from __future__ import annotations

import os
import stat
import sys
from pathlib import Path

import pytest
from helpers import cli, one_line_error

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


def _is_fifo(path: Path) -> bool:
    return stat.S_ISFIFO(os.lstat(path).st_mode)


def test_replace_files_moves_nothing_when_one_target_is_a_fifo(tmp_path):
    from walk3d.outputs import replace_files

    (tmp_path / "a.json").write_text("old")
    os.mkfifo(tmp_path / "b.png")
    with pytest.raises(FileExistsError, match="b.png is not a regular file"):
        with replace_files(tmp_path, "a.json") as tmp:
            (tmp / "a.json").write_text("new")
            (tmp / "b.png").write_text("new")
    assert (tmp_path / "a.json").read_text() == "old" and _is_fifo(tmp_path / "b.png")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.json", "b.png"]  # no temporary
    # negative control: a regular file there, and both are replaced
    (tmp_path / "b.png").unlink()
    (tmp_path / "b.png").write_text("old")
    with replace_files(tmp_path, "a.json") as tmp:
        (tmp / "a.json").write_text("new")
        (tmp / "b.png").write_text("new")
    assert [(tmp_path / n).read_text() for n in ("a.json", "b.png")] == ["new", "new"]


def test_calibrate_refuses_a_fifo_at_a_figure_and_replaces_a_regular_file(
    falisse, tmp_path, capsys
):
    from walk3d.body.model import build_body
    from walk3d.calibration.calibrate import calibrate_from_trial

    ik, grf, out = falisse / "gait_1_ik.mot", falisse / "gait_1_grf.mot", tmp_path / "cal.json"
    for name in ("cal_rollover.png", "cal_transition.png"):
        os.mkfifo(tmp_path / name)
        one_line_error(cli(capsys, "calibrate", "--ik", ik, "--grf", grf, "--out", out),
                       name, "not a regular file")  # fmt: skip
        with pytest.raises(ValueError, match=f"{name} is not a regular file"):  # no trial read
            calibrate_from_trial(tmp_path / "none.mot", grf, build_body(), out)
        assert _is_fifo(tmp_path / name) and sorted(os.listdir(tmp_path)) == [name]
        (tmp_path / name).unlink()
    # negative control: an earlier calibration's regular files at the same places are replaced
    out.write_text('{"walk3d_calibration": 1}')
    for name in ("cal_rollover.png", "cal_transition.png"):
        (tmp_path / name).write_text("the earlier figure")
    code, _, err = cli(capsys, "calibrate", "--ik", ik, "--grf", grf, "--out", out)
    assert code == 0, err
    for name in ("cal_rollover.png", "cal_transition.png"):
        assert (tmp_path / name).read_bytes().startswith(b"\x89PNG")


def test_report_refuses_a_fifo_at_its_default_page(tmp_path, capsys):
    from result_support import result_folder

    folder = result_folder(tmp_path / "r")
    (folder / "report.html").unlink(missing_ok=True)
    os.mkfifo(folder / "report.html")
    one_line_error(cli(capsys, "report", folder), "report.html", "not a regular file")
    assert _is_fifo(folder / "report.html")
    # negative control: a regular file there is replaced
    (folder / "report.html").unlink()
    (folder / "report.html").write_text("the earlier page")
    code, _, err = cli(capsys, "report", folder)
    assert code == 0, err
    assert (folder / "report.html").read_text().startswith("<!")


def test_audit_refuses_a_fifo_at_its_default_file(tmp_path, capsys):
    tracked = tmp_path / "tracked"
    tracked.mkdir()
    os.mkfifo(tracked / "audit.json")
    one_line_error(cli(capsys, "audit", tracked, tmp_path), "audit.json", "not a regular file")
    assert _is_fifo(tracked / "audit.json")
    # negative control: with a regular file there, the check passes and the folder is read
    (tracked / "audit.json").unlink()
    (tracked / "audit.json").write_text('{"criterion": "", "terms": [], "limb_work": {}, '
                                        '"bursts": {}}')  # an earlier audit  # fmt: skip
    code, _, err = cli(capsys, "audit", tracked, tmp_path)
    assert code == 2 and "not a regular file" not in err, err


@pytest.mark.parametrize("name", ["sweep.csv", "sweep.png"])
def test_sweep_refuses_a_fifo_at_its_table_or_figure_before_any_solve(tmp_path, capsys, name):
    out = tmp_path / "s"
    out.mkdir()
    (out / "sweep.json").write_text("not json")  # an earlier sweep's folder
    os.mkfifo(out / name)
    one_line_error(cli(capsys, "sweep", "--speeds", "1.2", "--out", out), name,
                   "not a regular file")  # fmt: skip
    assert _is_fifo(out / name)
    # negative control: with a regular file there, the check passes and sweep.json is read
    (out / name).unlink()
    (out / name).write_text("the earlier table")
    one_line_error(cli(capsys, "sweep", "--speeds", "1.2", "--out", out), "sweep.json")
