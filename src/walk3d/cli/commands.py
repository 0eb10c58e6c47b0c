"""``walk3d body``, ``walk3d predict``, ``walk3d compile``, ``walk3d cache`` and
``walk3d campaign``."""

from __future__ import annotations

import json
import sys
from typing import Annotated

import typer
from rich.table import Table

from walk3d.cli.common import (
    EXIT_WRITE,
    SOLVER,
    CalibrationFile,
    Criterion,
    DoubleSupport,
    FromTrial,
    Height,
    HslLibrary,
    LinearSolver,
    Mass,
    MaxIter,
    Nodes,
    Period,
    Perturbation,
    Restarts,
    Sex,
    SolverName,
    Speed,
    TrialGrf,
    app,
    check_output_folder,
    console,
    fail,
    settings_from_options,
)
from walk3d.problem.terms import DEFAULT_PRESET


@app.command()
def body(
    mass: Mass = 68.8,
    height: Height = 1.77,
    sex: Sex = "male",
    as_json: Annotated[bool, typer.Option("--json", help="Print one JSON object.")] = False,
) -> None:
    """Print the segment table (mass, centre of mass, inertia, length) and joint parameters."""
    from walk3d.body.model import build_body
    from walk3d.body.report import body_table

    try:
        model = build_body(mass, height, sex)
    except ValueError as exc:
        fail(str(exc))
    table = body_table(model)
    if as_json:
        sys.stdout.write(json.dumps(table) + "\n")
        return
    t = Table(title=f"walk3d body: {mass:g} kg, {height:g} m, {sex} (de Leva 1996)")
    for col in ("segment", "mass kg", "COM m (x, y, z)", "inertia kg m² (x, y, z)", "length m"):
        t.add_column(col)
    for s in table["segments"]:
        t.add_row(
            s["name"],
            f"{s['mass_kg']:.4f}",
            " ".join(f"{v:+.4f}" for v in s["com_m"]),
            " ".join(f"{v:.4f}" for v in s["inertia_kg_m2"]),
            f"{s['length_m']:.4f}",
        )
    console.print(t)
    j = Table(title="joints (ranges in degrees, strengths in N m: positive / negative)")
    for col in ("joint", "type", "DoF", "range", "strength"):
        j.add_column(col)
    for row in table["joints"]:
        for k, dof in enumerate(row["dofs"]):
            lo, hi = row["range_deg"][k]
            j.add_row(
                row["name"] if k == 0 else "",
                row["type"] if k == 0 else "",
                dof,
                f"{lo:g} .. {hi:g}",
                f"{row['strength_positive_Nm'][k]:.0f} / {row['strength_negative_Nm'][k]:.0f}",
            )
    console.print(j)


def _calibration_fields(path: str | None) -> dict:
    """Settings fields from a calibration file, or one error line and exit 2."""
    if path is None:
        return {}
    from walk3d.io.calibration import read_calibration

    try:
        d = read_calibration(path)
    except (OSError, ValueError) as exc:
        fail(" ".join(str(exc).split()))
    r, tr = d["rollover"], d["transition"]
    return {
        "rollover_s": tuple(float(v) for v in r["s"]),
        "rollover_ankle": tuple(tuple(float(c) for c in p) for p in r["ankle_m"]),
        "transition_ratios": tuple(float(tr[k]) for k in ("mu_x", "mu_z", "varpi_x", "varpi_y")),
    }


def _descriptors_from_trial(ctx, from_trial, grf, **given: float) -> tuple[float, float, float]:
    """V, T, Td for predict: the trial's, except options given explicitly on the command line."""
    if from_trial is None and grf is None:
        return given["speed"], given["period"], given["double_support"]
    if from_trial is None or grf is None:
        fail("--from-trial and --grf go together")
    from walk3d.trials.descriptors import descriptors_from_trial

    explicit = {
        k for k in given if getattr(ctx.get_parameter_source(k), "name", "") == "COMMANDLINE"
    }
    speed = given["speed"] if "speed" in explicit else None
    try:
        d = descriptors_from_trial(from_trial, grf, speed=speed)
    except (OSError, ValueError) as exc:
        fail(" ".join(str(exc).split()))
    values = {"speed": d.speed, "period": d.period, "double_support": d.double_support}
    values.update({k: given[k] for k in explicit})
    console.print(
        f"descriptors from {from_trial}: V = {values['speed']:.4f} m/s, "
        f"T = {values['period']:.4f} s, Td = {values['double_support']:.4f} s "
        f"(period: {d.period_method})",
        markup=False,
        soft_wrap=True,
    )
    return values["speed"], values["period"], values["double_support"]


@app.command()
def predict(
    ctx: typer.Context,
    out: Annotated[str, typer.Option("--out", help="Result folder (created).")],
    speed: Speed = 1.3806,
    period: Period = 1.08,
    double_support: DoubleSupport = 0.16,
    mass: Mass = 68.8,
    height: Height = 1.77,
    sex: Sex = "male",
    criterion: Criterion = DEFAULT_PRESET,
    seed: Annotated[int, typer.Option("--seed", help="Random start.", rich_help_panel=SOLVER)] = 0,
    solver: SolverName = "ipopt",
    nodes: Nodes = 20,
    threads: Annotated[
        int | None,
        typer.Option(
            "--threads", help="Threads for one solve (default: every core).", rich_help_panel=SOLVER
        ),
    ] = None,
    from_trial: FromTrial = None,
    grf: TrialGrf = None,
    calibration: CalibrationFile = None,
    perturbation: Perturbation = 0.05,
    restarts: Restarts = 1,
    max_iter: MaxIter = 800,
    linear_solver: LinearSolver = "mumps",
    hsl_library: HslLibrary = None,
) -> None:
    """Predict one gait cycle and write DIR/summary.json, result.npz, motion.mot, grf.mot and
    summary.png. Exit code 0 if the solve converged, 1 if not (results are still written and
    labelled), 2 for bad input, 3 if the folder could not be written (nothing is left), 130 on
    Ctrl-C. An earlier result in DIR is replaced. With --from-trial IK.mot --grf GRF.mot, V, T
    and Td come from the trial unless --speed, --period or --double-support are given."""
    check_output_folder(out, replaces="summary.json")
    speed, period, double_support = _descriptors_from_trial(
        ctx, from_trial, grf, speed=speed, period=period, double_support=double_support
    )
    if threads is None:
        from walk3d.problem.settings import available_cores

        threads = min(available_cores(), 64)
    settings = settings_from_options(
        criterion, solver, seed, speed=speed, period=period, double_support=double_support,
        mass=mass, height=height, sex=sex, nodes=nodes, threads=threads, max_iter=max_iter,
        perturbation=perturbation, restarts=restarts, linear_solver=linear_solver,
        hsl_library=hsl_library,
        **_calibration_fields(calibration),
    )  # fmt: skip
    from walk3d.io.errors import OutputWriteError
    from walk3d.predict import predict as run

    try:
        with console.status("walk3d: starting") as status:
            pred = run(settings, seed, solver, out_dir=out,
                       on_stage=lambda msg: status.update(f"walk3d: {msg}"))  # fmt: skip
    except OutputWriteError as exc:
        fail(str(exc), code=EXIT_WRITE)
    s = pred.summary
    t = Table(title=f"walk3d predict -> {out}")
    t.add_column("quantity")
    t.add_column("value")
    verdict = "yes" if s["converged"] else "NO - not a valid prediction"
    tries = s["attempts"]
    after = f", {tries} standing starts (--restarts)" if tries > 1 else ""
    t.add_row("converged", f"{verdict} ({s['status']}, {s['iterations']} iterations{after})")
    t.add_row("wall time", f"{s['wall_time_s']:.1f} s")
    if solver == "ipopt":
        comp = s.get("compiled_derivatives") or []
        t.add_row("derivatives", f"compiled C ({', '.join(comp)})" if comp else
                  "CasADi VM (run `walk3d compile` once for faster solves)")  # fmt: skip
        t.add_row("linear algebra", f"{settings.solver.linear_solver.upper()} on {s['blas']}")
    objective_rows(t, s["objective"], settings.model.criterion)
    t.add_row(
        "stride length", f"{s['stride_length_m']:.4f} m (target {s['stride_length_target_m']:.4f})"
    )
    t.add_row("step width", f"{s['step_width_m']:.3f} m")
    t.add_row("contact residual", f"{1000 * s['double_support_contact_residual_m']:.3f} mm")
    t.add_row("max constraint violation", f"{s['max_constraint_violation']:.2e} (at the nodes)")
    w = s["cycle_violations"]["worst"]
    t.add_row("on the 101-sample cycle", f"worst {w['kind']} {w['value']:.3g} (limit "
              f"{w['limit']:g}: {'holds' if w['holds'] else 'EXCEEDED'})")  # fmt: skip
    g = s["gait_checks"]
    realism = (
        f"peak Fy {g['peak_vertical_grf_bw']:.2f} BW, pelvis rotation "
        f"{g['pelvis_rotation_range_deg']:.0f} deg, list {g['pelvis_list_range_deg']:.0f} deg, "
        f"roughness {g['roughness_worst']:.2f} ({g['roughness_worst_dof']})"
    )
    t.add_row("realism", realism)
    t.add_row(
        "looks like walking",
        f"{'yes' if g['looks_like_walking'] else 'no'} (knee {g['knee_swing_max_deg']:.0f} deg in "
        f"swing, hip {g['hip_stance_max_deg']:.0f} deg in stance, two Fy humps: "
        f"{'yes' if g['two_fy_humps'] else 'no'})",
    )
    console.print(t)
    if not s["converged"]:
        raise typer.Exit(1)


def objective_rows(t: Table, objective: dict, criterion: str) -> None:
    """The criterion rows of the predict table: the minimized one first (with its weights),
    then every term with its x/y/z split."""
    from walk3d.problem import terms

    w = objective.get("C_weighted")
    if terms.label(criterion) == "C_weighted" and w:
        name = terms.preset_name(criterion)
        t.add_row(
            "criterion",
            f"{w['total']:.4g} = "
            + " + ".join(f"{v:g}·C_{k}" for k, v in w["weights"].items())
            + (f" (preset {name})" if name else ""),
        )
    for key in ("C_tor", "C_en", *(f"C_{k}" for k in terms.EXTRAS)):
        c = objective.get(key)
        if c:
            t.add_row(key, f"{c['total']:.4g}  (x {c['x']:.3g}, y {c['y']:.3g}, z {c['z']:.3g})")


@app.command(name="compile")
def compile_model(
    speed: Speed = 1.3806,
    period: Period = 1.08,
    double_support: DoubleSupport = 0.16,
    mass: Mass = 68.8,
    height: Height = 1.77,
    sex: Sex = "male",
    criterion: Criterion = DEFAULT_PRESET,
    nodes: Nodes = 20,
    calibration: CalibrationFile = None,
) -> None:
    """Compile the solver's derivatives to C for these options and keep them in the model
    cache. Later predictions and campaigns with the same sex, criterion and calibration use
    them, at any body mass, stature, speed, period and double support (about twice as fast a
    solve). Takes minutes once; needs a C compiler ($CC or cc). Exit code 2 without a compiler
    or for bad input."""
    settings = settings_from_options(
        criterion, "ipopt", 0, speed=speed, period=period, double_support=double_support,
        mass=mass, height=height, sex=sex, nodes=nodes, **_calibration_fields(calibration),
    )  # fmt: skip
    from walk3d.cli.compile import compile_with_progress

    compile_with_progress(settings, console)


@app.command(name="cache")
def cache_info(
    clear: Annotated[
        bool,
        typer.Option(
            "--clear", help="Delete every cached model, compiled library and BLAS bridge."
        ),
    ] = False,
) -> None:
    """Show the model cache folder ($WALK3D_CACHE_DIR, else the user cache folder) and what it
    holds; with --clear, delete its entries (always safe: they are rebuilt, or recompiled with
    walk3d compile, when needed)."""
    from walk3d.solve import model_cache

    use = model_cache.cache_usage()
    state = "" if model_cache.cache_enabled() else " (off: WALK3D_CACHE)"
    console.print(f"walk3d cache: {model_cache.cache_dir()}{state}", markup=False, highlight=False)
    console.print(f"{use['models']} model entries, {use['libraries']} compiled libraries, "
                  f"{use['bridges']} BLAS bridges, {use['bytes'] / 1e6:.1f} MB")  # fmt: skip
    if clear:
        files, freed = model_cache.clear_entries()
        console.print(f"deleted {files} files, {freed / 1e6:.1f} MB")


@app.command()
def campaign(
    starts: Annotated[int, typer.Option("--starts", help="Number of random starts.")],
    out: Annotated[str, typer.Option("--out", help="Campaign folder (created or resumed).")],
    criterion: Criterion = DEFAULT_PRESET,
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
    period: Period = 1.08,
    double_support: DoubleSupport = 0.16,
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
    perturbation: Perturbation = 0.05,
    restarts: Restarts = 1,
    linear_solver: LinearSolver = "mumps",
    hsl_library: HslLibrary = None,
    calibration: CalibrationFile = None,
) -> None:
    """Run N random starts in parallel (Dask) and rank them. Each finished start is stored
    at once in DIR/starts/seed_<seed>/ (a walk3d predict folder plus record.json); rerunning
    the same command resumes (a larger --starts adds starts). Writes DIR/ranking.csv and
    DIR/best/. Exit code 0 if a start converged, 1 if none did, 2 for bad input, 3 if starts
    could not be written (a rerun retries them, and starts that failed on the disk, memory or a
    lost worker), 130 on Ctrl-C."""
    if starts < 1:
        fail(f"--starts must be a positive integer, got {starts}")
    if workers is not None and workers < 1:
        fail(f"--workers must be a positive integer, got {workers}")
    check_output_folder(out)
    if scheduler:
        from walk3d.campaign.runner import check_scheduler

        try:
            check_scheduler(scheduler)
        except ValueError as exc:
            fail(str(exc))
    settings = settings_from_options(
        criterion, solver, seed, speed=speed, period=period, double_support=double_support,
        mass=mass, height=height, sex=sex, nodes=nodes, max_iter=max_iter,
        perturbation=perturbation, restarts=restarts, linear_solver=linear_solver,
        hsl_library=hsl_library, **_calibration_fields(calibration),
    )  # fmt: skip
    from walk3d.campaign import CampaignMismatch, run_campaign
    from walk3d.campaign.ranking import top_table
    from walk3d.cli.compile import compile_with_progress, worth_compiling
    from walk3d.io.errors import OutputWriteError

    if solver == "ipopt" and (compile_c or (compile_c is None and worth_compiling(starts))):
        compile_with_progress(settings, console)

    try:
        report = run_campaign(settings, starts, seed, out, workers=workers, scheduler=scheduler,
                              solver=solver, console=console)  # fmt: skip
    except CampaignMismatch as exc:
        fail(" ".join(str(exc).split()))
    except OSError as exc:
        fail(str(OutputWriteError(out, exc)), code=EXIT_WRITE)
    console.print(top_table(report.rows, criterion))
    retried = f", {report.retried} retried after an environment failure" if report.retried else ""
    console.print(
        f"{len(report.rows)} starts in {out}: {report.converged} converged, "
        f"{report.errors} errors; this run {report.ran}{retried}, resumed {report.skipped} "
        f"({report.wall_time_s:.1f} s); ranking in {out}/ranking.csv"
    )
    if report.missing:
        fail(f"{report.missing} starts could not be recorded in {out} (disk full?); free space "
             "and rerun the same command to run them", code=EXIT_WRITE)  # fmt: skip
    if report.best_seed is None:
        console.print("no start converged: no best/ folder was written")
        raise typer.Exit(1)
    console.print(f"best converged start: seed {report.best_seed}, copied to {out}/best/")
