"""``walk3d track``: the measured gait inside walk3d's model (docs/tracking.md)."""

from __future__ import annotations

from typing import Annotated

import typer
from rich.table import Table

from walk3d.cli.common import (
    EXIT_WRITE,
    Height,
    Mass,
    PlateThreshold,
    Sex,
    app,
    check_output_file,
    console,
    fail,
    input_file,
    positive_options,
)


@app.command(short_help="Track a measured gait inside walk3d's model.")
def track(
    out: Annotated[str, typer.Option("--out", help="Result folder to write.")],
    ik: Annotated[
        str | None, typer.Option("--ik", help="IK .mot of a measured trial.", callback=input_file)
    ] = None,
    grf: Annotated[
        str | None, typer.Option("--grf", help="GRF .mot of the same trial.", callback=input_file)
    ] = None,
    table: Annotated[
        str | None,
        typer.Option(
            "--table", help="A cycle table (.csv) instead of a trial.", callback=input_file
        ),
    ] = None,
    mass: Mass = 68.8,
    height: Height = 1.77,
    sex: Sex = "male",
    speed: Annotated[
        float | None,
        typer.Option("--speed", help="V, m/s (default: the trial's; a treadmill's belt speed)."),
    ] = None,
    period: Annotated[
        float | None, typer.Option("--period", help="T, s (default: the trial's).")
    ] = None,
    double_support: Annotated[
        float | None, typer.Option("--double-support", help="Td, s (default: the trial's).")
    ] = None,
    criterion: Annotated[
        str, typer.Option("--criterion", help="The criterion kept at a small weight.")
    ] = "natural",
    weight: Annotated[
        float, typer.Option("--weight", help="Weight of the tracking against the criterion (1).")
    ] = 100.0,
    threshold: PlateThreshold = 20.0,
    seed: Annotated[int, typer.Option("--seed", help="Random start.")] = 0,
    only: Annotated[
        list[str] | None,
        typer.Option(
            "--only",
            help="Track these DoFs alone, comma-separated or repeated (knee_flexion: both "
            "sides); the others follow the criterion.",
        ),
    ] = None,
    relax: Annotated[
        list[str] | None,
        typer.Option(
            "--relax",
            help="loop=M, foot-flat=DEG or heel-rise=FRACTION: relax a "
            "constraint of the model to see what it costs the tracking (repeat).",
        ),
    ] = None,
) -> None:
    """Solve walk3d's own problem, every constraint of walk3d predict kept, with the criterion
    replaced by the deviation from a measured gait (--ik with --grf, or --table) plus a small
    weight on the criterion. Writes the result folder with tracking.csv (RMSE per DoF and force
    component) and, where a DoF misses by more than 3 deg, binding.csv (the constraints with the
    largest multipliers). Exit code 0 if the solve converged, 1 if not, 2 for bad input, 3 if
    the folder could not be written."""
    from walk3d.io.errors import DataFileError, OutputWriteError
    from walk3d.results.prediction import check_result_folder

    positive_options(mass=mass, height=height, threshold=threshold, speed=speed, period=period,
                     double_support=double_support, weight=weight)  # fmt: skip
    if sex not in ("male", "female"):
        fail(f"--sex must be 'male' or 'female', got {sex!r}")
    if table is not None and (ik is not None or grf is not None):
        given = " and ".join(o for o, v in (("--ik", ik), ("--grf", grf)) if v is not None)
        fail(f"give one measured gait: --table or --ik with --grf, not both (--table and {given} "
             "were given)")  # fmt: skip
    if table is None and ik is None:
        fail("give a measured gait: --ik IK.mot with --grf GRF.mot, or --table CYCLE.csv")
    if ik is not None and grf is None:
        fail("--ik needs --grf (the heel strikes come from the ground reaction)")
    try:
        check_result_folder(out, "--out")
    except ValueError as exc:
        fail(str(exc))
    from walk3d.tracking import only_dofs, relaxations, track_settings, write_tracking
    from walk3d.validation.target import tracking_target

    try:
        relaxed = relaxations(relax or [])
    except ValueError as exc:
        fail(str(exc))
    names = None if only is None else [n.strip() for item in only for n in item.split(",")]
    if names is not None and not all(names):
        fail(f"--only: an empty DoF name in {','.join(only)!r}; name DoFs such as knee_flexion")

    given = {"speed": speed, "period": period, "double_support": double_support}
    try:
        target = tracking_target(table=table, ik=ik, grf=grf, mass=mass, threshold=threshold,
                                 **given)  # fmt: skip
        if names is not None:
            target = only_dofs(target, names)
        settings = track_settings(target, mass=mass, height=height, sex=sex,
                                  criterion=criterion, weight=weight, **given,
                                  **relaxed)  # fmt: skip
    except (OSError, DataFileError, ValueError) as exc:
        fail(" ".join(str(exc).split()))
    try:
        with console.status("walk3d: tracking") as status:
            tracked = write_tracking(target, settings, out, seed,
                                     lambda msg: status.update(f"walk3d: {msg}"))  # fmt: skip
    except OutputWriteError as exc:
        fail(str(exc), code=EXIT_WRITE)
    s = tracked.prediction.summary
    t = Table(title=f"walk3d track -> {out}")
    for col in ("quantity", "RMSE", "largest error"):
        t.add_column(col)
    for row in tracked.rows:
        t.add_row(row["quantity"], f"{row['rmse']:.2f} {row['unit']}",
                  f"{row['max_abs']:.2f} {row['unit']}")  # fmt: skip
    console.print(t)
    verdict = "yes" if s["converged"] else "NO - not a valid tracking"
    console.print(f"converged: {verdict} ({s['status']}, {s['iterations']} iterations, "
                  f"{s['wall_time_s']:.1f} s)", markup=False)  # fmt: skip
    for row in tracked.binding:
        console.print(f"binds: {row['kind']} {row['name']} (|multiplier| summed "
                      f"{row['multiplier']:.3g}; nodes {row['nodes']})", markup=False)  # fmt: skip
    if not s["converged"]:
        raise typer.Exit(1)


@app.command(short_help="What the criterion charges a tracked gait, phase by phase.")
def audit(
    tracked: Annotated[str, typer.Argument(help="Result folder of walk3d track.")],
    predicted: Annotated[str, typer.Argument(help="Result folder of walk3d predict.")],
    out: Annotated[
        str | None,
        typer.Option("--out", help="Write the tables as JSON here (default TRACKED/audit.json)."),
    ] = None,
) -> None:
    """What the prediction's criterion charges the tracked gait against the predicted one: each
    term per gait phase and in total (raw, and weighted as the criterion weighs it), each leg's
    centre-of-mass work in double support, and the right leg's joint-power bursts (J/kg).
    Written as JSON to TRACKED/audit.json, whose report.html then shows it, or to --out (its
    missing folders made, as calibrate, report and animate make theirs).
    TRACKED may be a prediction too (two predicted gaits, charged by PREDICTED's criterion;
    one warning line says so). Exit code 2 for a folder that is not a complete result or an
    --out that cannot be a JSON file, lies in a walk3d result folder (but TRACKED/audit.json)
    or is an existing file other than an earlier audit (checked before the audit), 3 if it
    cannot be written."""
    import json
    import sys
    from pathlib import Path

    from walk3d.io.atomic import atomic_write_text
    from walk3d.io.errors import DataFileError
    from walk3d.outputs import same_path
    from walk3d.results.audit import is_audit_file, is_tracking
    from walk3d.tracking import audit as run

    default = Path(tracked) / "audit.json"
    own = out is None or (Path(tracked).is_dir() and same_path(out, default))
    kind = ("walk3d audit", is_audit_file)  # an earlier audit is replaced, nothing else
    if not own:  # a folder, device, result's file, user's file...: refused now
        check_output_file(out, suffix=".json", existing=kind)
    elif Path(tracked).is_dir():  # the default, refused alike
        check_output_file(str(default), "--out" if out else "the audit", home=tracked,
                          existing=kind)  # fmt: skip
    try:
        with console.status("walk3d: auditing"):
            result = run(tracked, predicted)
    except (OSError, DataFileError, ValueError) as exc:
        fail(" ".join(str(exc).split()))
    if not is_tracking(tracked):
        sys.stderr.write(f"walk3d: warning: TRACKED {tracked} is a prediction, not a tracking "
                         "(walk3d track): the audit compares two predicted gaits, its "
                         f"'tracked' columns are {tracked}'s\n")  # fmt: skip
    _audit_tables(result)
    target = default if own else Path(out)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)  # as calibrate, report, animate do
        atomic_write_text(target, json.dumps(result, indent=1) + "\n")
        if own:
            from walk3d.report.writer import write_report_or_warn
            from walk3d.results.prediction import record_file

            record_file(tracked, "audit.json")
            write_report_or_warn(tracked)
    except (OSError, DataFileError) as exc:
        fail(f"cannot write {target}: {getattr(exc, 'strerror', None) or exc}", code=EXIT_WRITE)
    console.print(f"written to {target}", markup=False)


def _audit_tables(result: dict) -> None:
    from walk3d.results.audit import PHASES

    t = Table(title=f"criterion terms, s (weighted: x weight); {result['criterion']}")
    t.add_column("term")
    t.add_column("weight")
    for phase in (*PHASES, "total"):
        t.add_column(f"{phase} T / P")
    for row in result["terms"]:
        cells = [f"{row[f'tracked {p}']:.3g} / {row[f'predicted {p}']:.3g}"
                 for p in (*PHASES, "total")]  # fmt: skip
        t.add_row(row["term"], f"{row['weight']:g}", *cells)
    console.print(t)
    console.print(f"C_weighted: tracked {result['C_weighted tracked']:.4g}, predicted "
                  f"{result['C_weighted predicted']:.4g}", markup=False)  # fmt: skip
    for key, unit in (("limb_work", "J/kg per step"), ("bursts", "J/kg")):
        t = Table(title=f"{key.replace('_', ' ')}, {unit}")
        t.add_column("")
        names = list(result[key]["tracked"])
        for n in names:
            t.add_column(n)
        for label in ("tracked", "predicted"):
            t.add_row(label, *(f"{result[key][label][n]:.3f}" for n in names))
        console.print(t)
