"""``walk3d campaign``: many random starts in parallel, ranked."""

from __future__ import annotations

import sys
from typing import Annotated

import typer

from walk3d.cli import changes as what_if
from walk3d.cli.changes import AddedMass, EqualSteps, FullCycle, LegLength, Range, Strength
from walk3d.cli.commands import calibration_fields
from walk3d.cli.common import (
    EXIT_WRITE,
    SOLVER,
    CalibrationFile,
    Criterion,
    DoubleSupport,
    Handover,
    Height,
    HslLibrary,
    LinearSolver,
    Mass,
    MaxIter,
    Nodes,
    Paper,
    Period,
    Perturbation,
    Restarts,
    Sex,
    SolverName,
    Speed,
    Start,
    app,
    check_output_folder,
    console,
    fail,
    gait_fields,
    paper_case,
    scheduler_option,
    settings_from_options,
)
from walk3d.cli.warning_lines import warning_lines
from walk3d.model.terms import DEFAULT_PRESET


@app.command(short_help="Run random starts in parallel (Dask) and rank them.")
def campaign(
    ctx: typer.Context,
    starts: Annotated[int, typer.Option("--starts", help="Number of random starts.")],
    out: Annotated[str, typer.Option("--out", help="Campaign folder (created or resumed).")],
    criterion: Criterion = DEFAULT_PRESET,
    handover: Handover = True,
    seed: Annotated[
        int, typer.Option("--seed", help="Base seed: start k uses seed+k.", rich_help_panel=SOLVER)
    ] = 0,
    workers: Annotated[
        int | None, typer.Option("--workers", help="Local worker processes (default: cores).")
    ] = None,
    scheduler: Annotated[
        str | None,
        typer.Option(
            "--scheduler",
            help="Address of a running Dask scheduler (its workers must see --out).",
        ),
    ] = None,
    speed: Speed = 1.3806,
    period: Period = "auto",
    double_support: DoubleSupport = "auto",
    paper: Paper = False,
    mass: Mass = 68.8,
    height: Height = 1.77,
    sex: Sex = "male",
    solver: SolverName = "ipopt",
    nodes: Nodes = 20,
    max_iter: MaxIter = 800,
    compile_c: Annotated[
        bool | None,
        typer.Option(
            "--compile/--no-compile",
            help="Compile the derivatives to C first (as walk3d compile). Default: when at "
            "least 30 starts are to run and a C compiler is found.",
        ),
    ] = None,
    start: Start = "atlas",
    perturbation: Perturbation = 0.05,
    restarts: Restarts = 1,
    linear_solver: LinearSolver = "mumps",
    hsl_library: HslLibrary = None,
    calibration: CalibrationFile = None,
    strength: Strength = None,
    limits: Range = None,
    added_mass: AddedMass = None,
    leg_length: LegLength = None,
    full_cycle: FullCycle = False,
    equal_steps: EqualSteps = False,
) -> None:
    """Run N random starts in parallel (Dask) and rank them. Each finished start is stored
    at once in DIR/starts/seed_<seed>/ (a walk3d predict folder plus record.json); rerunning
    the same command resumes (a larger --starts adds starts). Writes DIR/ranking.csv and
    DIR/best/. Exit code 0 if a start converged, 1 if none did, 2 for bad input, 3 if starts
    could not be written (a rerun retries them, and starts that failed on the disk, memory or a
    lost worker), 130 on Ctrl-C. Ends with DIR/report.html (walk3d report)."""
    from walk3d.campaign.runner import MAX_STARTS, MAX_WORKERS

    if not 1 <= starts <= MAX_STARTS:
        fail(f"--starts must be an integer in [1, {MAX_STARTS}], got {starts}")
    if workers is not None and not 1 <= workers <= MAX_WORKERS:
        fail(f"--workers must be an integer in [1, {MAX_WORKERS}], got {workers}")
    check_output_folder(out)
    scheduler_option(scheduler)
    case = paper_case(ctx, paper, {"speed": speed, "period": period, "mass": mass, "sex": sex,
                                   "double_support": double_support, "height": height,
                                   "criterion": criterion})  # fmt: skip
    settings = settings_from_options(
        case["criterion"], solver, seed,
        **gait_fields(case["speed"], case["period"], case["double_support"], case["height"]),
        mass=case["mass"], height=case["height"], sex=case["sex"], nodes=nodes, max_iter=max_iter,
        start=start, perturbation=perturbation, restarts=restarts, linear_solver=linear_solver,
        hsl_library=hsl_library, handover=handover, **calibration_fields(calibration),
        **what_if.changes_option(strength, limits, added_mass, full_cycle, leg_length, equal_steps),
    )  # fmt: skip
    from walk3d.campaign import CampaignMismatch, run_campaign
    from walk3d.campaign.ranking import top_table
    from walk3d.cli.compile import compile_with_progress, worth_compiling
    from walk3d.io.errors import OutputWriteError

    if solver == "ipopt" and (compile_c or (compile_c is None and worth_compiling(starts))):
        compile_with_progress(settings, console)

    try:
        with warning_lines():  # a damaged start run again: one line
            report = run_campaign(settings, starts, seed, out, workers=workers,
                                  scheduler=scheduler, solver=solver, console=console)  # fmt: skip
    except CampaignMismatch as exc:
        fail(" ".join(str(exc).split()))
    except OSError as exc:
        fail(str(OutputWriteError(out, exc)), code=EXIT_WRITE)
    console.print(top_table(report.rows, case["criterion"], per_metre=bool(settings.gait.free)))
    retried = f", {report.retried} retried after an environment failure" if report.retried else ""
    console.print(
        f"{len(report.rows)} starts in {out}: {report.converged} converged, "
        f"{report.errors} errors; this run {report.ran}{retried}, resumed {report.skipped} "
        f"({report.wall_time_s:.1f} s); ranking in {out}/ranking.csv"
    )
    if report.missing:
        fail(f"{report.missing} starts could not be recorded in {out} (disk full?); free space "
             "and rerun the same command to run them", code=EXIT_WRITE)  # fmt: skip
    _write_report(out)
    if report.best_seed is None:
        console.print("no start converged: no best/ folder was written")
        raise typer.Exit(1)
    console.print(f"best converged start: seed {report.best_seed}, copied to {out}/best/")


def _write_report(out: str) -> None:
    """``DIR/report.html`` at the end of a campaign; a failure is one warning line and leaves
    the exit code as it is."""
    from walk3d.report.writer import write_report

    try:
        _, path = write_report(out)
    except Exception as exc:  # noqa: BLE001 - the page is optional, the ranking is not
        sys.stderr.write(f"walk3d: warning: report.html not written in {out}: "
                         f"{' '.join(str(exc).split())}\n")  # fmt: skip
        return
    console.print(f"report: {path}", markup=False, highlight=False)
