"""walk3d atlas: bad input is one line and exit code 2, before any sweep; show lists the files."""

import os
import subprocess
import sys

import pytest
from helpers import cli, one_line_error

BAD = [
    (["--sex", "alien"], "--sex alien"),
    (["--criterion", "tor=1,accel=1"], "named presets"),
    (["--criterion", ""], "named presets"),
    (["--criterion", "bogus"], "--criterion bogus: expected named presets"),
    (["--speeds", "2:1:0.1"], "empty or reversed"),
    (["--speeds", "0.1:4:1e-10"], "speeds, at most 41"),
]


@pytest.mark.parametrize("args,word", BAD)
def test_atlas_build_bad_input_exits_2_with_one_line(tmp_path, args, word):
    cmd = [sys.executable, "-m", "walk3d.cli", "atlas", "build", "--work", str(tmp_path), *args]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and word in lines[0], r.stderr
    assert not any(tmp_path.iterdir())  # nothing was started


def test_atlas_show_lists_the_shipped_files():
    r = subprocess.run([sys.executable, "-m", "walk3d.cli", "atlas", "show"], capture_output=True,
                       text=True, timeout=60, env=os.environ | {"COLUMNS": "200"})  # fmt: skip
    assert r.returncode == 0, r.stderr
    assert "male" in r.stdout and "natural" in r.stdout and "yes" in r.stdout
    assert "17 (17)" in r.stdout and "19 (19)" in r.stdout  # handover entries (warm starts)


@pytest.mark.parametrize(
    ("args", "line"),
    [(["atlas"], "walk3d: error: walk3d atlas needs a command: build, show"),
     (["atlas", "bogus"], "walk3d: error: No such command 'bogus'.")],
)  # fmt: skip
def test_atlas_without_its_command_shows_the_help_and_one_error_line(args, line):
    """Not an empty "walk3d: error:" line; a wrong command is the control (its own message)."""
    r = subprocess.run([sys.executable, "-m", "walk3d.cli", *args], capture_output=True,
                       text=True, timeout=60, env=os.environ | {"COLUMNS": "200"})  # fmt: skip
    assert r.returncode == 2 and r.stderr.strip().splitlines() == [line], r.stderr
    assert ("Usage: walk3d atlas" in r.stdout + r.stderr) == (args == ["atlas"])


def test_atlas_build_prints_a_damaged_speed_warning_as_one_line(tmp_path, monkeypatch, capsys):
    """A speed folder solved again warned in Python's two-line form (file, line, source);
    now one 'walk3d: warning:' line as sweep prints it. Control: the build goes on and ends."""
    import warnings

    import walk3d.campaign.atlas as atlas
    from walk3d.cli import main
    from walk3d.model.terms import DEFAULT_PRESET

    def build(sex, preset, work, speeds, out, seed, progress):
        warnings.warn(f"{work}/v_1.200 cannot be read (summary.json: invalid JSON): solving "
                      "1.2 m/s again", RuntimeWarning, stacklevel=2)  # fmt: skip
        return tmp_path / f"{sex}-{preset}.json", 2, 2

    monkeypatch.setattr(atlas, "build_atlas", build)
    with pytest.raises(SystemExit) as info:
        main(["atlas", "build", "--work", str(tmp_path), "--sex", "male", "--criterion",
              DEFAULT_PRESET, "--speeds", "1.2,1.4"])  # fmt: skip
    out, err = capsys.readouterr()
    assert info.value.code in (0, None) and "2 of 2 speeds walk" in out, err
    assert err.strip().splitlines() == [
        f"walk3d: warning: {tmp_path}/v_1.200 cannot be read (summary.json: invalid JSON): "
        "solving 1.2 m/s again"
    ]


@pytest.fixture
def no_build(monkeypatch):
    """Fail the test if the atlas build (its sweeps) starts."""
    import walk3d.campaign.atlas as atlas

    def build(*args, **kwargs):
        pytest.fail("the atlas build started")

    monkeypatch.setattr(atlas, "build_atlas", build)


def _prediction_folder(folder):
    folder.mkdir()
    for name in ("summary.json", "result.npz", "motion.mot"):
        (folder / name).write_text("{}")
    return folder


@pytest.mark.parametrize(
    ("where", "words"),
    [("work-file", "--work {work} is an existing file"),
     ("work-prediction", "--work {work} holds files walk3d did not write (motion.mot, result.npz"),
     ("work-stray", "holds files walk3d did not write (notes/)"),
     ("out-file", "--out {out} is an existing file"),
     ("out-atlas-folder", "--out {out}/male-natural.json is a folder"),
     ("out-prediction", "--out {out} is a walk3d result or sweep folder"),
     ("work-inside-prediction", "--work {work} is inside the walk3d result folder")],
)  # fmt: skip
def test_atlas_build_refuses_its_folders_before_any_sweep(capsys, tmp_path, no_build, where,
                                                          words):  # fmt: skip
    """An --out that is a file failed after the sweeps (exit 3); a --work that is a prediction
    folder got the sweeps written into it."""
    work, out = tmp_path / "work", tmp_path / "atlas"
    if where == "work-file":
        work.write_text("x")
    elif where == "work-prediction":
        _prediction_folder(work)
    elif where == "work-stray":
        (work / "notes").mkdir(parents=True)
        (work / "notes" / "a.txt").write_text("mine")
    elif where == "out-file":
        out.write_text("x")
    elif where == "out-prediction":
        _prediction_folder(out)
    elif where == "work-inside-prediction":
        work = _prediction_folder(tmp_path / "pred") / "w"
    else:
        (out / "male-natural.json").mkdir(parents=True)
    r = cli(capsys, "atlas", "build", "--work", work, "--out", out, "--sex", "male")
    one_line_error(r, words.format(work=work, out=out))


def test_atlas_build_accepts_its_own_work_and_atlas_folders(capsys, tmp_path, monkeypatch):
    """Negative control: a resumed --work (a sweep folder, an empty one) and an --out holding
    other atlas files reach the build."""
    import walk3d.campaign.atlas as atlas

    work, out = tmp_path / "work", tmp_path / "atlas"
    (work / "male-natural").mkdir(parents=True)
    (work / "male-natural" / "sweep.json").write_text("{}")
    (work / "female-natural").mkdir()
    out.mkdir()
    (out / "male-tor.json").write_text("{}")
    built = []

    def build(sex, preset, *args):
        built.append(sex)
        return out / f"{sex}-{preset}.json", 1, 1

    monkeypatch.setattr(atlas, "build_atlas", build)
    code, stdout, err = cli(capsys, "atlas", "build", "--work", work, "--out", out)
    assert code in (0, None) and built == ["male", "female"], err


def test_the_api_refuses_the_folders_before_its_sweep(tmp_path, monkeypatch):
    import walk3d.campaign.atlas as atlas
    import walk3d.campaign.sweep as sweep

    monkeypatch.setattr(sweep, "run_sweep", lambda *a, **k: pytest.fail("the sweep started"))
    work = _prediction_folder(tmp_path / "p")
    with pytest.raises(ValueError, match="--work .* holds files walk3d did not write"):
        atlas.build_atlas("male", "natural", work, "1.2,1.3")
    (tmp_path / "a").write_text("x")
    with pytest.raises(ValueError, match="--out .* is an existing file"):
        atlas.build_atlas("male", "natural", tmp_path / "w", "1.2,1.3", tmp_path / "a")


def test_the_commands_default_speeds_are_the_atlas_builds():
    """The command states the speeds as text (its module must not load CasADi): the same as
    walk3d.campaign.atlas.ATLAS_SPEEDS, which the shipped atlas was built over."""
    import inspect

    from walk3d.campaign.atlas import ATLAS_SPEEDS
    from walk3d.campaign.sweep import parse_speeds
    from walk3d.cli.atlas_command import build

    default = inspect.signature(build).parameters["speeds"].default
    assert default == ATLAS_SPEEDS
    grid = parse_speeds(default)
    assert grid[0] == 0.4 and round(grid[-1], 6) == 2.2 and len(grid) == 19
