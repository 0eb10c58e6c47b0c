"""``walk3d track`` and ``walk3d audit``: bad input gets one line and exit 2 before any solve
(each with its control); the tracking of the shared Falisse trial (solve-marked)."""

import json
import os
import stat
import time

import numpy as np
import pytest
from helpers import cli, one_line_error, shared_data_dir, storage_with_nan

from walk3d.io.storage import read_storage, write_storage

FALISSE = shared_data_dir() / "falisse2019"
needs_data = pytest.mark.skipif(not FALISSE.is_dir(), reason=f"no shared data at {FALISSE}")
SUBJECT = ("--mass", "62", "--height", "1.7", "--sex", "female")


def _args(ik, grf, out):
    return ("track", "--ik", ik, "--grf", grf, *SUBJECT, "--out", out)


def test_track_needs_one_measured_gait(capsys, tmp_path):
    one_line_error(cli(capsys, "track", "--out", tmp_path / "o"), "--ik", "--table")
    one_line_error(cli(capsys, "track", "--ik", "a.mot", "--out", tmp_path / "o"), "--grf")
    both = cli(capsys, "track", "--table", "t.csv", "--ik", "a.mot", "--grf", "b.mot", "--out",
               tmp_path / "o")  # fmt: skip
    one_line_error(both, "not both", "--table and --ik and --grf")
    one_line_error(cli(capsys, "track", "--table", "t.csv", "--grf", "b.mot",
                       "--out", tmp_path / "o"), "not both", "--table and --grf")  # fmt: skip
    one_line_error(cli(capsys, "track", "--table", tmp_path / "none.csv", "--out", tmp_path / "o"),
                   "none.csv")  # fmt: skip
    for bad in ("loop", "loop=x", "knee=3", "loop=-1", "loop=1,loop=2"):
        one_line_error(cli(capsys, "track", "--table", "t.csv", "--relax", bad,
                           "--out", tmp_path / "o"), "--relax")  # fmt: skip


def test_the_track_term_needs_a_tracking(capsys, tmp_path):
    one_line_error(cli(capsys, "predict", "--criterion", "natural,track=1", "--out",
                       tmp_path / "p"), "track")  # fmt: skip


class Audited(Exception):
    """walk3d.tracking.audit was reached: the command accepted its input."""


def _audit_reached(monkeypatch) -> None:
    import walk3d.tracking as tracking

    def audit(*args, **kwargs):
        raise Audited

    monkeypatch.setattr(tracking, "audit", audit)


@pytest.mark.parametrize(
    ("name", "words"),
    [("fifo.json", "not a regular file"), ("folder.json", "is a folder"),
     ("x\udcff.json", "not valid UTF-8"), ("file/a.json", "is a file"),
     ("a" * 300 + ".json", "bytes long"), ("a.txt", "must name a .json file")],
    ids=["fifo", "folder", "byte-ff", "under-a-file", "300-bytes", "suffix"],
)  # fmt: skip
def test_audit_refuses_an_out_that_is_not_a_writable_json_file_before_the_audit(
    capsys, tmp_path, monkeypatch, name, words
):
    """--out was checked for its suffix only: a FIFO, a folder or a non-UTF-8 name failed after
    the audit (exit 3), the shared check of the other commands' --out was not made."""
    _audit_reached(monkeypatch)
    os.mkfifo(tmp_path / "fifo.json")
    (tmp_path / "folder.json").mkdir()
    (tmp_path / "file").write_text("mine")
    one_line_error(cli(capsys, "audit", tmp_path / "t", tmp_path / "p", "--out", tmp_path / name),
                   "--out", words)  # fmt: skip
    assert stat.S_ISFIFO(os.stat(tmp_path / "fifo.json").st_mode)
    assert (tmp_path / "file").read_text() == "mine"


def test_audit_with_a_writable_out_reaches_the_audit(capsys, tmp_path, monkeypatch):
    """Negative control: a new .json file, and an earlier audit to replace."""
    _audit_reached(monkeypatch)
    (tmp_path / "old.json").write_text('{"criterion": "", "terms": [], "limb_work": {}, '
                                       '"bursts": {}}')  # fmt: skip
    for name in ("new.json", "old.json"):
        with pytest.raises(Audited):
            cli(capsys, "audit", tmp_path / "t", tmp_path / "p", "--out", tmp_path / name)


@needs_data
def test_bad_trials_get_one_line_before_any_solve(capsys, tmp_path):
    ik, grf = FALISSE / "gait_1_ik.mot", FALISSE / "gait_1_grf.mot"
    ik_store = read_storage(ik)
    cols = list(ik_store.columns)
    # a missing column
    drop = tmp_path / "drop_ik.mot"
    keep = [c for c in cols if c != "knee_angle_r"]
    write_storage(drop, ik_store.time, keep, ik_store.data[:, [cols.index(c) for c in keep]],
                  in_degrees=bool(ik_store.in_degrees))  # fmt: skip
    # an IK shorter than a cycle
    short = tmp_path / "short_ik.mot"
    write_storage(short, ik_store.time[:40], cols, ik_store.data[:40],
                  in_degrees=bool(ik_store.in_degrees))  # fmt: skip
    # NaN
    nan = storage_with_nan(ik, tmp_path / "nan_ik.mot", "knee_angle_r", range(10, 12))
    # no heel strike: the vertical force flattened
    g = read_storage(grf)
    flat = g.data.copy()
    for k, c in enumerate(g.columns):
        if c.endswith("_vy"):
            flat[:, k] = 0.0
    flat_grf = tmp_path / "flat_grf.mot"
    write_storage(flat_grf, g.time, list(g.columns), flat)
    t0 = time.perf_counter()
    for bad_ik, bad_grf, word in (
        (drop, grf, "knee_angle_r"),
        (short, grf, "short_ik.mot"),
        (nan, grf, "nan_ik.mot"),
        (ik, flat_grf, "flat_grf.mot"),
    ):
        one_line_error(cli(capsys, *_args(bad_ik, bad_grf, tmp_path / "o")), word)
    assert time.perf_counter() - t0 < 30  # refused before any solve
    assert not (tmp_path / "o").exists()
    from walk3d.validation.target import tracking_target

    assert tracking_target(ik=ik, grf=grf, mass=62.0).period > 0  # control: the files as shipped


@pytest.mark.solve
@needs_data
def test_tracking_the_falisse_trial_converges_and_names_what_binds(capsys, tmp_path):
    out = tmp_path / "falisse"
    t0 = time.perf_counter()
    code, stdout, err = cli(
        capsys,
        *_args(FALISSE / "gait_1_ik.mot", FALISSE / "gait_1_grf.mot", out),
        "--relax",
        "loop=0.03,foot-flat=25,heel-rise=0.3",
    )
    assert code == 0, err
    assert time.perf_counter() - t0 < 120
    rows = {r.split(",")[0]: float(r.split(",")[2])
            for r in (out / "tracking.csv").read_text().splitlines()[1:]}  # fmt: skip
    for dof in ("hip_flexion_r", "knee_flexion_r", "ankle_dorsiflexion_r"):
        assert rows[dof] <= 3.0, (dof, rows[dof])
    summary = json.loads((out / "summary.json").read_text())
    assert summary["converged"] and summary["objective"]["C_track"]["total"] > 0
    manifest = json.loads((out / "manifest.json").read_text())
    assert "tracking.csv" in manifest["files"]
    # the closed loop, kept: the tracking misses and names the loop
    strict = tmp_path / "strict"
    code, stdout, _ = cli(capsys, *_args(FALISSE / "gait_1_ik.mot", FALISSE / "gait_1_grf.mot",
                                         strict))  # fmt: skip
    assert code == 0
    binding = (strict / "binding.csv").read_text()
    assert "loop_" in binding.splitlines()[1]
    # the audit of the tracked against the predicted gait (here: the strict tracking itself)
    code, stdout, _ = cli(capsys, "audit", strict, out, "--out", tmp_path / "audit.json")
    assert code == 0 and "C_tor" in stdout
    audit = json.loads((tmp_path / "audit.json").read_text())
    assert {"terms", "limb_work", "bursts"} <= set(audit)
    assert np.isfinite(audit["C_weighted tracked"])


@pytest.mark.parametrize("only", [("",), (",",), ("knee_flexion,,hip_flexion",)],
                         ids=["empty", "comma", "empty-item"])  # fmt: skip
def test_an_empty_dof_name_in_only_is_refused(capsys, tmp_path, only):
    """`--only ""` tracked every DoF, `--only ,` none, and an empty item was skipped."""
    args = [a for o in only for a in ("--only", o)]
    one_line_error(cli(capsys, "track", "--table", "t.csv", *args, "--out", tmp_path / "o"),
                   "--only", "empty")  # fmt: skip


def test_repeated_only_options_add_up_and_no_name_is_refused():
    """Repeated `--only` kept the last; the names of all reach only_dofs. The control: names
    that the target measures pass."""
    from dataclasses import make_dataclass

    from walk3d.tracking import only_dofs

    target = make_dataclass("Target", ["dof_names", "angle_mask"])(
        ["knee_flexion_r", "knee_flexion_l", "hip_flexion_r"], np.ones(3, dtype=bool)
    )
    with pytest.raises(ValueError, match="names no DoF"):
        only_dofs(target, [])
    kept = only_dofs(target, ["knee_flexion", "hip_flexion_r"])
    assert kept.angle_mask.tolist() == [True, True, True]
    assert only_dofs(target, ["knee_flexion_l"]).angle_mask.tolist() == [False, True, False]
