"""walk3d compile in the foreground, ended while its compilers run: killed with ``kill -9`` it
left them running, orphaned, with GBs of memory; now a guard process ends them
(walk3d.solve.compiler_group). Ctrl-C and SIGTERM still end the command at once with one line.
The compilers are stand-ins that never end (tests/compiler_support.py)."""

import os
import signal
import subprocess
import time

import pytest
from compiler_support import alive, alive_after_kill_9, end, fake_compile, wait_gone

from walk3d.solve import compiler_group

pytestmark = pytest.mark.skipif(not compiler_group.POSIX, reason="process groups are POSIX")

FOREGROUND = """
import contextlib
import signal
import subprocess
import sys

import casadi as ca

import walk3d.cli.compile as command
from walk3d.cli import main
from walk3d.solve import compiled, compiler_group


def compile_solver(settings, on_done=None, jobs=None):
    x = ca.SX.sym("x")
    fns = {name: ca.Function(name, [x], [k * x]) for k, name in enumerate(("f", "g"), 1)}
    compiled.compile_functions("fake", fns, 2, on_done)
    return {"compiled": 2, "wall_time_s": 0.0}


signal.signal(signal.SIGINT, signal.SIG_DFL)  # not an inherited SIG_IGN: main() sets its own
command.compiled_status = lambda settings: {"missing": 2}
command.compile_solver = compile_solver
if sys.argv[1] == "unguarded":
    compiler_group.guarded_group = contextlib.nullcontext
main(["compile"])
"""
EXIT_WITHIN_S = 5.0
"""s: a signal ends the command at once (the guard's SIGTERM ends the compilers); room for a
loaded machine."""


def test_kill_9_of_walk3d_compile_ends_its_compilers(tmp_path):
    proc, pids = fake_compile(tmp_path, FOREGROUND, "guarded")
    try:
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
        assert wait_gone(pids) == [], (tmp_path / "log").read_text()
    finally:
        end(proc, pids)


def test_compilers_of_an_unguarded_compile_outlive_a_kill_9(tmp_path):
    """Negative control: without the guard the compilers run on, so the check above can fail."""
    assert alive_after_kill_9(tmp_path, FOREGROUND) == 4


ENDS = [(signal.SIGINT, 130, "walk3d: interrupted"), (signal.SIGTERM, 143, "walk3d: terminated")]


@pytest.mark.parametrize("sig, code, line", ENDS)
def test_a_signal_ends_walk3d_compile_and_its_compilers_at_once(tmp_path, sig, code, line):
    """The signal reaches walk3d only (the shell's Ctrl-C reaches its job's group, where the
    compilers no longer are): the guard ends them as the command stops."""
    proc, pids = fake_compile(tmp_path, FOREGROUND, "guarded")
    try:
        sent = time.perf_counter()
        proc.send_signal(sig)
        assert proc.wait(timeout=30) == code
        took = time.perf_counter() - sent
        assert wait_gone(pids) == []
    finally:
        end(proc, pids)
    err = (tmp_path / "log").read_text().strip().splitlines()
    assert err[-1:] == [line] and "Traceback" not in "\n".join(err), err
    assert took < EXIT_WITHIN_S, took


def test_an_unguarded_compile_waits_for_its_compilers_after_sigterm(tmp_path):
    """Negative control: without the guard the command waits for its compilers, so the check
    above can fail."""
    proc, pids = fake_compile(tmp_path, FOREGROUND, "unguarded")
    try:
        proc.send_signal(signal.SIGTERM)
        with pytest.raises(subprocess.TimeoutExpired):
            proc.wait(timeout=EXIT_WITHIN_S)
        assert len(alive(pids)) == 4
    finally:
        end(proc, pids)
