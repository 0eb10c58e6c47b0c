"""Rich table of a calibration, for the command line."""

from __future__ import annotations

from rich.table import Table

from walk3d.calibration.calibrate import CalibrationResult

__all__ = ["calibration_table"]


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
