"""``walk3d body``, ``walk3d predict`` and ``walk3d compile``."""

from __future__ import annotations

import json
import sys
from typing import Annotated

import typer
from rich.markup import escape
from rich.table import Table

from walk3d.cli import changes as what_if
from walk3d.cli import finished
from walk3d.cli.changes import AddedMass, EqualSteps, FullCycle, LegLength, Range, Strength
from walk3d.cli.common import (
    EXIT_WRITE,
    SOLVER,
    CalibrationFile,
    CompileLater,
    Criterion,
    DescriptorsFrom,
    DoubleSupport,
    FromTrial,
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
    SplitTerms,
    Start,
    TrialGrf,
    app,
    console,
    fail,
    gait_fields,
    paper_case,
    settings_from_options,
)
from walk3d.cli.labels import predict_exit_code, start_text
from walk3d.cli.warning_lines import warned
from walk3d.model.terms import DEFAULT_PRESET


@app.command(short_help="Print the segment table and joint parameters.")
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


def calibration_fields(path: str | None) -> dict:
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


def _descriptors_from_trial(ctx, from_trial, grf, **given) -> tuple:
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

    def shown(name: str, unit: str) -> str:  # a given "auto" (predicted) or a number
        v = values[name]
        return f"{v:.4f} {unit}" if isinstance(v, float) else f"{v} (predicted)"

    console.print(
        f"descriptors from {from_trial}: V = {shown('speed', 'm/s')}, "
        f"T = {shown('period', 's')}, Td = {shown('double_support', 's')} "
        f"(period: {d.period_method})",
        markup=False,
        soft_wrap=True,
    )
    return values["speed"], values["period"], values["double_support"]


@app.command(short_help="Predict one gait cycle and write its result folder.")
def predict(
    ctx: typer.Context,
    out: Annotated[str, typer.Option("--out", help="Result folder (created).")],
    speed: Speed = 1.3806,
    period: Period = "auto",
    double_support: DoubleSupport = "auto",
    paper: Paper = False,
    mass: Mass = 68.8,
    height: Height = 1.77,
    sex: Sex = "male",
    criterion: Criterion = DEFAULT_PRESET,
    handover: Handover = True,
    split_terms: SplitTerms = 0,
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
    start: Start = "atlas",
    descriptors_from: DescriptorsFrom = "atlas",
    perturbation: Perturbation = 0.05,
    restarts: Restarts = 1,
    max_iter: MaxIter = 800,
    linear_solver: LinearSolver = "mumps",
    hsl_library: HslLibrary = None,
    animate: Annotated[
        bool,
        typer.Option("--animate", help="Also write DIR/animation.mp4 (two cycles, a few s)."),
    ] = False,
    strength: Strength = None,
    limits: Range = None,
    added_mass: AddedMass = None,
    leg_length: LegLength = None,
    full_cycle: FullCycle = False,
    equal_steps: EqualSteps = False,
    compile_later: CompileLater = True,
) -> None:
    """Predict one gait cycle and write DIR/summary.json, result.npz, motion.mot, grf.mot,
    summary.png (and animation.mp4 with --animate) and, last, report.html. Exit codes: 0 the
    solve converged; 1 it did not (results are still written and labelled); 2 bad input,
    before any solve; 3 the folder could not be written (nothing is left); 4 it converged on a
    gait that does not look like walking (written and labelled); 130 Ctrl-C; 143 SIGTERM
    (nothing is written; docs/usage.md, Exit codes). An earlier result in DIR
    is replaced; a DIR that also holds files walk3d did not write is refused. T and Td are
    predicted with the gait unless given (--period, --double-support, --paper). With
    --from-trial IK.mot --grf GRF.mot, V, T and Td come from the trial unless --speed,
    --period or --double-support are given."""
    from walk3d.results.prediction import check_result_folder

    try:  # the API's check (walk3d.predict, Prediction.save)
        check_result_folder(out, "--out")
    except ValueError as exc:
        fail(str(exc))
    case = paper_case(ctx, paper, {"speed": speed, "period": period, "mass": mass, "sex": sex,
                                   "double_support": double_support, "height": height,
                                   "criterion": criterion})  # fmt: skip
    speed, period, double_support = _descriptors_from_trial(
        ctx, from_trial, grf, speed=case["speed"], period=case["period"],
        double_support=case["double_support"],
    )  # fmt: skip
    mass, height, sex, criterion = case["mass"], case["height"], case["sex"], case["criterion"]
    if threads is None:
        from walk3d.problem.settings import available_cores

        threads = min(available_cores(), 64)
    settings = settings_from_options(
        criterion, solver, seed, **gait_fields(speed, period, double_support, height),
        mass=mass, height=height, sex=sex, nodes=nodes, threads=threads, max_iter=max_iter,
        start=start, perturbation=perturbation, restarts=restarts, linear_solver=linear_solver,
        hsl_library=hsl_library, handover=handover, descriptors_from=descriptors_from,
        split_terms=split_terms,
        **calibration_fields(calibration),
        **what_if.changes_option(strength, limits, added_mass, full_cycle, leg_length, equal_steps),
    )  # fmt: skip
    before = finished.identity(out)
    try:
        _predict_and_show(settings, seed, solver, out, animate, compile_later, start)
    except KeyboardInterrupt:
        if "walk3d.cli.background" in sys.modules:  # no compile started by a stopped run
            sys.modules["walk3d.cli.background"].withdraw()
        code = finished.code_if_written(out, before)  # the signal came once the result was whole
        if code is None:
            raise
        raise typer.Exit(code) from None


def _predict_and_show(settings, seed: int, solver: str, out: str, animate: bool,
                      compile_later: bool, start: str) -> None:  # fmt: skip
    """Solve, write the folder and its report, print the table; the exit code as typer.Exit."""
    from walk3d.io.errors import OutputWriteError
    from walk3d.pipeline import predict as run
    from walk3d.report.writer import write_report_or_warn

    def run_and_report(on_stage):
        """The prediction, then its report.html (a page that fails is a warning)."""
        pred = run(settings, seed, solver, out_dir=out, animate=animate, on_stage=on_stage)
        write_report_or_warn(out)
        return pred

    try:
        with console.status("walk3d: starting") as status:
            pred = warned(run_and_report, lambda msg: status.update(f"walk3d: {msg}"))
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
    t.add_row("start", start_text(s))
    t.add_row("descriptors", descriptor_text(s["descriptors"]))
    if solver == "ipopt":
        from walk3d.cli import background

        comp = s.get("compiled_derivatives") or []
        try:  # the prediction is done: nothing here may fail it
            later = background.start(settings, comp, compile_later)
        except Exception:  # noqa: BLE001
            later = None
        vm = f"CasADi VM; {escape(later)}" if later else f"CasADi VM ({compile_hint(settings)})"
        t.add_row("derivatives", f"compiled C ({', '.join(comp)})" if comp else vm)
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
        f"swing, hip {g['hip_midstance_deg']:.0f} deg in mid-stance, two Fy humps: "
        f"{'yes' if g['two_fy_humps'] else 'no'})",
    )
    console.print(t)
    code = predict_exit_code(out, s)  # one warning line unless it converged and walks
    if code:
        raise typer.Exit(code)


def descriptor_text(d: dict) -> str:
    """One line of the descriptors (``summary.json``'s ``descriptors``), marking predicted ones."""

    def mark(name: str) -> str:
        by = " from the atlas" if d.get("predicted_by") == "atlas" else ""
        return f" (predicted{by})" if name in d["predicted"] else ""

    return (f"V {d['speed']:.3f} m/s, T {d['period']:.3f} s{mark('period')}, Td "
            f"{d['double_support']:.3f} s{mark('double_support')}; stride "
            f"{d['stride_length']:.3f} m, cadence {d['cadence']:.1f} steps/min, stance "
            f"{100 * d['stance_fraction']:.1f} %")  # fmt: skip


def compile_hint(settings) -> str:
    """What makes later solves of ``settings``' sex and criterion faster: the ``walk3d compile``
    command and its cost (165-180 s on 2 cores, docs/solver.md), or the options to repeat."""
    from walk3d.model import terms

    model = settings.model
    name = terms.preset_name(model.criterion)
    crit = "" if name == DEFAULT_PRESET else f" --criterion {name or model.criterion}"
    more = "" if type(model)(criterion=model.criterion) == model else " and this model's options"
    return (f"`walk3d compile --sex {settings.gait.sex}{crit}`{more} once, about 3 minutes, "
            "about halves later solves")  # fmt: skip


def objective_rows(t: Table, objective: dict, criterion: str) -> None:
    """The criterion rows of the predict table: the minimized one first (with its weights),
    then every term with its x/y/z split."""
    from walk3d.model import terms

    w = objective.get("C_weighted")
    if terms.label(criterion) == "C_weighted" and w:
        name = terms.preset_name(criterion)
        t.add_row(
            "criterion",
            f"{w['total']:.4g} = "
            + " + ".join(f"{v:g}·C_{k}" for k, v in w["weights"].items())
            + (f" (preset {name})" if name else ""),
        )
    for key in terms.reported(objective):
        c = objective.get(key)
        if c:
            t.add_row(key, f"{c['total']:.4g}  (x {c['x']:.3g}, y {c['y']:.3g}, z {c['z']:.3g})")


@app.command(name="compile", short_help="Compile the solver's derivatives to C: faster solves.")
def compile_model(
    speed: Speed = 1.3806,
    period: Period = "auto",
    double_support: DoubleSupport = "auto",
    mass: Mass = 68.8,
    height: Height = 1.77,
    sex: Sex = "male",
    criterion: Criterion = DEFAULT_PRESET,
    handover: Handover = True,
    nodes: Nodes = 20,
    calibration: CalibrationFile = None,
) -> None:
    """Compile the solver's derivatives to C for these options and keep them in the model
    cache. Later predictions and campaigns with the same sex, criterion and calibration use
    them, at any body mass, stature, speed, period and double support (about twice as fast a
    solve). Takes minutes once; needs a C compiler ($CC or cc). Exit code 2 without a compiler
    or for bad input, 3 if the model cache cannot be written (a full disk)."""
    settings = settings_from_options(
        criterion, "ipopt", 0, **gait_fields(speed, period, double_support, height),
        mass=mass, height=height, sex=sex, nodes=nodes, handover=handover,
        **calibration_fields(calibration),
    )  # fmt: skip
    from walk3d.cli.compile import compile_with_progress

    compile_with_progress(settings, console)
