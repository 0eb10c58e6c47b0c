"""The trials file of walk3d fit-criterion: what it accepts, and one line for what it does not."""

import pytest
from typer.testing import CliRunner

from walk3d.cli import app
from walk3d.fitting.trials import read_trials
from walk3d.io.errors import DataFileError

GOOD = """
[[trial]]
name = "w"
speed = 1.3
period = 1.1
double_support = 0.12
reference = "ref.csv"

[[trial]]
name = "t"
ik = "sub/ik.mot"
grf = "sub/grf.mot"
mass = 62
height = 1.7
sex = "female"
reference = ["ref.csv"]
reference_speed = 1.1
"""


@pytest.fixture
def folder(tmp_path):
    (tmp_path / "sub").mkdir()
    for name in ("ref.csv", "sub/ik.mot", "sub/grf.mot"):
        (tmp_path / name).write_text("x")
    return tmp_path


def test_trials_read_with_paths_from_the_files_folder(folder):
    (folder / "trials.toml").write_text(GOOD)
    w, t = read_trials(folder / "trials.toml")
    assert (w.name, w.speed, w.mass, w.reference) == ("w", 1.3, 68.8, [folder / "ref.csv"])
    assert (t.ik, t.sex, t.reference_speed) == (folder / "sub" / "ik.mot", "female", 1.1)


@pytest.mark.parametrize("change, words", [
    (('name = "t"', 'name = "w"'), "share a name"),
    (('grf = "sub/grf.mot"\n', ""), "ik and grf come together"),
    (("period = 1.1\n", ""), "speed, period and double_support"),
    (("mass = 62", "mass = -62"), "mass"),
    (('ik = "sub/ik.mot"', 'ik = "sub/none.mot"'), "no such file"),
    (("[[trial]]", "[[walk]]", -1), "no \\[\\[trial\\]\\] tables"),
    (("reference_speed", "belt"), "belt"),
    (("[[trial]]", "[[trial]"), "not a TOML file"),
    # text and bools where a number goes: pydantic would read "6_8" as 68 and true as 1 s
    (("mass = 62", 'mass = "6_8"'), "mass: Input should be a valid number"),
    (("period = 1.1", "period = true"), "period: Input should be a valid number"),
])  # fmt: skip
def test_bad_trials_are_one_line(folder, change, words):
    old, new, *count = change
    (folder / "trials.toml").write_text(GOOD.replace(old, new, *(count or [1])))
    with pytest.raises(DataFileError, match=words) as info:
        read_trials(folder / "trials.toml")
    assert "\n" not in str(info.value)


def test_the_good_file_is_not_refused(folder):  # the negative control of the table above
    (folder / "trials.toml").write_text(GOOD)
    assert len(read_trials(folder / "trials.toml")) == 2


@pytest.mark.parametrize("args, words", [
    (["nofile.toml", "--parameter", "impact"], "nofile.toml"),
    (["{trials}", "--parameter", "nosuch"], "not a criterion term"),
    (["{trials}", "--parameter", "impact", "--base", "tor"], "no weights to fit"),
    (["{trials}", "--parameter", "impact", "--hold-out", "zz"], "not a trial"),
    (["{trials}", "--parameter", "impact", "--seed", "-1"], "--seed"),
])  # fmt: skip
def test_cli_bad_input_is_one_line_and_exit_2(folder, args, words):
    (folder / "trials.toml").write_text(GOOD)
    args = [a.format(trials=folder / "trials.toml") for a in args]
    res = CliRunner().invoke(app, ["fit-criterion", *args, "--out", str(folder / "fit")])
    assert res.exit_code == 2, res.output
    assert words in res.output and "Traceback" not in res.output
    assert not (folder / "fit").exists()


@pytest.mark.parametrize("kind", ["fifo", "folder", "regular"])
def test_a_trial_file_that_is_no_regular_file_is_refused(folder, kind):
    """A FIFO named by a trial was taken for a file, and its reader blocked for ever.
    Negative control: the regular file is accepted."""
    import os

    (folder / "trials.toml").write_text(GOOD)
    ref = folder / "ref.csv"
    if kind != "regular":
        ref.unlink()
        os.mkfifo(ref) if kind == "fifo" else ref.mkdir()
    if kind == "regular":
        assert len(read_trials(folder / "trials.toml")) == 2
        return
    with pytest.raises(DataFileError, match=f"trial w: {ref} is (a folder|not a regular file)"):
        read_trials(folder / "trials.toml")
