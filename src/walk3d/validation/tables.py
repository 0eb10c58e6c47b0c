"""Rich tables of a validation run and of a calibration, for the command line."""

from __future__ import annotations

from rich.table import Table

from walk3d.validation.calibrate import CalibrationResult
from walk3d.validation.run import Validation

__all__ = ["calibration_table", "table2", "table3"]


def _fmt(value, digits: int = 3) -> str:
    return "-" if value is None or value != value else f"{value:.{digits}f}"


def table2(v: Validation, title: str) -> Table:
    """Table 2 of the first prediction: RMSE, r, the reference's mean SD and the status."""
    t = Table(title=title)
    for col in ("quantity", "unit", "RMSE", "r", "ref. SD", "status"):
        t.add_column(col)
    key = "" if "rmse" in v.table2_columns else f"_{v.comparisons[0].prediction_name}"
    for row in v.table2:
        t.add_row(row["label"], row["unit"], _fmt(row[f"rmse{key}"]), _fmt(row[f"r{key}"], 2),
                  _fmt(row["reference_sd"]), row["status"])  # fmt: skip
    return t


def table3(rows: list[dict]) -> Table:
    """Table 3: per source and criterion, the total and the z, x, y shares."""
    t = Table(title="Table 3: criteria and their x/y/z split")
    for col in ("source", "criterion", "total", "z", "x", "y"):
        t.add_column(col)
    for k in range(0, len(rows), 4):
        block = {r["component"]: r for r in rows[k : k + 4]}
        tot = block["total"]
        cells = [f"{block[c]['percent']:.0f}% ({block[c]['value']:.4g})" for c in "zxy"]
        t.add_row(tot["source"], tot["criterion"], f"{tot['value']:.4g}", *cells)
    return t


def calibration_table(result: CalibrationResult, title: str) -> Table:
    """Descriptors, roll-over quality, transition ratios and their RMSE (N/kg, N m/kg)."""
    cal, check = result.calibration, result.transition
    t = Table(title=title)
    t.add_column("quantity")
    t.add_column("value")
    d = cal.descriptors
    t.add_row("descriptors", f"V {d['speed_m_per_s']:.4f} m/s, T {d['period_s']:.4f} s, "
              f"Td {d['double_support_s']:.4f} s ({d['period_method']})")  # fmt: skip
    q = cal.quality["rollover"]
    t.add_row("roll-over", f"{q['stances']} stance(s), theta {q['theta_range_deg'][0]:.0f}.."
              f"{q['theta_range_deg'][1]:.0f} deg, spline RMS {1000 * q['rms_m']:.1f} mm, "
              f"ankle drift at foot flat {1000 * q['flat_drift_m']:.1f} mm")  # fmt: skip
    r = cal.ratios
    t.add_row("transition ratios", f"mu_x {r.mu_x:.3f}, mu_z {r.mu_z:.3f}, "
              f"varpi_x {r.varpi_x:.3f}, varpi_y {r.varpi_y:.3f}")  # fmt: skip
    for label, rmse in (
        ("fitted", check.rmse),
        ("heel-strike ratios", check.rmse_heel_strike_ratios),
    ):
        t.add_row(f"transition RMSE ({label})", ", ".join(f"{k} {v:.3f}" for k, v in rmse.items()))
    return t
