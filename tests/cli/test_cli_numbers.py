"""Numeric options read as the user sees them (walk3d.cli.numbers): Python's float() and int(),
which Typer uses, read ``6_8`` as 68 and a full-width ``２`` as 2; walk3d refuses them with one
line."""

from __future__ import annotations

import pytest
import typer

import walk3d.cli  # noqa: F401  (registers the commands)
from walk3d.cli.common import app
from walk3d.cli.numbers import plain_numbers


@pytest.fixture(scope="module")
def command():
    return typer.main.get_command(app)


@pytest.mark.parametrize(
    ("args", "message"),
    [(["predict", "--mass", "6_8"], "--mass takes a finite decimal number, got '6_8'"),
     (["predict", "--mass=6_8"], "--mass takes a finite decimal number"),
     (["predict", "--seed", "3.0"], "--seed takes an integer"),
     (["predict", "--speed", "1.2\u0663"], "--speed takes a finite decimal number"),
     (["atlas", "build", "--seed", "1_0"], "--seed takes an integer"),
     (["track", "--period", "1_1"], "--period takes a finite decimal number"),
     (["predict", "--leg-length-difference=-.0_2"], "--leg-length-difference takes a finite"),
     (["predict", "--leg-length-difference", "-0.0２"], "--leg-length-difference takes")],
)  # fmt: skip
def test_a_number_that_is_not_plain_is_refused(command, args, message):
    assert plain_numbers(command, args) == message or message in plain_numbers(command, args)


@pytest.mark.parametrize(
    "args",
    [["predict", "--mass", "68", "--speed=1.2e0", "--seed", "3"],
     ["predict", "--out", "6_8"],  # not a numeric option
     ["predict", "--", "--mass", "6_8"],
     ["predict", "--speed", "nan"],  # read as written: the command refuses it by its range
     ["body", "--mass", "-60"], ["predict", "--leg-length-difference", "-0.02"],
     ["predict", "--seed", " 3", "--mass", " 68 "]],  # spaces around: the number as typed
)  # fmt: skip
def test_plain_numbers_and_other_options_pass(command, args):
    """The control: plain decimals, and text in a text option, are left to the command."""
    assert plain_numbers(command, args) is None


def test_the_command_refuses_before_it_runs(capsys):
    with pytest.raises(SystemExit) as info:
        walk3d.cli.main(["body", "--mass", "6_8"])
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert err == "walk3d: error: --mass takes a finite decimal number, got '6_8'\n"


def test_fit_criterion_refuses_an_out_that_is_a_file_in_one_line(tmp_path, capsys):
    """``walk3d fit-criterion --out FILE`` is one line and exit 2 (it was a traceback); the
    file is left as it was."""
    trials = tmp_path / "trials.toml"
    trials.write_text('[[trial]]\nname = "t"\nspeed = 1.2\nperiod = 1.1\ndouble_support = 0.12\n'
                      'reference = ["t.csv"]\n')  # fmt: skip
    (tmp_path / "t.csv").write_text("x\n")
    out = tmp_path / "afile"
    out.write_text("mine")
    with pytest.raises(SystemExit) as info:
        walk3d.cli.main(["fit-criterion", str(trials), "--parameter", "accel", "--out", str(out)])
    err = capsys.readouterr().err
    assert info.value.code == 2 and err.count("\n") == 1, err
    assert err.startswith("walk3d: error: --out") and "existing file" in err, err
    assert out.read_text() == "mine"


@pytest.mark.parametrize(
    ("option", "value"),
    [("--popsize", "99999999999"), ("--generations", "99999999999999999999"),
     ("--seed", "99999999999999999999999"), ("--workers", "99999999999")],
)  # fmt: skip
def test_fit_criterion_refuses_absurd_sizes_before_its_folder(tmp_path, capsys, option, value):
    """A population or seed CMA-ES cannot take was a MemoryError traceback, or refused only
    after the fit's folder was made; the control (valid sizes) reaches the --out check."""
    trials = tmp_path / "trials.toml"
    trials.write_text('[[trial]]\nname = "t"\nspeed = 1.2\nperiod = 1.1\ndouble_support = 0.12\n'
                      'reference = ["t.csv"]\n')  # fmt: skip
    (tmp_path / "t.csv").write_text("x\n")
    out = tmp_path / "fit"
    with pytest.raises(SystemExit) as info:
        walk3d.cli.main(["fit-criterion", str(trials), "--parameter", "accel", "--out", str(out),
                         option, value])  # fmt: skip
    err = capsys.readouterr().err
    assert info.value.code == 2 and err.startswith(f"walk3d: error: {option} must be"), err
    assert not out.exists()
