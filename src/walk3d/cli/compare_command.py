"""``walk3d compare DIR_A DIR_B [--out DIR]``: what changed between two predictions."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.table import Table

from walk3d.cli.common import EXIT_WRITE, app, check_output_folder, console, fail

_SHOWN = ("hip_flexion_r", "hip_flexion_l", "knee_flexion_r", "knee_flexion_l",
          "ankle_dorsiflexion_r", "ankle_dorsiflexion_l")  # fmt: skip
"""The DoFs printed (the CSV holds all 24)."""
_WRITES = ("compare.csv", "compare.png", "report.html")
"""What ``--out`` writes: an earlier comparison's folder holding anything else is refused."""


@app.command(short_help="Compare two results: criteria, angles and moments.")
def compare(
    dir_a: Annotated[str, typer.Argument(help="First prediction folder (A).")],
    dir_b: Annotated[str, typer.Argument(help="Second prediction folder (B).")],
    out: Annotated[
        str | None,
        typer.Option(
            "--out",
            help="Also write DIR/compare.csv (every DoF), compare.png and "
            "report.html (both in one page).",
        ),
    ] = None,
) -> None:
    """Print what changed from A to B: the criteria, the body mass, and the sagittal hip, knee
    and ankle angles (deg) and moments (N·m/kg), both sides: each one's range over the cycle
    and the RMS and largest change, sample by sample. With --out, the table of every DoF's
    angle and moment as compare.csv, a figure of both over the cycle as compare.png, and both
    in report.html. A result that did not converge or does not walk is named in a warning line
    and marked in report.html. Exit code 2 for a folder that is not a result or two results
    that do not compare, 3 if --out cannot be written."""
    from walk3d.cli.labels import warn_if_invalid
    from walk3d.io.atomic import atomic_write_text
    from walk3d.io.errors import DataFileError, OutputWriteError
    from walk3d.io.tables import write_csv_table
    from walk3d.outputs import new_folder, replace_files, write_errors
    from walk3d.plots.compare import compare_figure
    from walk3d.report.compare_page import compare_page
    from walk3d.results.compare import COLUMNS
    from walk3d.results.compare import compare as compare_rows
    from walk3d.results.prediction import load_result

    if out is not None:
        check_output_folder(out, replaces="compare.csv", own=_WRITES)
    preds = []
    for folder in (dir_a, dir_b):
        try:
            preds.append(load_result(folder))
        except (OSError, DataFileError, ValueError, KeyError) as exc:
            fail(f"cannot read {folder}: {' '.join(str(exc).split())}")
    try:
        rows = compare_rows(*preds)
    except ValueError as exc:
        fail(str(exc))
    t = Table(title=f"walk3d compare: A = {dir_a}, B = {dir_b}")
    for col in ("quantity", "unit", "A min/max", "B min/max", "change RMS/largest"):
        t.add_column(col, justify="left" if col in ("quantity", "unit") else "right")
    for r in rows:
        if r["group"] in ("criterion", "body"):
            if r["quantity"] in ("C_weighted", "C_tor", "C_en", "C_effort", "body_mass"):
                t.add_row(r["quantity"], r["unit"], f"{r['a_max']:.4g}", f"{r['b_max']:.4g}",
                          f"{r['largest_change']:+.4g}")  # fmt: skip
        elif r["quantity"] in _SHOWN:
            t.add_row(r["quantity"], r["unit"], f"{r['a_min']:.3g}/{r['a_max']:.3g}",
                      f"{r['b_min']:.3g}/{r['b_max']:.3g}",
                      f"{r['rms_change']:.2g}/{r['largest_change']:+.2g}")  # fmt: skip
    console.print(t)
    for name, pred in zip((dir_a, dir_b), preds, strict=True):
        warn_if_invalid(name, pred.summary)
    if out is None:
        return
    folder, labels = Path(out), (Path(dir_a).name, Path(dir_b).name)
    try:  # all three or none: built aside; a folder made for them goes again on failure
        with (
            write_errors(folder),
            new_folder(folder, _WRITES),
            replace_files(folder, last="report.html") as tmp,
        ):
            write_csv_table(tmp / "compare.csv", COLUMNS, rows)
            compare_figure(*preds, tmp / "compare.png", labels=labels)
            page = compare_page(
                rows,
                (tmp / "compare.png").read_bytes(),
                labels,
                (preds[0].summary, preds[1].summary),
            )
            atomic_write_text(tmp / "report.html", page)
    except OutputWriteError as exc:
        fail(str(exc), code=EXIT_WRITE)
    console.print(f"wrote {folder / 'compare.csv'}, {folder / 'compare.png'} and "
                  f"{folder / 'report.html'}")  # fmt: skip
