"""walk3d predict's background compile (walk3d.cli.background): when it starts, when it does not,
the lock, and what the background process leaves behind."""

import os
import subprocess
import sys

import pytest

from walk3d import api
from walk3d.cli import background
from walk3d.problem.settings import PredictionSettings
from walk3d.solve import compiled

SETTINGS = api.settings(1.3, sex="female", period=1.04, double_support=0.12)
HOLD = """
import sys, time
from pathlib import Path
from walk3d.cli.background import hold
with hold(Path(sys.argv[1]), wait=False) as held:
    print(held, flush=True)
    time.sleep(float(sys.argv[2]))
"""


@pytest.fixture
def spawned(tmp_path, monkeypatch):
    """A cache folder of its own, a compiler found, and a recorder in place of the spawn."""
    monkeypatch.setenv("WALK3D_CACHE_DIR", str(tmp_path))
    monkeypatch.setenv(background.ENV_LATER, "1")
    monkeypatch.setattr(compiled, "compiler", lambda: ["cc"])
    calls = []
    monkeypatch.setattr(background, "_spawn", lambda cmd, log: calls.append((cmd, log)))
    return calls


def _holder(lock, seconds: float = 30.0) -> subprocess.Popen:
    """Another process holding ``lock`` (it prints True once it does)."""
    proc = subprocess.Popen([sys.executable, "-c", HOLD, str(lock), str(seconds)],
                            stdout=subprocess.PIPE, text=True)  # fmt: skip
    assert proc.stdout.readline().strip() == "True"
    return proc


def test_tests_start_no_background_compile():
    assert not background.later_enabled()  # tests/conftest.py turns it off


def test_a_vm_prediction_starts_one_detached_compile_of_its_settings(spawned):
    line = background.start(SETTINGS, [])
    assert line and "compiling in the background" in line
    ((cmd, log),) = spawned
    key = background.target_id(SETTINGS)
    assert cmd[1:4] == ["-m", "walk3d.cli.background", key] and log.name.endswith(".log")
    assert PredictionSettings.model_validate_json(open(cmd[4]).read()) == SETTINGS
    what_if = api.settings(1.1, sex="male", changes={"strength": [("ankle_r", 0.5)]},
                           full_cycle=True)  # fmt: skip
    background.start(what_if, [])
    assert PredictionSettings.model_validate_json(open(spawned[1][0][4]).read()) == what_if


def test_no_compile_when_compiled_off_or_without_a_compiler(spawned, monkeypatch):
    assert background.start(SETTINGS, ["full"]) is None
    assert background.start(SETTINGS, [], flag=False) is None
    monkeypatch.setenv(background.ENV_LATER, "off")
    assert background.start(SETTINGS, []) is None
    monkeypatch.setenv(background.ENV_LATER, "1")
    monkeypatch.setattr(compiled, "compiler", lambda: None)
    assert background.start(SETTINGS, []) is None
    assert spawned == []
    monkeypatch.setattr(compiled, "compiler", lambda: ["cc"])  # control: now it starts
    assert background.start(SETTINGS, []) is not None and len(spawned) == 1


def test_a_held_lock_or_a_failed_compile_starts_none_and_a_released_lock_does(spawned):
    lock = background.lock_path()
    holder = _holder(lock)
    try:
        assert background.running(lock)
        assert "is running" in background.start(SETTINGS, [])
        assert spawned == []
    finally:
        holder.kill()
        holder.wait()
    assert lock.is_file() and not background.running(lock)  # the OS released it
    assert "compiling in the background" in background.start(SETTINGS, [])
    assert len(spawned) == 1
    background.paths(background.target_id(SETTINGS))["failed"].write_text("CompileError: cc\n")
    assert "failed" in background.start(SETTINGS, []) and len(spawned) == 1
    assert background.clear_failed() == 1
    assert "compiling in the background" in background.start(SETTINGS, [])


def test_the_target_is_the_sex_and_model_not_the_subject_or_descriptors():
    same = api.settings(1.7, sex="female", mass=50.0, height=1.55)
    assert background.target_id(same) == background.target_id(SETTINGS)
    assert background.target_id(api.settings(1.3, sex="male")) != background.target_id(SETTINGS)
    other = api.settings(1.3, sex="female", criterion="tor")
    assert background.target_id(other) != background.target_id(SETTINGS)


def _run_job(tmp_path, text: str, key: str = "0123456789abcdef"):
    # CC that does not exist: should the lock ever fail, no real compile runs
    env = os.environ | {"WALK3D_CACHE_DIR": str(tmp_path), "CC": "/nonexistent/cc"}
    job = tmp_path / f"compile-{key}-test.json"
    job.write_text(text)
    r = subprocess.run([sys.executable, "-m", "walk3d.cli.background", key, str(job)], env=env,
                       capture_output=True, text=True, timeout=120)  # fmt: skip
    return r, background.paths(key) | {"json": job}


def test_the_background_process_records_a_failure_and_deletes_its_job(tmp_path, monkeypatch):
    monkeypatch.setenv("WALK3D_CACHE_DIR", str(tmp_path))
    r, p = _run_job(tmp_path, "{not settings")
    assert r.returncode == 1 and "Traceback" not in r.stdout + r.stderr
    assert "failed" in r.stdout and p["failed"].read_text().startswith("ValidationError")
    assert not p["json"].exists() and not background.running(background.lock_path())


def test_the_background_process_leaves_a_held_lock_alone(tmp_path, monkeypatch):
    monkeypatch.setenv("WALK3D_CACHE_DIR", str(tmp_path))
    holder = _holder(background.lock_path())
    try:
        r, p = _run_job(tmp_path, SETTINGS.model_dump_json(), "fedcba9876543210")
    finally:
        holder.kill()
        holder.wait()
    assert r.returncode == 0 and "another process" in r.stdout
    assert not p["json"].exists() and not p["failed"].exists()
