"""An input file that is a FIFO, a device or a folder: one line naming the option and saying it
is not a regular file, exit code 2, before the command reads anything (a FIFO blocked
calibrate --ik, predict --calibration, --criterion and --from-trial for ever, and validate
--reference FIFO said "reference file not found")."""

import os

import pytest
from helpers import cli, one_line_error

CASES = {
    "calibrate --ik": (["calibrate", "--ik", "{f}.mot", "--grf", "{r}", "--out", "{o}.json"],
                       "--ik"),
    "predict --calibration": (["predict", "--calibration", "{f}.json", "--out", "{o}"],
                              "--calibration"),
    "predict --criterion": (["predict", "--criterion", "{f}.toml", "--out", "{o}"], "--criterion"),
    "predict --from-trial": (["predict", "--from-trial", "{f}.mot", "--grf", "{r}", "--out",
                              "{o}"], "--from-trial"),
    "predict --grf": (["predict", "--from-trial", "{r}", "--grf", "{f}.mot", "--out", "{o}"],
                      "--grf"),
    "validate --reference": (["validate", "{o}", "--reference", "{r}", "--reference",
                              "{f}.csv"], "--reference"),
    "track --table": (["track", "--table", "{f}.csv", "--out", "{o}"], "--table"),
    "fit-criterion": (["fit-criterion", "{f}.toml", "--out", "{o}", "--parameter", "accel"],
                      "trials"),
    "compile --calibration": (["compile", "--calibration", "{f}.json"], "--calibration"),
}  # fmt: skip
"""Each command and option that reads a file the user names: its arguments, with ``{f}`` the
file checked, ``{r}`` a regular file and ``{o}`` a path never written, and the option's name."""


@pytest.mark.parametrize("case", CASES)
@pytest.mark.parametrize(("kind", "why"), [("fifo", "is not a regular file (a FIFO)"),
                                           ("device", "is not a regular file (a device)"),
                                           ("regular", None)])  # fmt: skip
def test_an_input_that_is_no_regular_file_is_refused_naming_the_option(
    capsys, tmp_path, case, kind, why
):
    """Negative control: a regular file of the wrong content gets past the check to the
    command's reader, which refuses it for its content (still exit 2, nothing solved)."""
    args, option = CASES[case]
    regular = tmp_path / "regular.txt"
    regular.write_text("neither of walk3d's formats\n")
    f = tmp_path / "input"
    suffix = next(a for a in args if a.startswith("{f}"))[3:]
    checked = f.with_suffix(suffix)
    if kind == "fifo":
        os.mkfifo(checked)
    elif kind == "device":
        checked.symlink_to(os.devnull)
    else:
        checked.write_text("neither of walk3d's formats\n")
    out = tmp_path / "never"
    argv = [a.format(f=f, r=regular, o=out) for a in args]
    result = cli(capsys, *argv)
    if why is None:
        code, _, err = result
        assert code == 2 and "regular file" not in err and "Traceback" not in err, err
    else:
        one_line_error(result, f"{option} ", f"{checked.name}: {why}")
    assert not out.exists() and not out.with_suffix(".json").exists()
