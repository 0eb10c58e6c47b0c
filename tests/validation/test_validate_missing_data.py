"""walk3d validate with a reference that lacks data: nothing scored is one line and exit 2, a
partial reference a warning naming what it lacks and a score marked partial, and an IK and a
GRF file whose times do not overlap are refused."""

import json

from validation_support import exits_with_one_line, run_walk3d

from walk3d.io.storage import read_storage
from walk3d.trials.trial import check_overlap


def _table_without(falisse, tmp_path, prefix):
    """The Falisse cycle table less its columns starting with ``prefix`` (all but percent for
    ``""``)."""
    lines = (falisse / "cycle_right_leg_mean_sd.csv").read_text().splitlines()
    names = lines[0].split(",")
    keep = [i for i, n in enumerate(names) if i == 0 or (prefix and not n.startswith(prefix))]
    path = tmp_path / f"without_{prefix or 'all'}.csv"
    path.write_text("\n".join(",".join(line.split(",")[i] for i in keep) for line in lines))
    return path


def test_a_reference_with_only_percent_is_refused_before_writing(pred_dir, tmp_path, falisse):
    r = run_walk3d("validate", pred_dir, "--reference", _table_without(falisse, tmp_path, ""),
             "--out", tmp_path / "v")  # fmt: skip
    exits_with_one_line(r, "without_all.csv holds none of the scored quantities")
    assert not (tmp_path / "v").exists()


def test_a_reference_without_the_knee_gives_a_partial_score(pred_dir, tmp_path, falisse):
    r = run_walk3d("validate", pred_dir, "--reference", _table_without(falisse, tmp_path, "knee_"),
             "--out", tmp_path / "v")  # fmt: skip
    assert r.returncode == 0, r.stderr
    warnings = [line for line in r.stderr.splitlines() if line.startswith("walk3d: warning:")]
    assert len(warnings) == 1 and "knee_flexion angle, knee_flexion moment" in warnings[0]
    assert "PARTIAL, without 2 of 8" in " ".join(r.stdout.split())
    saved = json.loads((tmp_path / "v" / "score.json").read_text())
    assert saved["partial"] is True
    assert saved["missing"] == ["angle:knee_flexion", "moment:knee_flexion"]
    # negative control: the whole table is a full score, without a warning
    r = run_walk3d("validate", pred_dir, "--reference", falisse / "cycle_right_leg_mean_sd.csv",
             "--out", tmp_path / "w")  # fmt: skip
    assert r.returncode == 0 and "warning" not in r.stderr and "PARTIAL" not in r.stdout
    assert json.loads((tmp_path / "w" / "score.json").read_text())["partial"] is False


def test_an_ik_and_a_grf_that_do_not_overlap_are_refused(pred_dir, tmp_path, falisse):
    lines = (falisse / "gait_1_grf.mot").read_text().splitlines()
    head = next(i for i, line in enumerate(lines) if line.strip().lower() == "endheader") + 2
    for i in range(head, len(lines)):
        t, _, rest = lines[i].partition("\t")
        lines[i] = f"{float(t) + 100:.4f}\t{rest}"
    shifted = tmp_path / "grf_shift.mot"
    shifted.write_text("\n".join(lines) + "\n")
    r = run_walk3d("validate", pred_dir, "--reference", falisse / "gait_1_ik.mot", "--reference",
             shifted, "--out", tmp_path / "v")  # fmt: skip
    exits_with_one_line(r, "gait_1_ik.mot", "grf_shift.mot", "do not overlap in time")
    assert not (tmp_path / "v").exists()
    # negative control: the trial's own files overlap
    check_overlap(read_storage(falisse / "gait_1_ik.mot"), read_storage(falisse / "gait_1_grf.mot"),
                  "IK")  # fmt: skip
