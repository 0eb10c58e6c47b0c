"""walk3d predict's background compile (walk3d.cli.background): when it starts, when it does not,
and what the background process leaves behind."""

import os
import subprocess
import sys

import pytest

from walk3d import api
from walk3d.cli import background
from walk3d.problem.settings import PredictionSettings
from walk3d.solve import compiled

SETTINGS = api.settings(1.3, sex="female", period=1.04, double_support=0.12)


@pytest.fixture
def spawned(tmp_path, monkeypatch):
    """A cache folder of its own, a compiler found, and a recorder in place of Popen."""
    monkeypatch.setenv("WALK3D_CACHE_DIR", str(tmp_path))
    monkeypatch.setenv(background.ENV_LATER, "1")
    monkeypatch.setattr(compiled, "compiler", lambda: ["cc"])
    calls = []
    monkeypatch.setattr(background, "_spawn", lambda cmd, log: calls.append((cmd, log)))
    return calls


def test_a_vm_prediction_starts_one_detached_compile_of_its_settings(spawned):
    line = background.start(SETTINGS, [])
    assert line and "compiling in the background" in line
    ((cmd, log),) = spawned
    assert cmd[1:3] == ["-m", "walk3d.cli.background"] and log.name.endswith(".log")
    job = background.paths(background.target_id(SETTINGS))["json"]
    assert cmd[3] == str(job)
    assert PredictionSettings.model_validate_json(job.read_text()) == SETTINGS


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


def test_a_running_or_failed_compile_is_not_started_again_and_a_stale_lock_is(spawned):
    p = background.paths(background.target_id(SETTINGS))
    p["lock"].write_text(str(os.getpid()))  # alive
    assert "is running" in background.start(SETTINGS, [])
    assert spawned == []
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True).stdout.strip()  # fmt: skip
    p["lock"].write_text(dead)  # stale: its process has ended
    assert background.running(p["lock"]) is None
    assert "compiling in the background" in background.start(SETTINGS, [])
    assert len(spawned) == 1
    p["failed"].write_text("CompileError: cc failed\n")
    assert "failed" in background.start(SETTINGS, []) and len(spawned) == 1


def test_the_target_is_the_sex_and_model_not_the_subject_or_descriptors():
    same = api.settings(1.7, sex="female", mass=50.0, height=1.55)
    assert background.target_id(same) == background.target_id(SETTINGS)
    assert background.target_id(api.settings(1.3, sex="male")) != background.target_id(SETTINGS)
    other = api.settings(1.3, sex="female", criterion="tor")
    assert background.target_id(other) != background.target_id(SETTINGS)


def _run_job(tmp_path, text: str, key: str = "0123456789abcdef"):
    env = os.environ | {"WALK3D_CACHE_DIR": str(tmp_path)}
    job = tmp_path / f"compile-{key}.json"
    job.write_text(text)
    r = subprocess.run([sys.executable, "-m", "walk3d.cli.background", str(job)], env=env,
                       capture_output=True, text=True, timeout=120)  # fmt: skip
    return r, background.paths(key) | {"json": job}


def test_the_background_process_records_a_failure_and_cleans_up(tmp_path, monkeypatch):
    monkeypatch.setenv("WALK3D_CACHE_DIR", str(tmp_path))
    r, p = _run_job(tmp_path, "{not settings")
    assert r.returncode == 1 and "Traceback" not in r.stdout + r.stderr
    assert "failed" in r.stdout and p["failed"].read_text().startswith("ValidationError")
    assert not p["lock"].exists() and not p["json"].exists()


def test_the_background_process_leaves_a_live_lock_alone(tmp_path, monkeypatch):
    monkeypatch.setenv("WALK3D_CACHE_DIR", str(tmp_path))
    key = "fedcba9876543210"
    background.paths(key)["lock"].write_text(str(os.getpid()))
    r, p = _run_job(tmp_path, SETTINGS.model_dump_json(), key)
    assert r.returncode == 0 and "another process" in r.stdout
    assert p["lock"].read_text() == str(os.getpid()) and not p["failed"].exists()
