"""``walk3d sweep``: predictions across speeds with the period and double support predicted."""

from __future__ import annotations

from typing import Annotated

import typer

from walk3d.cli import changes as what_if
from walk3d.cli.changes import AddedMass, EqualSteps, FullCycle, LegLength, Range, Strength
from walk3d.cli.common import (
    EXIT_WRITE,
    SOLVER,
    Criterion,
    Height,
    Mass,
    MaxIter,
    Nodes,
    Restarts,
    Sex,
    app,
    check_output_file,
    check_output_folder,
    console,
    fail,
    settings_from_options,
)
from walk3d.cli.warning_lines import warning_lines
from walk3d.model.terms import DEFAULT_PRESET


@app.command(short_help="Predict across walking speeds, each from its neighbour.")
def sweep(
    speeds: Annotated[
        str, typer.Option("--speeds", help="start:stop:step (stop included) or a list, m/s.")
    ],
    out: Annotated[str, typer.Option("--out", help="Sweep folder (created or resumed).")],
    mass: Mass = 68.8,
    height: Height = 1.77,
    sex: Sex = "male",
    criterion: Criterion = DEFAULT_PRESET,
    seed: Annotated[int, typer.Option("--seed", help="Random start.", rich_help_panel=SOLVER)] = 0,
    nodes: Nodes = 20,
    restarts: Restarts = 1,
    max_iter: MaxIter = 800,
    strength: Strength = None,
    limits: Range = None,
    added_mass: AddedMass = None,
    leg_length: LegLength = None,
    full_cycle: FullCycle = False,
    equal_steps: EqualSteps = False,
) -> None:
    """Predict one gait cycle at each speed with T and Td predicted, each started from its
    solved neighbour, and write DIR/sweep.csv (T, Td, stride length, cadence, criterion, gait
    checks), DIR/sweep.png (against published adult relations) and one predict folder per speed
    in DIR/speeds/. Rerunning the same command resumes: a speed folder that cannot be read or
    whose arrays are not its summary's is solved again, one holding another speed's or
    problem's prediction is refused. Exit code 0
    if every speed converged and walks, 1 if not, 2 for bad input, 3 if the folder could not
    be written, 130 on Ctrl-C (finished speeds are kept)."""
    from walk3d.campaign.sweep import SweepMismatch, parse_speeds, run_sweep
    from walk3d.problem.descriptors import first_guess
    from walk3d.problem.settings import available_cores

    try:
        values = parse_speeds(speeds)
    except ValueError as exc:
        fail(str(exc))
    check_output_folder(out, replaces="sweep.json")
    for name in ("sweep.json", "sweep.csv", "sweep.png"):  # none a device or FIFO: refused now
        check_output_file(f"{out}/{name}")
    t, td = first_guess(float(values[0]), height) if 1.0 <= height <= 2.4 else (1.0, 0.1)
    settings = settings_from_options(
        criterion, "ipopt", seed, speed=float(values[0]), period=t, double_support=td,
        free=("period", "double_support"), mass=mass, height=height, sex=sex, nodes=nodes,
        threads=min(available_cores(), 64), restarts=restarts, max_iter=max_iter,
        **what_if.changes_option(strength, limits, added_mass, full_cycle, leg_length, equal_steps),
    )  # fmt: skip
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    columns = (TextColumn("{task.description}"), BarColumn(), TextColumn("{task.completed}/"
               "{task.total} speeds"), TimeElapsedColumn())  # fmt: skip
    try:
        with Progress(*columns, console=console, transient=True) as bar, warning_lines():
            task = bar.add_task("walk3d sweep", total=len(values))

            def progress(message: str, done: int, total: int) -> None:
                bar.update(task, completed=done, description=f"walk3d sweep: {message}"[:80])

            report = run_sweep(settings, values, out, seed=seed, on_progress=progress)
    except SweepMismatch as exc:
        fail(str(exc))
    except OSError as exc:
        from walk3d.io.errors import OutputWriteError

        fail(str(OutputWriteError(out, exc)), code=EXIT_WRITE)
    from rich.table import Table

    t = Table(title=f"walk3d sweep -> {out}")
    for col in ("V m/s", "T s", "Td s", "stride m", "cadence /min", "published", "converged",
                "walks", "start"):  # fmt: skip
        t.add_column(col)
    for r in report.rows:
        t.add_row(f"{r['speed']:.2f}", f"{r['period']:.3f}", f"{r['double_support']:.3f}",
                  f"{r['stride_length']:.3f}", f"{r['cadence']:.1f}",
                  f"{r['published_cadence']:.1f}", "yes" if r["converged"] else "NO",
                  "yes" if r["looks_like_walking"] else "NO", r["start"])  # fmt: skip
    console.print(t)
    tries = f", {report.tries} second-pass tries" if report.tries else ""
    console.print(
        f"{report.ran} speeds solved, {report.skipped} resumed{tries} "
        f"({report.wall_time_s:.0f} s); "
        f"table {out}/sweep.csv, figure {out}/sweep.png"
    )
    if not all(r["converged"] and r["looks_like_walking"] for r in report.rows):
        raise typer.Exit(1)
