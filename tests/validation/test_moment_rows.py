"""Sagittal moment rows of Table 2 (issue #41): present, OpenSim's signs per kg of body mass,
and aligned as the shared yardstick ``../shared/tools/realism.py`` aligns when given its heel
strike. No solve: the shipped atlas solution saved as a result folder."""

from __future__ import annotations

import csv
import importlib
import importlib.util
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from validation_support import REPO

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "verify"))
from verify_support import atlas_prediction  # noqa: E402

from walk3d.io.storage import read_storage  # noqa: E402
from walk3d.results.prediction import PredictedCycle, load_result, save_prediction  # noqa: E402
from walk3d.validation.run import validate  # noqa: E402

SAGITTAL = {"hip_flexion": "hip_flexion", "knee_flexion": "knee_angle",
            "ankle_dorsiflexion": "ankle_angle"}  # fmt: skip
"""walk3d quantity -> OpenSim coordinate (right side without ``_r``)."""
YARDSTICK = REPO.parent / "shared" / "tools" / "realism.py"
compare_module = importlib.import_module("walk3d.validation.compare")


@pytest.fixture(scope="module")
def folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The atlas solution as a result folder (``inverse_dynamics.sto``, ``motion.mot``...)."""
    pred, body = atlas_prediction()
    return save_prediction(pred, tmp_path_factory.mktemp("moments") / "atlas", body=body)


def _cycle(pred: PredictedCycle, time: np.ndarray, values: np.ndarray, t_hs: float) -> np.ndarray:
    """``values`` on 0–100 % from a right heel strike at ``t_hs`` (periodic, 101 samples)."""
    period = compare_module.cycle_timing(pred)[0]
    t = time - time[0]
    keep = t < period * (1 - 1e-9)
    query = np.mod(t_hs + np.linspace(0.0, 1.0, 101) * period, period)
    return np.interp(query, t[keep], values[keep], period=period)


def _own_table(folder: Path, path: Path, knee: float, sign: float, per_kg: bool) -> Path:
    """A cycle table of the folder's own ``inverse_dynamics.sto`` columns and knee angle;
    ``knee=-1`` writes gait2392's convention (knee angle and moment negative in flexion),
    ``sign=-1`` flips every moment (the negative control)."""
    pred = load_result(folder)
    t_hs = compare_module.cycle_timing(pred)[1]
    ids, mot = read_storage(folder / "inverse_dynamics.sto"), read_storage(folder / "motion.mot")
    assert mot.in_degrees
    cols = {"knee_angle_deg": knee * _cycle(pred, mot.time, mot.column("knee_angle_r"), t_hs)}
    unit, scale = ("Nm_per_kg", 1.0 / pred.body_mass) if per_kg else ("Nm", 1.0)
    for coordinate in SAGITTAL.values():
        k = knee if coordinate == "knee_angle" else 1.0
        values = _cycle(pred, ids.time, ids.column(f"{coordinate}_r_moment"), t_hs)
        cols[f"{coordinate}_moment_{unit}"] = sign * k * scale * values
    with path.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["percent_cycle", *(f"{c}_mean" for c in cols)])
        for i, p in enumerate(np.linspace(0.0, 100.0, 101)):
            w.writerow([p, *(repr(float(v[i])) for v in cols.values())])
    return path


def test_table2_csv_has_the_sagittal_moments_in_n_m_per_kg(folder, falisse, tmp_path):
    v = validate({"prediction": load_result(folder)}, [falisse / "cycle_right_leg_mean_sd.csv"],
                 tmp_path / "v", figures=False)  # fmt: skip
    with (tmp_path / "v" / "table2.csv").open() as f:
        rows = {r["quantity"]: r for r in csv.DictReader(f) if r["group"] == "moment"}
    for name in SAGITTAL:
        row = rows[name]
        assert (row["unit"], row["status"]) == ("N m/kg", "ok"), row
        assert -1.0 <= float(row["r"]) <= 1.0 and 0.0 < float(row["rmse"]) < 2.0, row
        assert float(row["r"]) == pytest.approx(v.comparisons[0].row(f"moment:{name}").r, 1e-5)


@pytest.mark.parametrize(("knee", "per_kg"), [(1.0, True), (-1.0, True), (-1.0, False)])
def test_own_inverse_dynamics_as_reference_gives_r_one(folder, tmp_path, knee, per_kg):
    """walk3d's own ``<coordinate>_r_moment`` columns, in either knee convention and in N m or
    N m/kg, are the prediction's moments exactly: r = 1, RMSE 0."""
    table = _own_table(folder, tmp_path / "own.csv", knee, 1.0, per_kg)
    rows = validate({"p": load_result(folder)}, [table], figures=False).comparisons[0]
    for name in SAGITTAL:
        row = rows.row(f"moment:{name}")
        assert row.r == pytest.approx(1.0, abs=1e-9) and row.rmse < 1e-9, (name, row)


def test_sign_flipped_reference_gives_r_minus_one(folder, tmp_path):
    table = _own_table(folder, tmp_path / "flipped.csv", -1.0, -1.0, True)
    rows = validate({"p": load_result(folder)}, [table], figures=False).comparisons[0]
    for name in SAGITTAL:
        row = rows.row(f"moment:{name}")
        assert row.r == pytest.approx(-1.0, abs=1e-9) and row.rmse > 0.1, (name, row)


@pytest.mark.skipif(not YARDSTICK.is_file(), reason=f"shared yardstick not found at {YARDSTICK}")
def test_validate_agrees_with_the_yardstick_at_its_heel_strike(folder, falisse, monkeypatch):
    """realism.py's GRF and angle rows are validate's once both start the cycle at realism.py's
    heel strike (at most one sample after validate's, docs/criteria.md); realism.py has no
    moment rows, so its own resampling and knee sign applied to ``inverse_dynamics.sto`` must
    give validate's moment rows."""
    ref = falisse / "cycle_right_leg_mean_sd.csv"
    run = subprocess.run([sys.executable, str(YARDSTICK), str(folder), str(ref), "--json"],
                         capture_output=True, text=True, check=True)  # fmt: skip
    figures = json.loads(run.stdout.strip().splitlines()[-1])
    pred = load_result(folder)
    period, t_hs = compare_module.cycle_timing(pred)
    fy = pred.grf_force[:, 0, 1] / pred.body_mass
    on = np.flatnonzero((fy[1:] > 0.02 * 9.81) & (fy[:-1] <= 0.02 * 9.81))[0] + 1
    t0 = float(pred.time[on] - pred.time[0])
    assert 0.0 <= t0 - t_hs <= period / 100 + 1e-9  # the yardstick's sample-grid heel strike
    monkeypatch.setattr(compare_module, "cycle_timing", lambda p: (period, t0))
    rows = validate({"p": pred}, [ref], figures=False).comparisons[0]
    pairs = {"grf_vertical": "grf:grf_vertical", "grf_fore_aft": "grf:grf_fore_aft",
             "knee_flexion": "angle:knee_flexion", "hip_flexion": "angle:hip_flexion",
             "ankle_dorsiflexion": "angle:ankle_dorsiflexion"}  # fmt: skip
    for key, quantity in pairs.items():
        row = rows.row(quantity)
        assert abs(row.rmse - figures[key]) < 6e-4 and abs(row.r - figures[f"{key}_r"]) < 6e-4

    monkeypatch.syspath_prepend(str(YARDSTICK.parent))
    yardstick = importlib.import_module("realism")
    ids = read_storage(folder / "inverse_dynamics.sto")
    measured = np.genfromtxt(ref, delimiter=",", names=True)
    t = np.asarray(pred.time, float)
    for name, coordinate in SAGITTAL.items():
        sign = yardstick.ANGLES[name][3] if name in yardstick.ANGLES else 1  # the knee's -1
        p = yardstick.periodic_resample(
            ids.time, ids.column(f"{coordinate}_r_moment"), t[on], period
        ) / float(np.sum(pred.segment_mass))
        m = sign * np.asarray(measured[f"{coordinate}_moment_Nm_per_kg_mean"], float)
        row = rows.row(f"moment:{name}")
        assert row.rmse == pytest.approx(np.sqrt(np.mean((p - m) ** 2)), abs=1e-6), name
        assert row.r == pytest.approx(np.corrcoef(p, m)[0, 1], abs=1e-6), name


def test_realism_benchmark_reports_the_moments_per_source(folder, falisse, tmp_path):
    spec = importlib.util.spec_from_file_location("realism_benchmark",
                                                  REPO / "benchmarks" / "realism.py")  # fmt: skip
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    sources = bench.moment_sources(falisse.parent)
    assert all(f.is_file() for f in sources["falisse_mean"] + sources["falisse_gait_1"])
    got = bench.moment_rows(folder, {"falisse_mean": sources["falisse_mean"],
                                     "absent": [tmp_path / "no.csv"]})  # fmt: skip
    assert set(got) == {"falisse_mean"} and set(got["falisse_mean"]) == set(SAGITTAL)
    rows = validate({"p": load_result(folder)}, sources["falisse_mean"], figures=False)
    for name, row in got["falisse_mean"].items():
        assert row == {"r": rows.comparisons[0].row(f"moment:{name}").r,
                       "rmse": rows.comparisons[0].row(f"moment:{name}").rmse}  # fmt: skip
