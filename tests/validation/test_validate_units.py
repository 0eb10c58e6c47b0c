"""walk3d validate with measured angles in another unit than stated: one line and exit 2 before
anything is written (walk3d.io.angle_units); the lab's own files validate."""

import subprocess
import sys

import numpy as np
import pytest
from validation_support import cli_env

from walk3d.io import read_storage, write_storage
from walk3d.results.prediction import save_prediction


@pytest.fixture(scope="module")
def pred_dir(synthetic_prediction, tmp_path_factory):
    return save_prediction(synthetic_prediction, tmp_path_factory.mktemp("pred") / "p")


def _run(*args):
    cmd = [sys.executable, "-m", "walk3d.cli", *map(str, args)]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=120, env=cli_env())


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
    r = _run("validate", pred_dir, "--reference", bad, "--reference",
             falisse / "gait_1_grf.mot", "--out", tmp_path / "v")  # fmt: skip
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2 and len(lines) == 1, r.stderr
    assert lines[0].startswith("walk3d: error: bad.mot:") and words in lines[0], r.stderr
    assert not (tmp_path / "v").exists()
    # negative control: the trial's own IK, in degrees as its header says
    r = _run("validate", pred_dir, "--reference", falisse / "gait_1_ik.mot", "--reference",
             falisse / "gait_1_grf.mot", "--out", tmp_path / "w")  # fmt: skip
    assert r.returncode == 0, r.stderr
