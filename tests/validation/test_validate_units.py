"""walk3d validate with measured angles in another unit than stated: one line and exit 2 before
anything is written (walk3d.io.angle_units); the lab's own files validate."""

import numpy as np
import pytest
from validation_support import run_walk3d

from walk3d.io import read_storage, write_storage


@pytest.mark.parametrize(("in_degrees", "scale", "words"), [
    (False, 1.0, "read as inDegrees=no, beyond ±360°"),
    (True, np.radians(1.0), "spans less than 3° read as inDegrees=yes"),
])  # fmt: skip
def test_a_mislabelled_ik_is_refused(pred_dir, tmp_path, falisse, in_degrees, scale, words):
    ik = read_storage(falisse / "gait_1_ik.mot")
    data = np.array(ik.data)
    angles = [k for k, c in enumerate(ik.columns) if not c.endswith(("_tx", "_ty", "_tz"))]
    data[:, angles] *= scale
    bad = write_storage(tmp_path / "bad.mot", ik.time, ik.columns, data, in_degrees=in_degrees)
    r = run_walk3d("validate", pred_dir, "--reference", bad, "--reference",
             falisse / "gait_1_grf.mot", "--out", tmp_path / "v")  # fmt: skip
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2 and len(lines) == 1, r.stderr
    assert lines[0].startswith("walk3d: error: bad.mot:") and words in lines[0], r.stderr
    assert not (tmp_path / "v").exists()
    # negative control: the trial's own IK, in degrees as its header says
    r = run_walk3d("validate", pred_dir, "--reference", falisse / "gait_1_ik.mot", "--reference",
             falisse / "gait_1_grf.mot", "--out", tmp_path / "w")  # fmt: skip
    assert r.returncode == 0, r.stderr
