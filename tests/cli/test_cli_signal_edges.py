"""The two edges of the signal sweep (tests/cli/test_cli_signals.py) checked in one process: a
Ctrl-C or SIGTERM that Python swallows in a finalizer is sent again, and a signal after the
result folder is complete ends with the result's own exit code."""

from __future__ import annotations

import functools
import os
import signal
import sys
import time

import pytest

from walk3d.cli import _on_unraisable, finished


class _RaisesWhenCollected:
    def __init__(self, exc: BaseException) -> None:
        self.exc = exc

    def __del__(self) -> None:
        raise self.exc


def _signal_seen(sig: signal.Signals, exc: BaseException) -> tuple[list[int], list[str]]:
    """The signals the main thread got after a finalizer raised ``exc`` under walk3d's hook, and
    what reached the previous hook."""
    seen: list[int] = []
    printed: list[str] = []
    previous = signal.signal(sig, lambda signum, _frame: seen.append(signum))
    hook = sys.unraisablehook
    sys.unraisablehook = functools.partial(
        _on_unraisable, previous=lambda u: printed.append(repr(u.exc_value))
    )
    try:
        _RaisesWhenCollected(exc)  # collected at once: "Exception ignored in __del__"
        deadline = time.monotonic() + 2.0
        while not seen and time.monotonic() < deadline:
            time.sleep(0.01)
    finally:
        signal.signal(sig, previous)
        sys.unraisablehook = hook
    return seen, printed


def test_a_swallowed_interrupt_is_sent_again():
    """A KeyboardInterrupt ignored in a finalizer comes back as SIGINT, silently; any other
    unraisable error (the control) goes to the previous hook, and sends nothing."""
    seen, printed = _signal_seen(signal.SIGINT, KeyboardInterrupt())
    assert seen == [signal.SIGINT] and not printed
    seen, printed = _signal_seen(signal.SIGINT, ValueError("boom"))
    assert not seen and printed == ["ValueError('boom')"]


def test_a_swallowed_termination_is_sent_again_as_sigterm():
    from walk3d.solve.progress import Terminated

    seen, _ = _signal_seen(signal.SIGTERM, Terminated())
    assert seen == [signal.SIGTERM]


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    from result_support import result_folder

    return result_folder(tmp_path_factory.mktemp("r") / "out")


def test_a_signal_after_the_commit_keeps_the_results_code(written, tmp_path, capsys):
    """A new complete folder: its exit code (0, converged and walking) and one line; the same
    folder as before the run, a missing one or an incomplete one (the controls): None, so the
    signal ends the run with 130 or 143."""
    assert finished.code_if_written(written, None) == 0
    assert "was complete (report.html and the table skipped)" in capsys.readouterr().err
    assert finished.code_if_written(written, finished.identity(written)) is None
    assert finished.code_if_written(tmp_path / "none", None) is None
    broken = tmp_path / "broken"
    broken.mkdir()
    (broken / "summary.json").write_text("{}")
    assert finished.code_if_written(broken, None) is None
    assert not capsys.readouterr().err


def test_the_identity_changes_when_a_folder_is_renamed_into_place(tmp_path):
    a, b = tmp_path / "a", tmp_path / "b"
    a.mkdir()
    b.mkdir()
    before = finished.identity(a)
    os.rename(a, tmp_path / "old")
    os.rename(b, a)
    assert finished.identity(a) != before and finished.identity(tmp_path / "none") is None


_AT_EXIT = """
import os, signal, sys
sys.argv = ["walk3d", "body"]
import walk3d.cli
def end(code):  # the command's own end, os._exit, after it reports the handler
    print("ignored at exit:", signal.getsignal(signal.SIGTERM) == signal.SIG_IGN, flush=True)
    os._exit(code or 0)
walk3d.cli._end_now = end
try:
    walk3d.cli.main({argv})
except SystemExit:
    end(0)
"""


def test_the_command_ignores_a_signal_once_its_outcome_is_decided():
    """Python's exit restores the default action of a handled signal, and a SIGTERM in the last
    moments then killed the command with its result complete and no line: the command (no
    ``argv``) ignores both signals as it exits; an in-process call (the control) gets its own
    handler back."""
    import subprocess

    def run(argv: str) -> str:
        r = subprocess.run([sys.executable, "-c", _AT_EXIT.format(argv=argv)],
                           capture_output=True, text=True, timeout=60)  # fmt: skip
        return r.stdout.strip().splitlines()[-1]

    assert run("") == "ignored at exit: True"
    assert run('["body"]') == "ignored at exit: False"
