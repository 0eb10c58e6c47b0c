"""Standard output that cannot be written: /dev/full is one line and exit code 3, a closed pipe
(``walk3d body | head -1``) a quiet exit with code 141; never a traceback. Standard error that
cannot be written leaves the exit code as it is (2 for bad input)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
needs_dev_full = pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full")


def _env() -> dict[str, str]:
    path = os.pathsep.join([str(REPO / "src"), os.environ.get("PYTHONPATH", "")])
    return dict(os.environ, PYTHONPATH=path)


def _walk3d(*args: str, stdout) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "walk3d.cli", *args], stdout=stdout,
                          stderr=subprocess.PIPE, text=True, timeout=120, env=_env())  # fmt: skip


@needs_dev_full
@pytest.mark.parametrize("args", [("body", "--json"), ("body",)])
def test_a_full_disk_is_one_line_and_exit_3(args):
    with open("/dev/full", "w") as full:
        r = _walk3d(*args, stdout=full)
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 3 and len(lines) == 1, r.stderr
    assert lines[0] == "walk3d: error: cannot write the output: no space left on device"


def test_a_closed_pipe_is_a_quiet_exit_141():
    """The reader end is closed before walk3d writes, as ``head -1`` does after a line."""
    read, write = os.pipe()
    os.close(read)
    try:
        r = _walk3d("body", stdout=write)
    finally:
        os.close(write)
    assert r.returncode == 141 and r.stderr == "", r.stderr


def test_a_writable_output_is_exit_0(tmp_path):
    """Negative control: the same command into a file."""
    with open(tmp_path / "out.json", "w") as f:
        r = _walk3d("body", "--json", stdout=f)
    assert r.returncode == 0 and r.stderr == ""
    assert (tmp_path / "out.json").read_text().startswith("{")


def _walk3d_to_full_stderr(*args: str, stdout=subprocess.DEVNULL) -> int:
    with open("/dev/full", "w") as full:
        return subprocess.run([sys.executable, "-m", "walk3d.cli", *args], stdout=stdout,
                              stderr=full, timeout=120, env=_env()).returncode  # fmt: skip


@needs_dev_full
@pytest.mark.parametrize(
    "args", [("body", "--mass", "nan"), ("body", "--bogus"), ("atlas",), ("body", "--sex", "x")]
)
def test_bad_input_exits_2_when_stderr_cannot_be_written(args):
    """The error line failed to write and the traceback of that failure made it exit 1."""
    assert _walk3d_to_full_stderr(*args) == 2


@needs_dev_full
def test_a_full_stdout_is_exit_3_when_stderr_is_full_too():
    with open("/dev/full", "w") as full:
        assert _walk3d_to_full_stderr("body", "--json", stdout=full) == 3


@needs_dev_full
def test_good_input_exits_0_with_stderr_full(tmp_path):
    """Negative control: nothing to say on stderr, the output is written."""
    with open(tmp_path / "out.json", "w") as f:
        assert _walk3d_to_full_stderr("body", "--json", stdout=f) == 0
    assert (tmp_path / "out.json").read_text().startswith("{")


def test_a_log_warning_is_one_walk3d_line_during_a_command(monkeypatch, capsys):
    """A warning that walk3d logs while a command runs (a damaged cache entry) is one line with
    the command's prefix; after the command (the control) walk3d's logger has its handler no
    more."""
    import logging

    import walk3d.cli

    log = logging.getLogger("walk3d.solve.model_cache")

    def run(args):
        log.warning("ignoring damaged model cache entry %s\n(%s); rebuilding", "x.bin", "bad")
        sys.exit(0)

    monkeypatch.setattr(walk3d.cli, "_run", run)
    with pytest.raises(SystemExit) as info:
        walk3d.cli.main(["body"])
    assert info.value.code == 0
    err = capsys.readouterr().err
    assert err == "walk3d: warning: ignoring damaged model cache entry x.bin (bad); rebuilding\n"
    assert not any(
        h.__class__.__name__ == "_LogLines" for h in logging.getLogger("walk3d").handlers
    )
