"""An --out with ``..`` after a symbolic link: ``L/../cmp`` with L a link to p1b/mine lies in
the result p1b (the file system follows L, then ``..``), so it is refused in one line naming
p1b; textually normalised, it passed the check and was written among p1b's files."""

import os

import pytest
from helpers import cli, one_line_error
from result_support import bare_result_folder
from test_cli_out_in_results import LATE, _args, complete  # noqa: F401

from walk3d.outputs import check_output_file


@pytest.mark.parametrize("case", ["compare", "sweep", "validate"])
def test_dotdot_after_a_link_into_a_result_is_refused(tmp_path, capsys, complete, case):  # noqa: F811
    result = bare_result_folder(tmp_path / "p1b")
    (result / "mine").mkdir()
    os.symlink(result / "mine", tmp_path / "L")
    before = sorted(p.name for p in result.iterdir())
    out = f"{tmp_path}/L/../cmp"
    one_line_error(cli(capsys, *_args(case, tmp_path, out, complete, late=False)),
                   f"--out {out} is inside the walk3d result folder {result}")  # fmt: skip
    assert sorted(p.name for p in result.iterdir()) == before
    with pytest.raises(ValueError, match=f"inside the walk3d result folder {result}"):
        check_output_file(f"{tmp_path}/L/../cal2.json", suffix=".json")


def test_dotdot_after_a_link_out_of_a_result_passes(tmp_path, capsys, complete):  # noqa: F811
    """Negative control: a link in p1 to a free folder; ``p1/L/../x`` is the free folder's
    sibling, not p1's, so the command reaches its later check."""
    result = bare_result_folder(tmp_path / "p1")
    (tmp_path / "free" / "mine").mkdir(parents=True)
    os.symlink(tmp_path / "free" / "mine", result / "L")
    out = f"{result}/L/../x"
    got = cli(capsys, *_args("compare", tmp_path, out, complete, late=True))
    one_line_error(got, LATE["compare"][2])
    assert "inside the walk3d result folder" not in got[2]
    check_output_file(f"{result}/L/../cal2.json", suffix=".json")
