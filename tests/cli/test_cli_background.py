"""walk3d predict's background compile (walk3d.cli.background): when it starts, when it does not,
the lock, and what the background process leaves behind."""

import os
import signal
import subprocess
import sys
import time

import pytest
from compiler_support import alive_after_kill_9, end, fake_compile, wait_gone

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
    assert len(p["failed"].read_text().splitlines()) == 1  # pydantic's message had 3 lines
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


FAKE_COMPILE = """
import contextlib
import sys
from pathlib import Path

import casadi as ca

import walk3d.solve.solver as solver
from walk3d.cli import background
from walk3d.solve import compiled, compiler_group


def compile_solver(settings, on_done=None, jobs=None):
    x = ca.SX.sym("x")
    fns = {name: ca.Function(name, [x], [k * x]) for k, name in enumerate(("f", "g"), 1)}
    compiled.compile_functions("fake", fns, jobs=2)  # two compilers at once, as JOBS
    return {"compiled": 2, "wall_time_s": 0.0}


solver.compile_solver = compile_solver
if sys.argv[1] == "background":
    sys.exit(background.run(sys.argv[2], Path(sys.argv[3])))
compiler_group.guarded_group = contextlib.nullcontext  # the compilers' own guard off
compile_solver(None)  # the compile alone, no background process around it
"""


@pytest.mark.skipif(not background.POSIX, reason="process groups are POSIX")
@pytest.mark.parametrize("how", ["kill-9", "kill-9-group", "sigterm"])
def test_the_compilers_die_with_the_background_process(tmp_path, monkeypatch, how):
    """kill -9 of the compiling process left its two compilers running, orphaned (3.6 GB and
    1.6 GB); the fake compilers here sleep, each with a child as gcc has cc1. The failure
    marker says it was killed, and the job file is gone. When the whole group is killed, the
    guard with it, the job file stays: the control that the check can fail."""
    monkeypatch.setenv("WALK3D_CACHE_DIR", str(tmp_path))
    job = tmp_path / "compile-0123456789abcdef-test.json"
    job.write_text(SETTINGS.model_dump_json())
    proc, pids = fake_compile(tmp_path, FAKE_COMPILE, "background", "0123456789abcdef", str(job))
    try:
        if how == "kill-9-group":
            os.killpg(proc.pid, signal.SIGKILL)
        else:
            os.kill(proc.pid, signal.SIGTERM if how == "sigterm" else signal.SIGKILL)
        proc.wait(timeout=30)
        assert wait_gone(pids) == [], (tmp_path / "log").read_text()
    finally:
        end(proc, pids)
    if how != "kill-9-group":  # the guard, in the group, is killed with it
        marker = background.paths("0123456789abcdef")["failed"]
        deadline = time.monotonic() + 10.0  # the guard writes it as the compilers' guard ends them
        while not marker.exists() and time.monotonic() < deadline:
            time.sleep(0.05)
        lines = marker.read_text().splitlines()
        assert len(lines) == 1 and lines[0].startswith("Killed:"), lines  # no background retry
    assert job.exists() == (how == "kill-9-group")
    assert "Traceback" not in (tmp_path / "log").read_text()


@pytest.mark.skipif(not background.POSIX, reason="process groups are POSIX")
def test_compilers_of_a_compile_outside_the_background_process_outlive_a_kill(tmp_path):
    """Negative control: the same compile killed without the background process around it, and
    without the compilers' own guard (walk3d.solve.compiler_group), leaves its compilers
    running, as the background process did, so the check above can fail."""
    assert alive_after_kill_9(tmp_path, FAKE_COMPILE) == 4


def test_a_compile_lock_that_is_a_folder_is_a_one_line_failure_marker(tmp_path, spawned):
    """The process died with a traceback in its log and left no marker, so every later
    prediction started it again."""
    background.lock_path().mkdir()
    r, p = _run_job(tmp_path, SETTINGS.model_dump_json(), background.target_id(SETTINGS))
    assert r.returncode == 1 and "Traceback" not in r.stdout + r.stderr, r.stdout + r.stderr
    lines = p["failed"].read_text().splitlines()
    assert len(lines) == 1 and lines[0].startswith("IsADirectoryError"), lines
    assert not p["json"].exists()
    assert "failed" in background.start(SETTINGS, []) and spawned == []  # no retry


def _build_folder(cache, name: str) -> object:
    folder = cache / name
    folder.mkdir()
    (folder / "walk3d_full_hess_1.c").write_bytes(b"x" * 100_000)
    return folder


def test_the_next_compile_start_removes_the_build_folders_of_ended_compiles(tmp_path, monkeypatch):
    """A killed compile left 68 MB of .build-* folders that nothing removed. A folder of a
    running build (its pid alive, here this test's) stays."""
    monkeypatch.setenv("WALK3D_CACHE_DIR", str(tmp_path))
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True)  # fmt: skip
    left = [_build_folder(tmp_path, f".build-{dead.stdout.strip()}-abc"),
            _build_folder(tmp_path, ".build-999999999-xyz")]  # fmt: skip
    running = _build_folder(tmp_path, f".build-{os.getpid()}-def")
    r, _ = _run_job(tmp_path, "{not settings")
    assert "removed 2 build folders of an ended compile, 0.2 MB" in r.stdout, r.stdout
    assert not any(f.exists() for f in left) and running.is_dir()


def test_build_folders_stay_while_another_process_holds_the_lock(tmp_path, monkeypatch):
    """Negative control: a compile on another machine sharing the folder holds the lock."""
    monkeypatch.setenv("WALK3D_CACHE_DIR", str(tmp_path))
    folder = _build_folder(tmp_path, ".build-999999999-xyz")
    holder = _holder(background.lock_path())
    try:
        r, _ = _run_job(tmp_path, "{not settings", "fedcba9876543210")
    finally:
        holder.kill()
        holder.wait()
    assert r.returncode == 0 and "another process" in r.stdout and folder.is_dir()


def test_a_stopped_run_withdraws_the_compile_it_started(tmp_path):
    """Ctrl-C or SIGTERM after the background compile started: :func:`background.withdraw`
    ends it (its whole session) and removes its job file; the control, not withdrawn, runs on."""
    import subprocess
    import time

    from walk3d.cli import background

    background.LAUNCHED.clear()
    procs = []
    for name in ("withdrawn", "control"):
        job = tmp_path / f"{name}.json"
        job.write_text("{}")
        procs.append((subprocess.Popen(["sleep", "30"], start_new_session=True), job))
    background.LAUNCHED.append(procs[0])
    background.withdraw()
    assert procs[0][0].wait(timeout=10) == -15 and not procs[0][1].exists()
    time.sleep(0.2)
    assert procs[1][0].poll() is None and procs[1][1].exists()
    procs[1][0].kill()
    procs[1][0].wait()
    assert not background.LAUNCHED
