"""benchmarks/validation_report.py regenerates docs/validation.md from prediction folders."""

import importlib.util
import re

from validation_support import REPO

from walk3d.results.prediction import save_prediction


def _script():
    path = REPO / "benchmarks" / "validation_report.py"
    spec = importlib.util.spec_from_file_location("validation_report", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_report_from_fake_predictions(synthetic_prediction, falisse, tmp_path):
    tor = save_prediction(synthetic_prediction, tmp_path / "tor")
    en = save_prediction(synthetic_prediction, tmp_path / "en")
    out = tmp_path / "docs" / "validation.md"
    code = _script().main(["--tor", str(tor), "--en", str(en), "--data", str(falisse),
                           "--out", str(out)])  # fmt: skip
    assert code == 0
    text = out.read_text()
    assert "## Table 2" in text and "## Table 3" in text and "| Knee flexion | deg |" in text
    assert "GRF vertical (Fy): " in text and "vs 1.79" in text  # the paper's headline values
    assert "walk3d predict --from-trial" in text and "--height 1.7 --sex female" in text
    links = re.findall(r"\]\((validation/[^)]+\.png)\)", text)
    assert len(links) >= 8
    for link in links:
        assert (out.parent / link).is_file(), link
