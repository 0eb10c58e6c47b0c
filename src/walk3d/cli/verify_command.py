"""``walk3d verify DIR``: replay a prediction in OpenSim and compare its inverse dynamics."""

from __future__ import annotations

from typing import Annotated

import typer
from rich.table import Table

from walk3d.cli.common import app, console, fail


def _moment_table(title: str, comparison, bars) -> Table:
    t = Table(title=title)
    for col in ("coordinate", "r", "RMSE N m", "RMSE % of peak", "peak N m", "bar"):
        t.add_column(col)
    for row in comparison.moments:
        t.add_row(row.coordinate, f"{row.r:.4f}", f"{row.rmse:.3f}", f"{row.rmse_pct_peak:.2f}",
                  f"{row.peak:.1f}", "pass" if row.passes(bars) else "FAIL")  # fmt: skip
    return t


def _residual_table(whole, smooth, bars) -> Table:
    t = Table(title="pelvis residual forces (OpenSim), % body weight")
    for col in ("force", "peak", "RMS", "peak away from touch-downs and ends", "bar"):
        t.add_column(col)
    for row, away in zip(whole.residuals, smooth.residuals, strict=True):
        t.add_row(row.column, f"{row.peak_pct_bw:.2f}", f"{row.rms_pct_bw:.2f}",
                  f"{away.peak_pct_bw:.2f}", "pass" if row.passes(bars) else "FAIL")  # fmt: skip
    return t


@app.command(short_help="Check a result with OpenSim's inverse dynamics.")
def verify(
    pred_dir: Annotated[str, typer.Argument(help="Prediction folder (walk3d predict --out).")],
    timeout: Annotated[
        float, typer.Option("--timeout", help="Seconds OpenSim may take.", min=1.0)
    ] = 300.0,
) -> None:
    """Run OpenSim's InverseDynamicsTool on DIR's model.osim + motion.mot + grf.xml, compare
    with inverse_dynamics.sto (hip, knee and ankle flexion moments: r and RMSE as % of peak;
    pelvis residual forces as % of body weight) and measure the stance foot's drift during
    foot-flat on model.osim. Exit code 0 within issue 26's bars (r >= 0.99, RMSE <= 2 % of
    peak, residual forces <= 2 % of body weight at every sample, drift < 5 mm), 1 outside
    them, 2 for bad input or without OpenSim (pip install 'walk3d\\[opensim]')."""
    import subprocess

    from walk3d.io.errors import DataFileError
    from walk3d.verify.compare import BARS
    from walk3d.verify.run import OpenSimMissing, check_timeout, verify_folder

    try:
        check_timeout(timeout)
    except ValueError:
        fail(f"--timeout must be a finite number of seconds up to 86400 (a day), got {timeout}")
    try:
        with console.status("walk3d: running OpenSim"):
            v = verify_folder(pred_dir, timeout=timeout)
    except OpenSimMissing as exc:
        fail(str(exc))
    except (OSError, DataFileError, ValueError, KeyError, RuntimeError) as exc:
        fail(f"cannot verify {pred_dir}: {' '.join(str(exc).split())}")
    except subprocess.TimeoutExpired:
        fail(f"cannot verify {pred_dir}: OpenSim took more than {timeout:g} s")
    console.print(_moment_table(f"flexion moments, OpenSim vs walk3d ({v.whole.n_samples} "
                                "samples, the whole cycle)", v.whole, BARS))  # fmt: skip
    console.print(_residual_table(v.whole, v.smooth, BARS))
    away = ", ".join(f"{r.coordinate} r {r.r:.4f} RMSE {r.rmse_pct_peak:.2f} %"
                     for r in v.smooth.moments)  # fmt: skip
    console.print(f"away from touch-downs and ends ({v.smooth.n_samples} samples): {away}",
                  markup=False)  # fmt: skip
    for side, d in v.drift_m.items():
        mark = "pass" if d < BARS.drift_max_m else "FAIL"
        console.print(f"{side} stance foot during foot-flat: moves {1000 * d:.2f} mm on "
                      f"model.osim ({1000 * v.walk3d_drift_m[side]:.2f} mm in walk3d) {mark}",
                      markup=False)  # fmt: skip
    for note in v.notes:
        console.print(f"note: {note}", markup=False)
    ok = v.passes(BARS)
    console.print("within the bars" if ok else "OUTSIDE the bars", markup=False)
    raise typer.Exit(0 if ok else 1)
