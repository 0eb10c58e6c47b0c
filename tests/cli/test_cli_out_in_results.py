"""Every command that writes a folder refuses an --out inside a walk3d result folder, in one line
and exit code 2, before any solve: ``sweep --out p1/sub`` wrote a sweep among p1's files, after
which ``predict --out p1`` was refused. The negative controls put --out beside the result and
reach a later check (a bad option given on purpose), so that nothing is solved either way."""

import pytest
from helpers import cli, one_line_error
from result_support import bare_result_folder, result_folder

LATE = {
    "predict": (["predict", "--out", "{o}"], ["--sex", "x"], "sex"),
    "sweep": (["sweep", "--speeds", "1.3", "--out", "{o}"], ["--sex", "x"], "sex"),
    "campaign": (["campaign", "--starts", "1", "--out", "{o}"], ["--sex", "x"], "sex"),
    "compare": (["compare", "{t}/a", "{t}/b", "--out", "{o}"], [], "cannot read"),
    "track": (["track", "--table", "{t}/t.csv", "--out", "{o}"], ["--relax", "x=1"], "--relax"),
    "fit-criterion": (["fit-criterion", "{t}/trials.toml", "--parameter", "accel", "--out",
                       "{o}"], ["--scheduler", "tcp://127.0.0.1:1"], "no Dask scheduler"),
    "validate": (["validate", "{p}", "--reference", "{t}/none.csv", "--out", "{o}"], [],
                 "none.csv"),
}  # fmt: skip
"""Each command: its arguments (``{o}`` the --out, ``{t}`` the test's folder, ``{p}`` a
complete result folder), an option that fails after the --out check, and its error's word."""


@pytest.fixture(scope="module")
def complete(tmp_path_factory):
    return result_folder(tmp_path_factory.mktemp("out_in_results") / "pred")


def _args(case: str, tmp_path, out, complete, late: bool) -> list[str]:
    trials = tmp_path / "trials.toml"
    trials.write_text('[[trial]]\nname = "t"\nspeed = 1.2\nperiod = 1.1\ndouble_support = 0.12\n'
                      'reference = ["t.csv"]\n')  # fmt: skip
    (tmp_path / "t.csv").write_text("x\n")
    args, later, _ = LATE[case]
    given = [a.format(o=out, t=tmp_path, p=complete) for a in args]
    return given + (later if late else [])


@pytest.mark.parametrize("case", LATE)
def test_an_out_inside_a_result_folder_is_refused_before_any_work(tmp_path, capsys, complete,
                                                                  case):  # fmt: skip
    result = bare_result_folder(tmp_path / "p1")
    before = sorted(p.name for p in result.iterdir())
    out = result / "sub"
    one_line_error(cli(capsys, *_args(case, tmp_path, out, complete, late=False)),
                   f"--out {out} is inside the walk3d result folder {result}")  # fmt: skip
    assert sorted(p.name for p in result.iterdir()) == before


@pytest.mark.parametrize("case", LATE)
def test_an_out_beside_a_result_folder_passes_the_check(tmp_path, capsys, complete, case):
    """Negative control: the same command with --out beside the result reaches its later
    check (the bad option given on purpose), not the result folder's refusal."""
    bare_result_folder(tmp_path / "p1")
    result = cli(capsys, *_args(case, tmp_path, tmp_path / "p1-sub", complete, late=True))
    one_line_error(result, LATE[case][2])
    assert "inside the walk3d result folder" not in result[2]


def test_validate_refuses_another_results_validation_folder(tmp_path, capsys, complete):
    """validate P --out Q/validation put P's validation in Q (its default place is
    P/validation, which stays accepted: the control reaches the reference)."""
    other = bare_result_folder(tmp_path / "q")
    args = ["validate", complete, "--reference", tmp_path / "none.csv", "--out"]
    one_line_error(cli(capsys, *args, other / "validation"), "inside the walk3d result folder")
    one_line_error(cli(capsys, *args, complete / "validation"), "none.csv")


def test_validate_names_out_for_another_folder_in_its_result(tmp_path, capsys, complete):
    """validate P --out P/other was refused naming the API's out_dir; it names --out, before
    the reference is read (control: P/validation, above, reaches the reference)."""
    args = ["validate", complete, "--reference", tmp_path / "none.csv", "--out"]
    one_line_error(
        cli(capsys, *args, complete / "other"),
        f"--out {complete / 'other'} is inside the walk3d result folder {complete}",
    )
    assert not (complete / "other").exists()


def test_animate_refuses_a_video_inside_another_result_folder(tmp_path, capsys):
    """animate A --out B/animation.mp4 would have put A's walk among B's files; the control
    (--out beside them) passes the check and reaches the reading of A."""
    walked, other = bare_result_folder(tmp_path / "a"), bare_result_folder(tmp_path / "b")
    one_line_error(
        cli(capsys, "animate", walked, "--out", other / "animation.mp4"),
        f"--out {other / 'animation.mp4'} is inside the walk3d result folder",
    )
    one_line_error(cli(capsys, "animate", walked, "--out", tmp_path / "a.mp4"), "cannot animate")
