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


@pytest.mark.parametrize("reason", ["[Errno 28] No space left on device: 'a.txt'", "odd"])
def test_a_failed_copy_to_best_is_one_short_error(tmp_path, monkeypatch, reason):
    """copytree's error lists every file that failed (2406 characters on a full disk); the
    error raised names the target and the first reason, once; nothing partial is left."""
    import shutil

    from walk3d.campaign import store

    (tmp_path / "src").mkdir()
    (tmp_path / "src" / "a.txt").write_text("x")

    def copy(source, target, **kw):
        raise shutil.Error([(str(source), str(target), reason)] * 50)

    monkeypatch.setattr(shutil, "copytree", copy)
    with pytest.raises(OSError) as info:
        store.replace_folder(tmp_path / "src", tmp_path / "best")
    line = str(OutputWriteError(tmp_path / "best", info.value))
    assert len(line) < 200 and "best" in line and line.count("odd") <= 1, line
    if "28" in reason:
        assert info.value.errno == errno.ENOSPC and "no space left" in line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["src"]


LEAK = """
import multiprocessing, os
lock = multiprocessing.get_context("spawn").Semaphore()  # starts the resource tracker
os._exit(0)  # as a run that Ctrl-C ends: the semaphore is never released
"""


@pytest.mark.parametrize("quiet", [True, False], ids=["the cluster's filter", "control: none"])
def test_the_resource_tracker_frees_a_leak_without_a_warning(quiet):
    """Ctrl-C while a local cluster's workers start left their semaphores to the resource
    tracker, which printed a two-line warning under 'walk3d: interrupted'. The cluster's
    processes run with runner.TRACKER_QUIET, which silences exactly that warning."""
    import os
    import subprocess
    import sys

    from walk3d.campaign.runner import TRACKER_QUIET

    env = dict(os.environ, PYTHONWARNINGS=TRACKER_QUIET if quiet else "")
    r = subprocess.run([sys.executable, "-c", LEAK], capture_output=True, text=True, env=env,
                       timeout=60)  # fmt: skip
    assert r.returncode == 0
    assert ("leaked semaphore" in r.stderr) is not quiet, r.stderr
