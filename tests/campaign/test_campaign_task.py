"""One campaign start on a worker (walk3d.campaign.task.run_start): a start whose result folder
does not fit on the disk stays pending, for a rerun; a start that fails otherwise is recorded
as an error."""

from __future__ import annotations

import errno

import pytest

from walk3d.campaign import task
from walk3d.io.errors import OutputWriteError
from walk3d.problem.settings import PredictionSettings


@pytest.mark.parametrize("full", [True, False], ids=["disk full", "control: a failed solve"])
def test_a_start_that_does_not_fit_stays_pending(tmp_path, monkeypatch, full):
    import walk3d.pipeline

    def predict(settings, seed, solver, out_dir):
        if full:
            raise OutputWriteError(out_dir, OSError(errno.ENOSPC, "No space left on device"))
        raise RuntimeError("the solve failed")

    monkeypatch.setattr(walk3d.pipeline, "predict", predict)
    settings = PredictionSettings().model_dump()
    record = task.run_start(settings, 3, "ipopt", str(tmp_path))
    left = sorted(p.name for p in tmp_path.iterdir())
    if full:
        assert record is None and left == []
    else:
        assert record["status"].startswith("error:") and left == ["seed_000003"]
