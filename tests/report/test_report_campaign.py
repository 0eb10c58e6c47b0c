"""report.html of a campaign folder (made without solving: copies of one result folder)."""

from __future__ import annotations

import re

from report_support import make_campaign

from walk3d.report.campaign_page import campaign_page
from walk3d.report.norms import Norms
from walk3d.report.writer import folder_kind

NO_DATA = Norms(None, {}, (), ())


def test_campaign_page_counts_ranks_and_shows_the_best(result_folder, tmp_path):
    out = make_campaign(tmp_path / "c", result_folder, {0: False, 1: True, 2: True, 3: True,
                                                        4: True, 5: True, 6: False}, 9)  # fmt: skip
    assert folder_kind(out) == "campaign" and folder_kind(result_folder) == "prediction"
    page = campaign_page(out, NO_DATA)
    assert '<td>finished (stored)</td><td class="num">7 of 9</td>' in page
    assert re.search(r"<td>converged</td><td[^>]*>5</td>", page)
    assert re.search(r"<td>converged and look like walking</td><td[^>]*>5</td>", page)
    assert re.search(r"did not converge or raised \(numerics\)</td><td[^>]*>2</td>", page)
    top = re.search(r"The 5 best starts.*?</table>", page, re.S).group(0)
    seeds = re.findall(r"<tr><td class=\"num\">\d</td><td class=\"num\">(\d+)</td>", top)
    assert seeds == ["1", "2", "3", "4", "5"]  # converged first, by criterion value
    assert "Best converged start: seed 1" in page
    assert page.count("<img") == 3 and "<h3>Criteria</h3>" in page  # the prediction's sections
    assert f"walk3d animate {out / 'best'}" in page


def test_a_campaign_without_a_converged_start_says_so(result_folder, tmp_path):
    out = make_campaign(tmp_path / "c", result_folder, {0: False, 1: False}, 2)
    page = campaign_page(out, NO_DATA)
    assert "No start converged" in page and "<img" not in page
    assert re.search(r"<td>converged</td><td[^>]*>0</td>", page)
