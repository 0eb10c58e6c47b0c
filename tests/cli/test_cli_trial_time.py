"""A measured trial whose time column is constant or zero (a storage exported without its
times) divided by zero in calibrate and predict --from-trial; now one line naming the file and
exit code 2, before any fit or solve. walk3d validate: tests/validation/test_cli_validate.py."""

import numpy as np
import pytest
from helpers import cli, one_line_error, shared_data_dir

from walk3d.io.storage import read_storage, write_storage

FALISSE = shared_data_dir() / "falisse2019"
pytestmark = pytest.mark.skipif(not FALISSE.is_dir(), reason=f"no shared data at {FALISSE}")
IK, GRF = FALISSE / "gait_1_ik.mot", FALISSE / "gait_1_grf.mot"


class Solved(Exception):
    """walk3d.pipeline.predict was reached: the command accepted its input."""


@pytest.fixture
def no_solve(monkeypatch):
    import walk3d.pipeline as pipeline

    def predict(*args, **kwargs):
        raise Solved

    monkeypatch.setattr(pipeline, "predict", predict)


def _timeless(src, dst, value):
    """A copy of the storage ``src`` with every time ``value`` (s)."""
    s = read_storage(src)
    write_storage(dst, np.full(len(s), value), s.columns, s.data, in_degrees=bool(s.in_degrees))
    return dst


@pytest.mark.parametrize("kind", ["ik", "grf"])
@pytest.mark.parametrize("value", [0.0, 1.5])
def test_predict_from_a_trial_without_times_is_refused(capsys, tmp_path, no_solve, kind, value):
    bad = _timeless(IK if kind == "ik" else GRF, tmp_path / f"bad_{kind}.mot", value)
    ik, grf = (bad, GRF) if kind == "ik" else (IK, bad)
    r = cli(capsys, "predict", "--from-trial", ik, "--grf", grf, "--out", tmp_path / "o")
    one_line_error(r, f"bad_{kind}.mot", "time is not increasing")
    assert not (tmp_path / "o").exists()


def test_predict_from_a_trial_with_its_times_reaches_the_solve(capsys, tmp_path, no_solve):
    """Negative control: the same trial as measured."""
    with pytest.raises(Solved):
        cli(capsys, "predict", "--from-trial", IK, "--grf", GRF, "--out", tmp_path / "o")


@pytest.mark.parametrize("kind", ["ik", "grf"])
def test_calibrate_a_trial_without_times_is_refused(capsys, tmp_path, kind):
    bad = _timeless(IK if kind == "ik" else GRF, tmp_path / f"bad_{kind}.mot", 0.0)
    ik, grf = (bad, GRF) if kind == "ik" else (IK, bad)
    r = cli(capsys, "calibrate", "--ik", ik, "--grf", grf, "--out", tmp_path / "c.json")
    one_line_error(r, f"bad_{kind}.mot", "time is not increasing")
    assert not list(tmp_path.glob("c*"))
