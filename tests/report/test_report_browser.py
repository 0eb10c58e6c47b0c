"""report.html in a real browser: headless Chromium renders it, the screenshot is not blank and
shows the figures, and every figure decodes (naturalWidth > 0). Negative controls: a blank
page fails the first check, a page with corrupted image data the second."""

from __future__ import annotations

import re
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import pytest
from report_support import DATA

from walk3d.report.writer import write_report

CHROMIUM = next((p for p in map(shutil.which, ("chromium", "chromium-browser")) if p), None)
pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(
        CHROMIUM is None, reason="headless Chromium not found (Debian: apt-get install chromium)"
    ),
]
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--virtual-time-budget=10000")  # fmt: skip
PROBE = (
    "<script>window.addEventListener('load', () => { const all = [...document.images]; "
    "const ok = all.filter(i => i.complete && i.naturalWidth > 0).length; "
    "document.body.insertAdjacentHTML('beforeend', "
    '`<p id="probe">images=${all.length} loaded=${ok}</p>`); });</script>'
)
PREDICTION_RED = np.array([214, 39, 40])  # walk3d.plots.cycles: the predicted curves


def _chromium(*args: str) -> subprocess.CompletedProcess:
    with tempfile.TemporaryDirectory(prefix="walk3d-chromium-") as profile:
        cmd = [CHROMIUM, *FLAGS, f"--user-data-dir={profile}", *args]
        return subprocess.run(cmd, capture_output=True, text=True, timeout=120)


def screenshot(page: Path, png: Path) -> np.ndarray:
    """RGB pixels of a 1200 x 3000 screenshot of ``page``."""
    from PIL import Image

    r = _chromium(f"--screenshot={png}", "--window-size=1200,3000", page.as_uri())
    assert png.is_file(), r.stderr[-2000:]
    return np.asarray(Image.open(png).convert("RGB"))


def images_loaded(page: Path) -> tuple[int, int]:
    """``(images, decoded images)`` of ``page`` once loaded, read from the DOM Chromium dumps
    after a probe script (added to a copy) has written them into it."""
    probed = page.with_name(page.stem + "_probe.html")
    probed.write_text(page.read_text(encoding="utf-8").replace("</body>", PROBE + "</body>"),
                      encoding="utf-8")  # fmt: skip
    r = _chromium("--dump-dom", probed.as_uri())
    m = re.search(r'id="probe">images=(\d+) loaded=(\d+)<', r.stdout)
    assert m, f"no probe in the dumped DOM: {r.stdout[-500:]} {r.stderr[-1000:]}"
    return int(m.group(1)), int(m.group(2))


def not_blank(pixels: np.ndarray) -> bool:
    """More than 3 % of the pixels not white, and more than 100 distinct colours."""
    non_white = np.any(pixels < 245, axis=-1).mean()
    colours = np.unique(pixels.reshape(-1, 3)[::7], axis=0).shape[0]
    return bool(non_white > 0.03 and colours > 100)


def shows_curves(pixels: np.ndarray) -> bool:
    """At least 2000 pixels of the predicted curves' red."""
    near = np.abs(pixels.astype(int) - PREDICTION_RED).max(axis=-1) < 40
    return bool(near.sum() > 2000)


@pytest.fixture(scope="module")
def page(result_folder, tmp_path_factory):
    folder = tmp_path_factory.mktemp("browser") / "v_1.300"
    shutil.copytree(result_folder, folder)
    _, path = write_report(folder, data=DATA if DATA.is_dir() else None)
    return path


def test_the_page_renders_with_its_figures(page, tmp_path):
    pixels = screenshot(page, tmp_path / "shot.png")
    assert pixels.shape == (3000, 1200, 3)
    assert not_blank(pixels)
    assert shows_curves(pixels)
    assert images_loaded(page) == (3, 3)


def test_a_blank_page_fails_the_non_blank_check(tmp_path):
    blank = tmp_path / "blank.html"
    blank.write_text("<!DOCTYPE html><html><body></body></html>\n", encoding="utf-8")
    pixels = screenshot(blank, tmp_path / "blank.png")
    assert not not_blank(pixels) and not shows_curves(pixels)


def test_corrupted_image_data_fails_the_figures_check(page, tmp_path):
    broken = tmp_path / "broken.html"
    text = re.sub(r'(<img [^>]*src="data:[^;]+;base64,)[^"]+"', r'\1bm90IGFuIGltYWdl"',
                  page.read_text(encoding="utf-8"))  # fmt: skip
    broken.write_text(text, encoding="utf-8")
    images, loaded = images_loaded(broken)
    assert images == 3 and loaded == 0
    assert not shows_curves(screenshot(broken, tmp_path / "broken.png"))
