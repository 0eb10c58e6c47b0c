"""Ctrl-C (SIGINT) and SIGTERM at any moment of `walk3d predict`: imports, model build, solve,
figures, writing. Each run ends within a few seconds with 130 or 143 and nothing written, or,
when the signal comes after the result is complete, with 0 and a complete result; never a
traceback, a retry, or a half-written folder (issue #60, item 6). From walk3d's first line on
(``walk3d/__init__.py``) the signal gives walk3d's line; before it, while Python itself starts,
the signal's default action ends the process (nothing written either)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

from walk3d.results.prediction import check_complete

TIMES_S = (0.15, 0.4, 0.8, 1.5, 2.5, 3.5, 4.5, 6.0, 8.0)
"""When the signal is sent after the start: from the imports to the figures and the writing of
the default prediction from the atlas (about 5-10 s on 2 cores)."""
EXIT_WITHIN_S = 5.0
"""s: the bar of issue #60 is 2 s; a loaded CI machine gets room."""
EXPECTED = {
    signal.SIGINT: (130, "walk3d: interrupted"),
    signal.SIGTERM: (143, "walk3d: terminated"),
}


def _run(tmp_path, sig: signal.Signals, after_s: float):
    out = tmp_path / "o"
    cmd = [sys.executable, "-m", "walk3d.cli", "predict", "--threads", "1",
           "--no-compile-later", "--out", str(out)]  # fmt: skip
    env = os.environ | {"OPENBLAS_NUM_THREADS": "1", "MPLBACKEND": "Agg"}
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    time.sleep(after_s)
    sent = time.perf_counter()
    p.send_signal(sig)
    _, err = p.communicate(timeout=120)
    return p.returncode, err, time.perf_counter() - sent, out


def _problem(code: int, err: str, took: float, out, sig: signal.Signals, after_s: float):
    """What is wrong with a run's end, or None."""
    if "Traceback" in err:
        return "a traceback"
    if code == 0:  # the signal came once the result was complete
        check_complete(out)
        return None
    if code == -sig:  # before Python ran walk3d's first line: the signal's own action
        ok = after_s < 0.3 and not err and not out.exists()  # (a shell reports 128 + N)
        return None if ok else f"killed by the signal at {after_s} s: {err!r}"
    want_code, want_line = EXPECTED[sig]
    if code != want_code or err.strip().splitlines()[-1:] != [want_line]:
        return f"exit {code}, stderr {err!r}"
    if out.exists():
        return f"left {sorted(p.name for p in out.iterdir())}"
    return f"ended {took:.1f} s after the signal" if took > EXIT_WITHIN_S else None


@pytest.mark.solve
@pytest.mark.parametrize("after_s", TIMES_S)
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_a_signal_at_any_moment_ends_cleanly(tmp_path, sig, after_s):
    code, err, took, out = _run(tmp_path, sig, after_s)
    leftovers = [p.name for p in tmp_path.iterdir() if p.name != "o"]
    assert not leftovers, leftovers  # no temporary beside the result
    assert _problem(code, err, took, out, sig, after_s) is None, err


def test_the_check_catches_a_program_that_ends_with_a_traceback(tmp_path):
    """The control: a Python program interrupted in its own code (a traceback, exit 1 or the
    signal's) is caught."""
    p = subprocess.Popen([sys.executable, "-c", "import time\ntime.sleep(30)"],
                         stderr=subprocess.PIPE, text=True)  # fmt: skip
    time.sleep(1.0)
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=30)
    assert _problem(p.returncode, err, 0.0, tmp_path / "o", signal.SIGINT, 1.0) is not None


def test_an_import_failed_by_ctrl_c_counts_as_the_interrupt():
    """A C extension interrupted while it is imported raises ImportError from the
    KeyboardInterrupt (seen with scipy.spatial): that ends as Ctrl-C does, not with a
    traceback; a plain ImportError does not (the control)."""
    from walk3d.cli import _from_interrupt

    try:
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as ki:
            raise ImportError("initialization failed") from ki
    except ImportError as exc:
        assert _from_interrupt(exc)
    assert not _from_interrupt(ImportError("no module named x"))
    schema_error = type("SchemaError", (Exception,), {})  # pydantic_core's, by its name
    assert _from_interrupt(
        schema_error('Error building "literal" validator:\n  KeyboardInterrupt: ')
    )
    assert not _from_interrupt(schema_error('Error building "literal" validator'))


_SHOW = (
    "import signal, walk3d\nprint(getattr(signal.getsignal(signal.SIGTERM), '__name__', 'default'))"
)


def _handler_in(tmp_path, script: str, **kw) -> str:
    path = tmp_path / "walk3d"  # a script of the command's name
    path.write_text(script)
    env = os.environ | {"PYTHONPATH": os.pathsep.join(sys.path)}
    r = subprocess.run([sys.executable, str(path)], capture_output=True, text=True, timeout=60,
                       env=env, **kw)  # fmt: skip
    assert r.returncode == 0, r.stderr
    return r.stdout.strip().splitlines()[-1]


def test_the_early_handlers_are_the_commands_alone(tmp_path):
    """Importing walk3d in the ``walk3d`` command installs walk3d's handler at once; a program
    importing walk3d (the control), a worker process started from the command (as Dask's) and
    a command whose caller ignores the signal keep theirs."""
    assert _handler_in(tmp_path, _SHOW) == "_exit_at_once"
    plain = subprocess.run(
        [sys.executable, "-c", _SHOW],
        capture_output=True,
        text=True,
        timeout=60,
        env=os.environ | {"PYTHONPATH": os.pathsep.join(sys.path)},
    )
    assert plain.stdout.strip() == "default", plain.stderr
    spawned = (
        "import multiprocessing as mp, signal\n"
        "def show(q):\n"
        "    import walk3d\n"
        "    q.put(getattr(signal.getsignal(signal.SIGTERM), '__name__', 'default'))\n"
        "if __name__ == '__main__':\n"
        "    ctx = mp.get_context('spawn'); q = ctx.Queue()\n"
        "    p = ctx.Process(target=show, args=(q,)); p.start(); print(q.get()); p.join()\n"
    )
    assert _handler_in(tmp_path, spawned) == "default"
    ignored = "import signal, walk3d\nprint(signal.getsignal(signal.SIGTERM) == signal.SIG_IGN)"
    hold = lambda: signal.signal(signal.SIGTERM, signal.SIG_IGN)  # noqa: E731
    assert _handler_in(tmp_path, ignored, preexec_fn=hold) == "True"
