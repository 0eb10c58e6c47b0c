"""walk3d predict --out that a file system or walk3d's UTF-8 files cannot hold: a byte that is
not UTF-8 (``$'/tmp/x\\xff'``), a name longer than a file system takes. One line and exit
code 2, before any solve; the solve is replaced by one that fails the test if it starts."""

import pytest
from typer.testing import CliRunner

from walk3d.cli import app
from walk3d.outputs import NAME_MAX_BYTES, TEMPORARY_BYTES


class Solved(Exception):
    """walk3d.pipeline.predict was reached: the command accepted its input."""


@pytest.fixture
def no_solve(monkeypatch):
    import walk3d.pipeline as pipeline

    def predict(*args, **kwargs):
        raise AssertionError("the solve started")

    monkeypatch.setattr(pipeline, "predict", predict)


def _predict(out):
    return CliRunner().invoke(app, ["predict", "--out", str(out)])


@pytest.mark.parametrize(
    ("name", "words"),
    [("x\udcff", "is not valid UTF-8 (byte 0xff)"),
     ("a" * 300, "is 300 bytes long, at most 231"),
     ("é" * 120, "is 240 bytes long, at most 231"),
     ("a" * 300 + "/result", "is 300 bytes long, at most 255")],
    ids=["byte-ff", "300-bytes", "240-bytes-utf8", "300-bytes-parent"],
)  # fmt: skip
def test_an_out_that_cannot_be_written_is_refused_before_the_solve(tmp_path, no_solve, name,
                                                                   words):  # fmt: skip
    """A shell's non-UTF-8 byte or a 300-byte name passed the check, the solve ran, and the
    folder could not be written (or named in summary.json) after it."""
    r = _predict(tmp_path / name)
    lines = r.stderr.strip().splitlines()
    assert r.exit_code == 2 and len(lines) == 1, (r.exception, r.output)
    assert lines[0].startswith("walk3d: error: --out") and words in lines[0], lines
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize(
    "name", ["résultat-歩行", "a" * (NAME_MAX_BYTES - TEMPORARY_BYTES)], ids=["utf8", "longest"]
)
def test_a_utf8_or_longest_name_reaches_the_solve(tmp_path, monkeypatch, name):
    """Negative control: UTF-8 beyond ASCII, and the longest name walk3d can write."""
    import walk3d.pipeline as pipeline

    def predict(*args, **kwargs):
        raise Solved

    monkeypatch.setattr(pipeline, "predict", predict)
    r = _predict(tmp_path / name)
    assert isinstance(r.exception, Solved), r.output
