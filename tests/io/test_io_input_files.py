"""Every walk3d reader reads through walk3d.io.checks.open_input: a FIFO (it blocked the read
for ever), a device or a folder in place of an input file is one DataFileError line saying it
is not a regular file, at once; a regular file, or a link to one, is read."""

import os
import threading
from pathlib import Path

import pytest

from walk3d.io import c3d, calibration, checks, criterion, cycle_table, storage, trc
from walk3d.io.errors import DataFileError
from walk3d.validation.run import sort_references

READERS = {
    "json": (checks.read_json_object, ".json"),
    "npz": (checks.read_npz, ".npz"),
    "xml": (checks.read_xml, ".xml"),
    "toml": (checks.read_toml, ".toml"),
    "storage": (storage.read_storage, ".mot"),
    "trc": (trc.read_trc, ".trc"),
    "cycle table": (cycle_table.read_cycle_table, ".csv"),
    "calibration": (calibration.read_calibration, ".json"),
    "criterion": (criterion.read_criterion, ".toml"),
    "c3d": (c3d.read_c3d, ".c3d"),
    "references": (lambda path: sort_references([path]), ".csv"),
}
"""Each reader of a file a user gives walk3d, and the suffix of its file."""


def _within(seconds: float, call):
    """What ``call()`` returned or raised, or a failure if it is still blocked after ``seconds``
    (it runs in a daemon thread: a read blocked for ever does not hold the test run)."""
    out = []

    def run():
        try:
            out.append(call())
        except Exception as exc:  # noqa: BLE001 - handed to the test
            out.append(exc)

    worker = threading.Thread(target=run, daemon=True)
    worker.start()
    worker.join(seconds)
    assert out, f"still blocked after {seconds} s"
    return out[0]


def _make(tmp_path: Path, kind: str, suffix: str) -> Path:
    path = tmp_path / f"input{suffix}"
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "folder":
        path.mkdir()
    elif kind == "device":
        path.symlink_to(os.devnull)
    else:
        path.write_bytes(b"neither of walk3d's formats\n")
    return path


@pytest.mark.parametrize("reader", READERS)
@pytest.mark.parametrize(("kind", "why"), [("fifo", "is not a regular file (a FIFO)"),
                                           ("device", "is not a regular file (a device)"),
                                           ("folder", "is a folder, not a file"),
                                           ("regular", None)])  # fmt: skip
def test_an_input_that_is_no_regular_file_is_one_line_at_once(tmp_path, reader, kind, why):
    """Negative control: a regular file is read, and refused (if at all) for its content."""
    read, suffix = READERS[reader]
    path = _make(tmp_path, kind, suffix)
    got = _within(10, lambda: read(path))
    if why is None:
        assert not isinstance(got, Exception) or "regular file" not in str(got), got
        return
    assert isinstance(got, DataFileError), got
    assert str(got) == f"{path.name}: {why}"


@pytest.mark.parametrize("kind", ["fifo", "device", "folder", "regular", "link", "missing"])
def test_input_problem_names_what_the_reader_refuses(tmp_path, kind):
    """The command line's check before any read (walk3d.cli.common.input_file). Negative
    controls: a regular file and a link to one pass, a missing file is left to its reader."""
    path = tmp_path / "input.mot"
    if kind == "link":
        (tmp_path / "real.mot").write_text("x")
        path.symlink_to(tmp_path / "real.mot")
    elif kind != "missing":
        path = _make(tmp_path, kind, ".mot")
    expected = {"fifo": "is not a regular file (a FIFO)", "device": "is not a regular file "
                "(a device)", "folder": "is a folder, not a file"}.get(kind)  # fmt: skip
    assert checks.input_problem(path) == expected
    if kind in ("regular", "link"):
        content = b"x" if kind == "link" else b"neither of walk3d's formats\n"
        assert checks.read_input(path) == content
