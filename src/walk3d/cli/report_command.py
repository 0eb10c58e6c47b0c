"""``walk3d report DIR``: a self-contained report.html of a prediction or campaign folder."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from walk3d.cli.common import EXIT_WRITE, app, check_output_file, console, fail


@app.command(short_help="Write a result's or a campaign's HTML page.")
def report(
    folder: Annotated[
        str, typer.Argument(help="Prediction folder (walk3d predict) or campaign folder.")
    ],
    out: Annotated[
        str | None, typer.Option("--out", help="HTML file (default: DIR/report.html).")
    ] = None,
    data: Annotated[
        str | None,
        typer.Option(
            "--data",
            help="Measured-data folder for the normative bands (default: $WALK3D_SHARED_DATA, "
            "else ../shared/data).",
        ),
    ] = None,
) -> None:
    """Write one self-contained HTML page: inputs, convergence, criteria with their x/y/z
    split, joint angles, moments and ground reactions over measured normative bands, and the
    animation if DIR has one; for a campaign, its starts, the five best and the best
    prediction. Written atomically; a page written into a prediction folder is listed in its
    manifest, and made again when deleted. Exit code 2 for a folder of neither kind, a bad
    option (an --out inside another walk3d result folder, or an existing file that is not a
    page walk3d wrote, too) or a --data folder whose
    tables are malformed or hold NaN or infinite values; 3 if it cannot be written."""
    from walk3d.report.html import is_walk3d_page
    from walk3d.report.norms import SOURCES, find_data, load_norms
    from walk3d.report.writer import build_report, save_report
    from walk3d.results.views import is_listed_view

    target = Path(out) if out is not None else None
    if target is not None and target.suffix.lower() not in (".html", ".htm"):
        fail(f"--out must name an .html file, got {target}")
    if not Path(folder).is_dir():
        fail(f"{folder} is not a folder")
    kind = ("walk3d report", lambda p: is_walk3d_page(p) or is_listed_view(p))  # not a user's
    if target is not None:  # a folder, device, FIFO, another result's or a user's file: refused
        check_output_file(str(target), home=folder, existing=kind)
    else:  # DIR's own page, of any walk3d version
        check_output_file(str(Path(folder) / "report.html"), "the page", home=folder)
    found = find_data(data)
    if data is not None and found is None:
        names = ", ".join(rel for rel, _ in SOURCES)
        fail(f"--data {data} holds none of {names}")
    try:
        norms = load_norms(found, strict=data is not None)
    except (OSError, ValueError) as exc:
        fail(f"--data {data}: {' '.join(str(exc).split())}")
    try:
        with console.status("walk3d: writing the report"):
            kind, page = build_report(folder, norms, target)
    except (OSError, ValueError) as exc:
        fail(f"cannot report on {folder}: {' '.join(str(exc).split())}")
    try:
        path = save_report(folder, kind, page, target)
    except (OSError, ValueError) as exc:
        fail(f"cannot write the report: {' '.join(str(exc).split())}", code=EXIT_WRITE)
    bands = f"bands from {found}" if norms.bands else "no measured bands found"
    console.print(f"walk3d report -> {path} ({kind}, {path.stat().st_size / 1e6:.2f} MB, "
                  f"{bands})", markup=False, highlight=False)  # fmt: skip
