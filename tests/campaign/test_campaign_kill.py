"""SIGKILL of a running ``walk3d campaign`` loses no finished start; rerunning completes it."""

import os
import signal
import subprocess
import sys
import time

import pytest

from walk3d.campaign import store

pytestmark = pytest.mark.campaign

STARTS = 4


def _command(out):
    options = f"--starts {STARTS} --seed 3 --workers 2 --nodes 6 --max-iter 3 --restarts 0".split()
    options += ["--criterion", "tor", "--period", "1.08", "--double-support", "0.16"]
    return [sys.executable, "-m", "walk3d.cli", "campaign", *options, "--out", str(out)]


def _finished(out):
    root = store.starts_dir(out)
    return [p for p in root.iterdir() if p.name.startswith("seed_")] if root.is_dir() else []


def _group_alive(pgid):
    try:
        os.killpg(pgid, 0)
    except ProcessLookupError:
        return False
    return True


def _wait_for_finished(proc, out, count, why):
    """Wait until ``count`` starts are stored, failing if the campaign ends first."""
    deadline = time.monotonic() + 150
    while len(_finished(out)) < count:
        assert proc.poll() is None, f"campaign ended before {why}"
        assert time.monotonic() < deadline, f"no {count} starts finished in time"
        time.sleep(0.05)


def test_kill_and_resume(tmp_path):
    out = tmp_path / "c"
    env = os.environ | {"OPENBLAS_NUM_THREADS": "1"}
    proc = subprocess.Popen(_command(out), start_new_session=True, env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)  # fmt: skip
    try:
        _wait_for_finished(proc, out, 2, "it could be killed")
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
    deadline = time.monotonic() + 20
    while _group_alive(proc.pid) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not _group_alive(proc.pid), "worker processes survived the kill"

    snapshot = {p: p.read_bytes() for d in _finished(out) for p in d.rglob("*") if p.is_file()}
    assert len(_finished(out)) < STARTS
    assert all(not p.name.startswith(".") for d in _finished(out) for p in d.iterdir())

    r = subprocess.run(_command(out), capture_output=True, text=True, timeout=300, env=env)
    assert r.returncode in (0, 1), r.stderr  # 1: no start converged (expected here)
    names = sorted(p.name for p in store.starts_dir(out).iterdir())
    assert names == [store.start_name(3 + k) for k in range(STARTS)]
    assert not [p for p in out.rglob(".tmp*")]
    for path, data in snapshot.items():
        assert path.read_bytes() == data, f"{path} changed on resume"
    ranking = (out / "ranking.csv").read_text().splitlines()
    assert len(ranking) == 1 + STARTS


def test_ctrl_c_stops_a_campaign_with_one_line_and_keeps_finished_starts(tmp_path):
    """SIGINT to the whole process group, as a terminal's Ctrl-C: a line, code 130, the
    finished starts stay and no temporary is left."""
    out = tmp_path / "c"
    env = os.environ | {"OPENBLAS_NUM_THREADS": "1"}
    default = lambda: signal.signal(signal.SIGINT, signal.SIG_DFL)  # noqa: E731 (not inherited SIG_IGN)
    proc = subprocess.Popen(_command(out), start_new_session=True, env=env, text=True,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            preexec_fn=default)  # fmt: skip
    try:
        _wait_for_finished(proc, out, 1, "Ctrl-C")
        os.killpg(proc.pid, signal.SIGINT)
        t0 = time.monotonic()
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 130, err
    assert time.monotonic() - t0 < 30
    assert "walk3d: interrupted" in err.splitlines()[-1] and "Traceback" not in err, err
    done = _finished(out)
    assert 1 <= len(done) < STARTS and all((d / store.RECORD_FILE).is_file() for d in done)
    assert not (out / "best").exists()  # no ranking or best/ of an interrupted run
    assert not list(out.rglob(".tmp_*"))  # the interrupted starts leave no partial folder


def _log_in_workers(level, text):
    import logging

    logging.getLogger("distributed.worker").log(level, text)


def test_local_workers_print_no_dask_error_logs(capfd):
    """A worker's ERROR (as its heartbeat logs once the scheduler has closed at Ctrl-C) is not
    printed; the control, a CRITICAL message from the same workers, is."""
    import logging

    from walk3d.campaign import runner

    with runner.dask_client(1, None, 1) as client:
        client.run(_log_in_workers, logging.ERROR, "probe-error-hidden")
        client.run(_log_in_workers, logging.CRITICAL, "probe-critical-shown")
        time.sleep(0.5)  # let the worker's stderr reach the file
    err = capfd.readouterr().err
    assert "probe-critical-shown" in err, err
    assert "probe-error-hidden" not in err, err
