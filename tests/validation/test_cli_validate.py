"""walk3d validate / calibrate: bad input is one line and exit 2; a full run writes its files."""

import pytest
from helpers import replace_result_file, storage_with_nan
from validation_support import exits_with_one_line, run_walk3d


def test_an_incomplete_result_folder_is_refused(pred_dir, tmp_path, falisse):
    import shutil

    bad = tmp_path / "p"
    shutil.copytree(pred_dir, bad)
    (bad / "motion.mot").unlink()  # what a crash between two files left before atomic folders
    r = run_walk3d("validate", bad, "--reference", falisse / "cycle_right_leg_mean_sd.csv")
    exits_with_one_line(r, "incomplete result folder: motion.mot is missing")


def test_nan_in_a_reference_ik_file_is_refused_naming_file_and_column(pred_dir, tmp_path, falisse):
    bad = storage_with_nan(falisse / "gait_1_ik.mot", tmp_path / "bad_ik.mot", "knee_angle_r",
                           range(40, 60))  # fmt: skip
    r = run_walk3d("validate", pred_dir, "--reference", bad, "--reference",
             falisse / "gait_1_grf.mot", "--out", tmp_path / "v")  # fmt: skip
    exits_with_one_line(r, "bad_ik.mot", "knee_angle_r", "data row 41")
    assert "quaternions" not in r.stderr


def test_malformed_cycle_table(pred_dir, tmp_path):
    lines = ["percent_cycle,knee_angle_deg_mean,knee_angle_deg_sd"]
    lines += [f"{p},{-30 + p / 4},{2.0}" for p in range(101)]
    lines[7] = lines[7].replace(",", ",x", 1)
    bad = tmp_path / "bad.csv"
    bad.write_text("\n".join(lines) + "\n")
    exits_with_one_line(
        run_walk3d("validate", pred_dir, "--reference", bad), "bad.csv:8", "not a number"
    )
    assert not (pred_dir / "validation").exists()


def test_truncated_trial_storage(pred_dir, tmp_path, falisse):
    lines = (falisse / "gait_1_ik.mot").read_text().splitlines()
    bad = tmp_path / "ik.mot"
    bad.write_text("\n".join(lines[:-5]) + "\n")
    exits_with_one_line(run_walk3d("validate", pred_dir, "--reference", bad), "ik.mot", "rows")


@pytest.mark.parametrize("value", ["0", "1.5"])
def test_a_trial_storage_whose_time_is_constant_is_refused(pred_dir, tmp_path, falisse, value):
    """It divided by zero (the sampling rate); the control is
    test_validate_writes_tables_and_figures, the same files with their times."""
    lines = (falisse / "gait_1_ik.mot").read_text().splitlines()
    head = next(i for i, line in enumerate(lines) if line.strip().lower() == "endheader") + 2
    lines[head:] = [value + "\t" + line.split(maxsplit=1)[1] for line in lines[head:]]
    bad = tmp_path / "ik.mot"
    bad.write_text("\n".join(lines) + "\n")
    r = run_walk3d("validate", pred_dir, "--reference", bad, "--reference",
                   falisse / "gait_1_grf.mot", "--out", tmp_path / "v")  # fmt: skip
    exits_with_one_line(r, "ik.mot", "time is not increasing")
    assert not (tmp_path / "v").exists()


def test_unknown_reference_and_missing_inputs(pred_dir, tmp_path):
    odd = tmp_path / "odd.sto"
    odd.write_text("x\nversion=1\nendheader\ntime\tfoo\n0\t1\n0.01\t2\n")
    exits_with_one_line(run_walk3d("validate", pred_dir, "--reference", odd), "neither")
    exits_with_one_line(
        run_walk3d("validate", pred_dir, "--reference", tmp_path / "none.csv"), "not found"
    )
    r = run_walk3d("validate", tmp_path / "nopred", "--reference", odd)
    exits_with_one_line(r, "prediction")
    r = run_walk3d("validate", pred_dir)
    assert r.returncode == 2 and "reference" in r.stderr and len(r.stderr.splitlines()) == 1


@pytest.mark.parametrize(
    ("speed", "words"),
    [
        ("nan", "--speed must be a finite positive number, got nan"),
        ("-1", "--speed must be a finite positive number, got -1.0"),
        ("9", "speed must be in (0, 4] m/s"),
    ],  # fmt: skip
)
def test_a_bad_belt_speed_is_one_plain_line(pred_dir, tmp_path, falisse, speed, words):
    """The settings' check, not pydantic's multi-line error with its web link."""
    r = run_walk3d("validate", pred_dir, "--reference", falisse / "gait_1_ik.mot", "--reference",
             falisse / "gait_1_grf.mot", "--speed", speed, "--out", tmp_path / "v")  # fmt: skip
    exits_with_one_line(r, words)
    assert "pydantic" not in r.stderr and "validation error" not in r.stderr
    assert not (tmp_path / "v").exists()


@pytest.mark.parametrize("speed", ["nan", "inf", "-1", "0"])
def test_a_bad_speed_is_refused_with_a_cycle_table_too(pred_dir, tmp_path, falisse, speed):
    """--speed nan was ignored (exit 0) when the reference is a cycle table."""
    args = ["validate", pred_dir, "--reference", falisse / "cycle_right_leg_mean_sd.csv"]
    r = run_walk3d(*args, "--speed", speed, "--out", tmp_path / "v")
    exits_with_one_line(r, "--speed must be a finite positive number")
    assert not (tmp_path / "v").exists()


@pytest.mark.parametrize("keyword", ["threshold", "speed"])
@pytest.mark.parametrize("value", [float("nan"), float("inf"), 0.0, -1.0])
def test_the_library_checks_threshold_and_speed_too(
    synthetic_prediction, tmp_path, falisse, keyword, value
):
    """validate(threshold=nan) with a cycle table raised nothing; the CLI refused it."""
    from walk3d.validation.run import validate

    table = [falisse / "cycle_right_leg_mean_sd.csv"]
    with pytest.raises(ValueError, match=f"^{keyword} must be a finite positive number"):
        validate({"p": synthetic_prediction}, table, tmp_path / "v", **{keyword: value})
    assert not (tmp_path / "v").exists()


def test_the_library_validates_with_a_good_threshold_and_speed(synthetic_prediction, falisse):
    """Control of the check above: finite positive values validate."""
    from walk3d.validation.run import validate

    table = [falisse / "cycle_right_leg_mean_sd.csv"]
    out = validate({"p": synthetic_prediction}, table, figures=False, speed=1.2, threshold=20.0)
    assert out.table2


@pytest.mark.parametrize("value", ["nan", "0"])
def test_a_bad_threshold_is_one_line_naming_it(pred_dir, tmp_path, falisse, value):
    """--threshold nan passed the check (nan <= 0 is false). Control: a good one validates."""
    args = ["validate", pred_dir, "--reference", falisse / "cycle_right_leg_mean_sd.csv"]
    r = run_walk3d(*args, "--threshold", value, "--out", tmp_path / "v")
    exits_with_one_line(r, f"--threshold must be a finite positive number, got {float(value)}")
    assert not (tmp_path / "v").exists()
    if value == "0":  # control, once: a good threshold validates
        assert run_walk3d(*args, "--threshold", "20", "--out", tmp_path / "v").returncode == 0


@pytest.mark.parametrize(
    ("forward", "words"),
    [("up", "forward axis must be one of +x, -x, +y, -y, +z, -z, got 'up'"),
     ("-y", "forward '-y' is the walking direction in C3D references, and none is given")],
)  # fmt: skip
def test_forward_without_a_c3d_reference_is_refused(pred_dir, tmp_path, falisse, forward, words):
    """--forward up with a cycle table was neither checked nor used (exit 0); a C3D reference
    had it refused. Negative control: the same run without --forward validates."""
    args = ["validate", pred_dir, "--reference", falisse / "cycle_right_leg_mean_sd.csv"]
    exits_with_one_line(run_walk3d(*args, "--forward", forward, "--out", tmp_path / "v"), words)
    assert not (tmp_path / "v").exists()
    if forward == "up":  # the control, once
        assert run_walk3d(*args, "--out", tmp_path / "v").returncode == 0


def test_the_library_checks_forward_before_any_work(tmp_path):
    """validate()'s own check, as the command's: an axis and a C3D reference, or no forward.
    Negative control: those pass."""
    from walk3d.validation.run import check_forward

    for ok in ((None, ["t.csv"]), ("-y", ["t.csv", "walk.C3D"]), ("+x", [tmp_path / "w.c3d"])):
        check_forward(*ok)
    with pytest.raises(ValueError, match="got 'up'"):
        check_forward("up", ["walk.c3d"])
    with pytest.raises(ValueError, match="none is given"):
        check_forward("+x", ["t.csv", "ik.mot"])


def test_calibrate_bad_input(tmp_path, falisse):
    exits_with_one_line(
        run_walk3d("calibrate", "--ik", tmp_path / "no.mot", "--grf", falisse / "gait_1_grf.mot",
             "--out", tmp_path / "c.json"), "no.mot")  # fmt: skip
    exits_with_one_line(
        run_walk3d("calibrate", "--ik", falisse / "gait_1_ik.mot", "--grf",
                   falisse / "gait_1_ik.mot", "--out", tmp_path / "c.json"),
        "ground reaction")  # fmt: skip
    assert not (tmp_path / "c.json").exists()


def test_predict_from_trial_bad_input(tmp_path, falisse):
    exits_with_one_line(run_walk3d("predict", "--out", tmp_path / "o", "--from-trial",
                         falisse / "gait_1_ik.mot"), "--grf")  # fmt: skip
    # the trial's descriptors reach the settings check (an invalid --nodes stops before solving)
    r = run_walk3d("predict", "--out", tmp_path / "o", "--from-trial", falisse / "gait_1_ik.mot",
             "--grf", falisse / "gait_1_grf.mot", "--nodes", "1")  # fmt: skip
    exits_with_one_line(r, "nodes")
    assert "V = 1.2705 m/s" in r.stdout and "T = 1.07" in r.stdout
    assert not (tmp_path / "o").exists()
    # the trial's V with T and Td predicted (auto given): printed as such, no traceback
    r = run_walk3d("predict", "--out", tmp_path / "o", "--from-trial", falisse / "gait_1_ik.mot",
             "--grf", falisse / "gait_1_grf.mot", "--period", "auto", "--double-support", "auto",
             "--nodes", "1")  # fmt: skip
    exits_with_one_line(r, "nodes")
    assert "V = 1.2705 m/s" in r.stdout and "T = auto (predicted)" in r.stdout


def test_validate_writes_tables_and_figures(pred_dir, tmp_path, falisse):
    out = tmp_path / "val"
    r = run_walk3d("validate", pred_dir, "--reference", falisse / "cycle_right_leg_mean_sd.csv",
             "--out", out)  # fmt: skip
    assert r.returncode == 0, r.stderr
    assert "Table 2" in r.stdout and "missing" in r.stdout and "Table 3" in r.stdout
    names = {p.name for p in out.iterdir()}
    assert {"table2.csv", "table3.csv", "measured_fit.csv", "grf.png", "moments.png",
            "angles.png"} <= names  # fmt: skip
    header = (out / "table2.csv").read_text().splitlines()[0]
    assert header == (
        "group,quantity,label,unit,status,n_cycles,reference_sd,reference_range,"
        "rmse,rmse_of_range,r,r2"
    )


def test_a_non_finite_recorded_period_is_one_line(pred_dir, tmp_path, falisse):
    """``settings.gait.period: Infinity`` printed two RuntimeWarnings and "array of sample
    points is empty"; the same folder with its own period validates (negative control)."""
    import json
    import shutil

    bad = shutil.copytree(pred_dir, tmp_path / "p")
    summary = json.loads((bad / "summary.json").read_text())
    summary["settings"]["gait"]["period"] = float("inf")
    replace_result_file(bad, "summary.json", json.dumps(summary).encode())
    table = falisse / "cycle_right_leg_mean_sd.csv"
    r = run_walk3d("validate", bad, "--reference", table, "--out", tmp_path / "v")
    exits_with_one_line(r, "settings.gait.period inf", "not the cycle's period")
    assert not (tmp_path / "v").exists()
    r = run_walk3d("validate", pred_dir, "--reference", table, "--out", tmp_path / "v")
    assert r.returncode == 0 and "Warning" not in r.stderr, r.stderr


def _labelled(pred_dir, tmp_path, **values):
    import json
    import shutil

    folder = shutil.copytree(pred_dir, tmp_path / "p")
    summary = json.loads((folder / "summary.json").read_text()) | values
    replace_result_file(folder, "summary.json", json.dumps(summary).encode())
    return folder


def test_a_result_that_did_not_converge_is_named_with_the_scores_reason(pred_dir, tmp_path,
                                                                       falisse):  # fmt: skip
    """Was "ok" on every row and "score 10.000" without the reason, no warning; exit stays 0."""
    table = falisse / "cycle_right_leg_mean_sd.csv"
    bad = _labelled(pred_dir, tmp_path, converged=False, status="Maximum_Iterations_Exceeded",
                    gait_checks={"looks_like_walking": True})  # fmt: skip
    r = run_walk3d("validate", bad, "--reference", table, "--out", tmp_path / "v")
    assert r.returncode == 0, r.stderr
    assert r.stderr.strip().splitlines() == [
        f"walk3d: warning: {bad}: the solve did not converge (Maximum_Iterations_Exceeded): "
        "not a valid prediction"]  # fmt: skip
    assert "(NOT CONVERGED)" in r.stdout
    assert "score 10.000 (failed: did not converge (Maximum_Iterations_Exceeded)" in r.stdout
    statuses = _table2_statuses(tmp_path / "v")
    assert "ok (not converged)" in statuses and "ok" not in statuses  # every scored row says it
    # negative control: the same folder converged and walking is neither warned nor failed
    good = _labelled(pred_dir, tmp_path / "g", converged=True,
                     gait_checks={"looks_like_walking": True})  # fmt: skip
    r = run_walk3d("validate", good, "--reference", table, "--out", tmp_path / "w")
    assert r.returncode == 0 and "warning" not in r.stderr, r.stderr
    assert "failed" not in r.stdout and "NOT CONVERGED" not in r.stdout
    assert "ok" in _table2_statuses(tmp_path / "w")
    walking = _labelled(pred_dir, tmp_path / "n", converged=True,
                        gait_checks={"looks_like_walking": False})  # fmt: skip
    r = run_walk3d("validate", walking, "--reference", table, "--out", tmp_path / "x")
    assert r.returncode == 0 and "ok (not walking)" in _table2_statuses(tmp_path / "x")


def _table2_statuses(folder) -> set[str]:
    import csv

    path = next(folder.glob("table2*.csv"))
    with path.open(newline="") as fh:
        return {row["status"] for row in csv.DictReader(line for line in fh if line[0] != "#")}
