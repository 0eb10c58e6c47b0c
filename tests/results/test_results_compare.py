"""walk3d compare: two predictions side by side, every DoF's angle and moment and the criteria
(issue #43). On the shipped atlas solution, no solve."""

from __future__ import annotations

import csv
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from walk3d.body.model import build_body
from walk3d.results.compare import COLUMNS, compare, dof_moments

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "verify"))


@pytest.fixture(scope="module")
def pred():
    from verify_support import atlas_prediction

    p, _ = atlas_prediction()
    objective = {"C_tor": {"total": 2.0, "x": 1.0, "y": 0.5, "z": 0.5}}
    return replace(p, summary={**p.summary, "objective": objective, "converged": True})


def _rows(rows, group):
    return {r["quantity"]: r for r in rows if r["group"] == group}


def test_dof_moments_are_the_joint_moments_on_each_dofs_axis(pred):
    m = dof_moments(pred)
    names, joints = list(pred.dof_names), list(pred.joint_names)
    assert m.shape == (pred.time.size, 24)
    np.testing.assert_array_equal(m[:, names.index("knee_flexion_r")],
                                  pred.joint_moment[:, joints.index("knee_r"), 2])  # fmt: skip
    np.testing.assert_array_equal(m[:, names.index("subtalar_inversion_l")],
                                  pred.joint_moment[:, joints.index("ankle_l"), 0])  # fmt: skip
    # every DoF once: the active axes of the joints, nothing else
    assert int(pred.joint_axis_active.sum()) == 24 == sum(j.n_dof for j in build_body().joints)


def test_a_prediction_against_itself_changes_nothing(pred):
    rows = compare(pred, pred)
    assert len(rows) == 1 + 1 + 48  # C_tor, body mass, 24 angles, 24 moments
    for r in rows:
        assert r["largest_change"] == 0.0 and r.get("rms_change", 0.0) == 0.0


def test_a_changed_angle_and_mass_show_where_they_changed(pred):
    names = list(pred.dof_names)
    k = names.index("ankle_dorsiflexion_r")
    angle = pred.joint_angle.copy()
    angle[:, k] += np.radians(5.0)
    mass = pred.segment_mass.copy()
    mass[1] += 10.0  # torso
    other = replace(pred, joint_angle=angle, segment_mass=mass)
    rows = compare(pred, other)
    angles, moments = _rows(rows, "angle"), _rows(rows, "moment")
    assert angles["ankle_dorsiflexion_r"]["rms_change"] == pytest.approx(5.0)
    assert angles["ankle_dorsiflexion_r"]["b_max"] == pytest.approx(
        angles["ankle_dorsiflexion_r"]["a_max"] + 5.0)  # fmt: skip
    assert all(r["rms_change"] == 0.0 for n, r in angles.items() if n != "ankle_dorsiflexion_r")
    assert _rows(rows, "body")["body_mass"]["largest_change"] == pytest.approx(10.0)
    # moments are per body mass: the same N·m over a heavier body
    knee = moments["knee_flexion_r"]
    assert knee["b_max"] == pytest.approx(knee["a_max"] * pred.body_mass / other.body_mass)


def test_predictions_on_other_grids_do_not_compare(pred):
    from types import SimpleNamespace

    fewer = SimpleNamespace(dof_names=pred.dof_names, time=pred.time[::2])
    with pytest.raises(ValueError, match="same DoFs and cycle samples"):
        compare(pred, fewer)
    renamed = SimpleNamespace(dof_names=pred.dof_names[::-1], time=pred.time)
    with pytest.raises(ValueError, match="same DoFs and cycle samples"):
        compare(pred, renamed)


def test_cli_writes_the_table_and_figure_and_refuses_a_non_result(pred, tmp_path):
    import walk3d

    a, b = tmp_path / "a", tmp_path / "b"
    walk3d.Prediction.of(pred).save(a, figure=False, report=False)
    walk3d.Prediction.of(pred).save(b, figure=False, report=False)
    out = tmp_path / "cmp"
    cmd = [sys.executable, "-m", "walk3d.cli", "compare", str(a), str(b), "--out", str(out)]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    with open(out / "compare.csv", newline="") as handle:
        table = list(csv.DictReader(handle))
    assert tuple(table[0]) == COLUMNS and len(table) == 50
    assert (out / "compare.png").stat().st_size > 10_000
    page = (out / "report.html").read_text(encoding="utf-8")
    assert "Criteria and body" in page and 'src="data:image/png;base64,' in page
    assert page.count("<tr>") == len(table) + 2  # every row, plus the two tables' headers
    (out / "notes.txt").write_text("mine")  # a file walk3d did not write: refused, kept
    again = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert again.returncode == 2 and "notes.txt" in again.stderr, again.stderr
    assert (out / "notes.txt").read_text() == "mine"
    bad = subprocess.run(cmd[:4] + [str(tmp_path / "nothing"), str(b)], capture_output=True,
                         text=True, timeout=120)  # fmt: skip
    assert bad.returncode == 2 and len(bad.stderr.strip().splitlines()) == 1, bad.stderr
    assert "Traceback" not in bad.stderr


def _compare_cli(capsys, a, b, out) -> tuple[int, str]:
    from walk3d.cli import main

    with pytest.raises(SystemExit) as info:
        main(["compare", str(a), str(b), "--out", str(out)])
    return info.value.code, capsys.readouterr().err


def test_compare_on_a_full_disk_exits_3_and_removes_only_what_it_created(pred, tmp_path, capsys,
                                                                          monkeypatch):  # fmt: skip
    """The half-written folder (compare.csv without the figure and page) was left behind. A
    new folder and the new folders above it go; an earlier comparison and a user's empty
    folder stay as they were. The full disk is an ENOSPC from the second file's sync."""
    from disk_support import full_disk, snapshot

    import walk3d

    a, b = tmp_path / "a", tmp_path / "b"
    walk3d.Prediction.of(pred).save(a, figure=False, report=False)
    walk3d.Prediction.of(pred).save(b, figure=False, report=False)
    earlier, empty = tmp_path / "earlier", tmp_path / "empty"
    assert _compare_cli(capsys, a, b, earlier)[0] == 0
    empty.mkdir()
    before = {"earlier": snapshot(earlier), "top": sorted(p.name for p in tmp_path.iterdir())}
    for out in (tmp_path / "new" / "deeper" / "cmp", earlier, empty):
        synced = full_disk(monkeypatch, after=1)
        code, err = _compare_cli(capsys, a, b, out)
        monkeypatch.undo()
        lines = err.strip().splitlines()
        assert code == 3 and len(lines) == 1 and "Traceback" not in err, err
        assert lines[0] == f"walk3d: error: could not write {out}: no space left on device"
        assert len(synced) == 1  # control: compare.csv was written before the disk filled up
    assert sorted(p.name for p in tmp_path.iterdir()) == before["top"]  # no "new", no temporary
    assert snapshot(earlier) == before["earlier"] and list(empty.iterdir()) == []
    # control: with room, the new folder is written
    assert _compare_cli(capsys, a, b, tmp_path / "new" / "deeper" / "cmp")[0] == 0
    assert sorted(p.name for p in (tmp_path / "new" / "deeper" / "cmp").iterdir()) == [
        "compare.csv", "compare.png", "report.html"]  # fmt: skip


@pytest.mark.parametrize(
    ("label", "words"),
    [({"converged": False, "status": "Maximum_Iterations_Exceeded"}, "did not converge"),
     ({"gait_checks": {"looks_like_walking": False}}, "does not look like walking")],
)  # fmt: skip
def test_cli_names_and_marks_a_result_that_is_not_a_valid_prediction(pred, tmp_path, capsys,
                                                                    label, words):  # fmt: skip
    """Was exit 0 with neither the console nor report.html saying so; the exit code stays."""
    import walk3d

    good, bad = tmp_path / "good", tmp_path / "bad"
    walk3d.Prediction.of(pred).save(good, figure=False, report=False)
    labelled = replace(pred, summary={**pred.summary, **label})
    walk3d.Prediction.of(labelled).save(bad, figure=False, report=False)
    code, err = _compare_cli(capsys, bad, good, tmp_path / "cmp")
    lines = err.strip().splitlines()
    assert code == 0 and len(lines) == 1 and lines[0].startswith(f"walk3d: warning: {bad}: ")
    assert words in lines[0], err
    page = (tmp_path / "cmp" / "report.html").read_text(encoding="utf-8")
    assert f"A = bad: the {'solve' if 'converge' in words else 'gait'}" in page and words in page
    # negative control: two valid results, no warning and no banner
    code, err = _compare_cli(capsys, good, good, tmp_path / "cmp2")
    assert code == 0 and err == "", err
    assert words not in (tmp_path / "cmp2" / "report.html").read_text(encoding="utf-8")
