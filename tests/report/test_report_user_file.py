"""``walk3d report DIR --out FILE``: an existing FILE is replaced only if it is a page walk3d
wrote (its generator meta tag, or a view its folder's manifest lists), never a user's file."""

from __future__ import annotations

from helpers import cli, one_line_error

from walk3d.report.html import GENERATOR, is_walk3d_page, page


def test_a_users_page_is_refused_and_walk3d_pages_are_replaced(fresh_folder, tmp_path, capsys):
    mine = tmp_path / "mine.html"
    mine.write_text("<html><body>my notes</body></html>\n")
    refused = cli(capsys, "report", fresh_folder, "--out", mine)
    one_line_error(refused, f"--out {mine} exists and is not a walk3d report")
    assert "my notes" in mine.read_text()
    ours = tmp_path / "ours.html"  # control: a page walk3d wrote is replaced, twice
    for _ in range(2):
        code, _, err = cli(capsys, "report", fresh_folder, "--out", ours)
        assert code == 0, err
    assert is_walk3d_page(ours)
    for _ in range(2):  # and the folder's own page
        code, _, err = cli(capsys, "report", fresh_folder, "--out", fresh_folder / "report.html")
        assert code == 0, err


def test_the_marker_is_in_the_head():
    assert GENERATOR in page("t").split("</head>")[0]
