"""report.html of a prediction: its sections, the normative bands, self-containment, the
animation, the manifest, and speed (no browser: tests/report/test_report_browser.py)."""

from __future__ import annotations

import base64
import json
import re
import time

import numpy as np
import pytest
from report_support import DATA, make_prediction, needs_data

from walk3d.plots.cycles import Panel, cycle_figure, nice_ticks
from walk3d.report.norms import Norms, _band, find_data, load_norms
from walk3d.report.prediction_page import prediction_page
from walk3d.report.writer import write_report
from walk3d.results.prediction import check_complete, load_result
from walk3d.validation.reference import Reference

NO_DATA = Norms(None, {}, (), ("no measured data folder found",))


def external_references(page: str) -> list[str]:
    """Every way a page could fetch something: src/href not a data URI, CSS url(), @import,
    <link>, <script src>."""
    hits = re.findall(r'(?:src|href)="(?!data:|#)([^"]*)"', page)
    hits += re.findall(r"url\((?!data:)", page) + re.findall(r"@import|<link\b|<script\b", page)
    return hits


def images(page: str) -> list[bytes]:
    return [base64.b64decode(m) for m in re.findall(r'<img[^>]*src="data:[^;]+;base64,([^"]+)"',
                                                     page)]  # fmt: skip


def test_the_page_has_inputs_convergence_criteria_and_three_figures(result_folder):
    pred = load_result(result_folder)
    page = prediction_page(pred, result_folder, NO_DATA)
    for text in ("Inputs", "1.3000 m/s", "68.8 kg, 1.77 m, male", "(given)", "Convergence",
                 "Solve_Succeeded", "1.00e-09", "Criteria", "C_tor", "C_weighted", "preset natural",
                 f"walk3d animate {result_folder}"):  # fmt: skip
        assert text in page, text
    assert "NOT CONVERGED" not in page
    figures = images(page)
    assert len(figures) == 3 and all(f.startswith(b"<svg") for f in figures)
    assert "Joint angles" in figures[0].decode() and "Ground reaction" in figures[2].decode()
    # the C_tor row: total and its x/y/z split as summary.json has them
    c = pred.summary["objective"]["C_tor"]
    row = re.search(r"<tr><td>C_tor</td>(.*?)</tr>", page).group(1)
    assert [f"{c[k]:.4g}" for k in ("total", "x", "y", "z")] == re.findall(r">([^<]+)</td>",
                                                                          row)[:4]  # fmt: skip


def test_without_measured_data_the_page_says_so_and_shows_the_prediction(result_folder):
    page = prediction_page(load_result(result_folder), result_folder, NO_DATA)
    assert "No measured normative data found" in page
    svg = images(page)[1].decode()
    assert "no measurement" in svg and "#d62728" in svg and "<polygon" not in svg


@needs_data
def test_bands_come_from_the_falisse_table_mean_plus_minus_sd(result_folder):
    from walk3d.io.cycle_table import read_cycle_table

    norms = load_norms(find_data(DATA))
    assert norms.folder == DATA and len(norms.sources) == 2
    table = read_cycle_table(DATA / "falisse2019" / "cycle_right_leg_mean_sd.csv")
    mean, sd = table.column("knee_angle_deg")
    band = norms.bands["angle:knee_flexion"]
    # knee_angle is negative in flexion in the table: the band is of flexion, positive
    assert np.allclose(band.mean, -mean) and np.allclose(band.high - band.low, 2 * sd)
    assert band.kind == "mean ± SD (Falisse et al. 2019)" and band.others[0][0] == "Winter"
    assert "angle:neck_flexion" not in norms.bands  # measured nowhere
    page = prediction_page(load_result(result_folder), result_folder, norms)
    assert "No measured normative data" not in page and "Falisse et al. 2019" in page
    svg = images(page)[0].decode()
    assert svg.count("<polygon") == 16  # 17 angles, the neck unmeasured


def test_band_rules_sd_first_else_min_max_of_means():
    p = np.linspace(0, 100, 101)
    one, two = np.ones(101), 2 * np.ones(101)
    nan = np.full(101, np.nan)
    a = Reference("a", p, {"k": one}, {"k": nan})
    b = Reference("b", p, {"k": two}, {"k": 0.5 * one})
    band = _band("k", [("a, no SD", a), ("b, SD", b)])
    assert np.allclose(band.low, 1.5) and np.allclose(band.high, 2.5) and band.kind.endswith("(b)")
    assert band.others[0][0] == "a"
    c = Reference("c", p, {"k": 3 * one}, {"k": nan})
    band = _band("k", [("a", a), ("c", c)])
    assert np.allclose(band.low, 1) and np.allclose(band.high, 3) and band.mean is None
    assert _band("other", [("a", a)]) is None


def test_a_non_converged_solve_is_labelled_clearly(evaluated, tmp_path):
    from walk3d.results.prediction import save_prediction

    settings, body, ev = evaluated
    folder = save_prediction(make_prediction(settings, ev, converged=False), tmp_path / "p",
                             body=body)  # fmt: skip
    page = prediction_page(load_result(folder), folder, NO_DATA)
    assert re.search(r'class="banner bad">NOT CONVERGED \(Maximum_Iterations_Exceeded\)', page)


@pytest.mark.parametrize(("value", "banner"), [("no", "bad"), (True, "ok"), (None, "bad")])
def test_only_a_recorded_true_is_converged_on_the_page(value, banner):
    """``"converged": "no"`` was bannered "Convergence not recorded"; True is the control."""
    from walk3d.report.prediction_page import status_banners

    first = status_banners({"converged": value, "status": "S"})[0]
    assert f'class="banner {banner}"' in first
    assert ("NOT CONVERGED" in first) == (banner == "bad")
    assert "not recorded" in status_banners({})[0]  # no solve recorded: not called failed


def test_the_page_is_self_contained_and_the_check_finds_external_links(result_folder):
    page = prediction_page(load_result(result_folder), result_folder, NO_DATA)
    assert external_references(page) == []
    # negative control: each kind of external reference is found
    for bad in (
        '<img src="https://cdn.example/x.png">',
        '<script src="a.js"></script>',
        '<link rel="stylesheet" href="s.css">',
        "<style>b{background:url(x.png)}</style>",
    ):
        assert external_references(page.replace("</body>", bad + "</body>")), bad


def test_the_animation_is_embedded_when_present(fresh_folder):
    video = b"\x00\x00\x00\x18ftypmp42 not really a video"
    (fresh_folder / "animation.mp4").write_bytes(video)
    page = prediction_page(load_result(fresh_folder), fresh_folder, NO_DATA)
    m = re.search(r'<video [^>]*src="data:video/mp4;base64,([^"]+)"', page)
    assert m and base64.b64decode(m.group(1)) == video
    assert "walk3d animate" not in page


def test_write_report_lists_the_page_in_the_manifest_and_is_fast(fresh_folder, tmp_path):
    t0 = time.perf_counter()
    kind, path = write_report(fresh_folder, data=DATA if DATA.is_dir() else None)
    elapsed = time.perf_counter() - t0
    assert kind == "prediction" and path == fresh_folder / "report.html"
    manifest = json.loads((fresh_folder / "manifest.json").read_text())
    assert manifest["files"]["report.html"] == path.stat().st_size
    check_complete(fresh_folder)
    assert elapsed < 3.0, f"report took {elapsed:.2f} s"
    # elsewhere: the manifest is left alone
    kind, other = write_report(fresh_folder, out=tmp_path / "r.html")
    assert other.is_file() and json.loads((fresh_folder / "manifest.json").read_text()) == manifest
    assert not [p for p in fresh_folder.iterdir() if p.name.startswith(".")]  # no temporary


@pytest.mark.parametrize("lo,hi", [(-3.2, 17.9), (0.0, 0.013), (5.0, 5.0), (-120, -95)])
def test_ticks_are_round_and_cover_the_range(lo, hi):
    ticks, decimals = nice_ticks(lo, hi)
    assert ticks[0] <= lo and ticks[-1] >= hi - 1e-12 and 2 <= ticks.size <= 7
    assert len({f"{t:.{decimals}f}" for t in ticks}) == ticks.size  # labels tell ticks apart


def test_a_figure_breaks_its_lines_at_missing_values():
    p = np.linspace(0, 100, 101)
    y = np.sin(p / 10)
    y[40:45] = np.nan
    svg = cycle_figure(p, [Panel("q", "deg", y)], "t")
    path = re.search(r'<path d="([^"]+)" fill="none" stroke="#d62728"', svg).group(1)
    assert path.count("M") == 2 and "nan" not in svg
    with pytest.raises(ValueError):
        cycle_figure(p, [], "t")


def test_the_left_and_right_section_shows_the_asymmetry_or_says_it_is_missing():
    from walk3d.report.prediction_page import _sides

    entry = {"right": 0.5744, "left": 1.6704, "difference": -1.096}
    summary = {"asymmetry": {"peak_ankle_plantarflexor_moment_nm_per_kg": entry,
                             "step_length_m": {"right": 0.7459, "left": 0.7452,
                                               "difference": 0.0007}},
               "problem": "full cycle"}  # fmt: skip
    html = _sides(summary)
    row = re.search(r"<tr><td>peak ankle plantarflexor moment</td>(.*?)</tr>", html).group(1)
    assert re.findall(r">([^<]+)</td>", row) == ["N m/kg", "0.57", "1.67", "-1.10"]
    assert "<td>step length</td><td>m</td>" in html and "full cycle" in html
    # negative control: a standing fallback has no steps, and the section says so
    assert "<table" not in _sides({"asymmetry": None}) and "without steps" in _sides({})
