"""The runnable examples in examples/ run as a user runs them (solve-marked: each predicts)."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


@pytest.mark.solve
def test_custom_term_example_solves_and_reports_its_term(tmp_path):
    out = tmp_path / "custom"
    env = {**os.environ, "WALK3D_COMPILE_LATER": "0"}
    proc = subprocess.run([sys.executable, str(EXAMPLES / "custom_term.py"), str(out)], env=env,
                          capture_output=True, text=True, timeout=600, check=False)  # fmt: skip
    assert proc.returncode == 0, proc.stdout[-1500:] + proc.stderr[-1500:]
    assert "C_trunk" in proc.stdout
    summary = json.loads((out / "summary.json").read_text())
    assert summary["converged"]
    assert summary["objective"]["C_weighted"]["parts"]["trunk"] > 0
    assert "C_trunk" in (out / "report.html").read_text()
    # negative control: the same criterion without the registration is refused
    refused = subprocess.run([sys.executable, "-m", "walk3d.cli", "predict", "--criterion",
                              "natural,trunk=1", "--out", str(tmp_path / "no")], env=env,
                             capture_output=True, text=True, timeout=120, check=False)  # fmt: skip
    assert refused.returncode == 2 and "unknown criterion term 'trunk'" in refused.stderr
