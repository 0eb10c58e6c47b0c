"""``walk3d validate --out`` writes all of its files or none: a full disk is exit 3 with the
folder in its one line and the earlier validation intact, Ctrl-C leaves nothing, and a folder
of other files is refused before any work (tests/disk_support.py injects the full disk)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from disk_support import full_disk, snapshot  # noqa: E402

TABLES = 3
"""table2.csv, table3.csv and measured_fit.csv, written before the figures."""


@pytest.fixture()
def table(falisse):
    return falisse / "cycle_right_leg_mean_sd.csv"


def _validate(capfd, *args) -> tuple[int, str]:
    from walk3d.cli import main

    with pytest.raises(SystemExit) as info:
        main(["validate", *map(str, args)])
    return info.value.code, capfd.readouterr().err


def test_validate_on_a_full_disk_exits_3_and_keeps_the_earlier_validation(
    pred_dir, table, tmp_path, capfd, monkeypatch
):
    out = tmp_path / "v"
    out.mkdir()
    (out / "table2.csv").write_text("the earlier table 2\n")
    (out / "grf.png").write_bytes(b"the earlier figure")
    before = snapshot(tmp_path)
    synced = full_disk(monkeypatch, after=TABLES)
    code, err = _validate(capfd, pred_dir, "--reference", table, "--out", out)
    assert code == 3, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    assert lines[0] == f"walk3d: error: could not write {out}: no space left on device"
    assert len(synced) == TABLES  # control: the tables were written when the disk filled up
    assert snapshot(tmp_path) == before and [p.name for p in tmp_path.iterdir()] == ["v"]


def test_validate_interrupted_while_writing_leaves_nothing(
    synthetic_prediction, table, tmp_path, monkeypatch
):
    from walk3d.validation.run import validate

    synced = full_disk(monkeypatch, after=TABLES, error=KeyboardInterrupt)
    with pytest.raises(KeyboardInterrupt):
        validate({"p": synthetic_prediction}, [table], tmp_path / "v")
    assert len(synced) == TABLES  # control: interrupted after the tables, before the figures
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("kind", ["folder of other files", "existing file"])
def test_validate_refuses_an_out_it_did_not_write(
    synthetic_prediction, pred_dir, table, tmp_path, capfd, kind
):
    from walk3d.validation.run import validate

    out = tmp_path / "mine"
    if kind == "existing file":
        out.write_text("mine")
    else:
        out.mkdir()
        (out / "thesis.txt").write_text("mine")
    before = snapshot(tmp_path)
    code, err = _validate(capfd, pred_dir, "--reference", table, "--out", out)
    assert code == 2 and len(err.strip().splitlines()) == 1 and kind in err, err
    with pytest.raises(ValueError, match=kind):  # the library refuses it too
        validate({"p": synthetic_prediction}, [table], out)
    assert snapshot(tmp_path) == before


def test_validate_refuses_an_earlier_validation_holding_a_file_of_the_user(
    synthetic_prediction, pred_dir, table, tmp_path, capfd
):
    """An earlier validation was replaced with the user's notes in it; now it is refused,
    naming them. Control: the earlier validation alone (and its temporaries) is replaced."""
    from walk3d.validation.run import validate

    out = tmp_path / "v"
    out.mkdir()
    for name in ("table2.csv", "table3.csv", "grf.png", ".table2.csv.0123456789ab.tmp"):
        (out / name).write_text("walk3d's")
    (out / "notes.txt").write_text("mine")
    before = snapshot(tmp_path)
    code, err = _validate(capfd, pred_dir, "--reference", table, "--out", out)
    assert code == 2 and len(err.strip().splitlines()) == 1 and "(notes.txt)" in err, err
    with pytest.raises(ValueError, match="did not write"):
        validate({"p": synthetic_prediction}, [table], out)
    assert snapshot(tmp_path) == before
    (out / "notes.txt").unlink()
    code, err = _validate(capfd, pred_dir, "--reference", table, "--out", out)
    assert code == 0, err
    assert (out / "table2.csv").read_text() != "walk3d's" and not (out / "notes.txt").exists()


@pytest.mark.parametrize("kind", ["link to an earlier validation", "dangling link", "folder"])
def test_validate_refuses_an_out_that_is_a_symbolic_link(
    synthetic_prediction, pred_dir, table, tmp_path, capfd, kind
):
    """--out linked to an earlier validation became a real folder, and the user's link was left
    as .tmp_old_<name>_<hex> for ever; a dangling one failed after the work. Now it is refused
    before any work, and the link kept. Negative control: the folder it points to validates."""
    from walk3d.validation.run import validate

    earlier = tmp_path / "earlier"
    assert validate({"p": synthetic_prediction}, [table], earlier, figures=False).table2
    link = tmp_path / "link"
    link.symlink_to(earlier if kind.startswith("link") else tmp_path / "nothing")
    out = earlier if kind == "folder" else link
    code, err = _validate(capfd, pred_dir, "--reference", table, "--out", out)
    if kind == "folder":
        assert code == 0, err
        return
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert f"--out {link} is a symbolic link" in err, err
    before = snapshot(tmp_path)
    with pytest.raises(ValueError, match="is a symbolic link"):  # the library refuses it too
        validate({"p": synthetic_prediction}, [table], link)
    assert snapshot(tmp_path) == before and link.is_symlink()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["earlier", "link"]
