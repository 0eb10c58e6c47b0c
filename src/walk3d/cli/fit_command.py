"""``walk3d fit-criterion``: criterion weights fitted to measured trials (docs/fitting.md)."""

from __future__ import annotations

from typing import Annotated

import typer
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table

from walk3d.cli.common import (
    EXIT_WRITE,
    app,
    check_output_folder,
    console,
    fail,
    input_file,
    scheduler_option,
)
from walk3d.model.terms import DEFAULT_PRESET

MAX_GENERATIONS = 1000
"""CMA-ES generations of one fit: each predicts every trial per candidate, so more is weeks."""
MAX_POPSIZE = 1000
"""Candidates per generation (CMA-ES's default for a few weights is 6–8)."""


@app.command("fit-criterion", short_help="Fit criterion weights to measured trials (CMA-ES).")
def fit_criterion(
    trials: Annotated[
        str,
        typer.Argument(help="TOML file of the trials (docs/fitting.md).", callback=input_file),
    ],
    out: Annotated[str, typer.Option("--out", help="Fit folder (created or resumed).")],
    parameter: Annotated[
        list[str],
        typer.Option(
            "--parameter",
            help="A term whose weight is fitted, or a model option (heel_rise, load_ramp): name or "
            "name=low:high.",
        ),
    ],
    base: Annotated[
        str, typer.Option("--base", help="The criterion the weights start from.")
    ] = DEFAULT_PRESET,
    generations: Annotated[int, typer.Option("--generations", help="CMA-ES generations.")] = 6,
    popsize: Annotated[int, typer.Option("--popsize", help="Candidates per generation.")] = 8,
    descriptors: Annotated[
        list[str] | None,
        typer.Option("--descriptors", help="given and/or predicted T and Td (default: given)."),
    ] = None,
    hold_out: Annotated[
        list[str] | None,
        typer.Option("--hold-out", help="A trial scored, not fitted on (repeatable)."),
    ] = None,
    seed: Annotated[int, typer.Option("--seed", help="Seed of CMA-ES and the starts.")] = 0,
    workers: Annotated[
        int | None, typer.Option("--workers", help="Local worker processes (default: cores).")
    ] = None,
    scheduler: Annotated[
        str | None, typer.Option("--scheduler", help="A running Dask scheduler's address.")
    ] = None,
) -> None:
    """Fit criterion weights to measured trials with CMA-ES on Dask workers. Each candidate
    predicts every trial and is scored by the realism yardstick (1 = at the bar). Rerunning the
    same command resumes. Writes DIR/criterion.toml for walk3d predict --criterion."""
    from walk3d.fitting.run import fit_criterion as run
    from walk3d.fitting.search import FitMismatch
    from walk3d.fitting.search import parameter as make_parameter
    from walk3d.fitting.trials import read_trials
    from walk3d.io.errors import DataFileError
    from walk3d.model import terms

    if not 0 <= seed < 2**32:  # CMA-ES's seed range
        fail(f"--seed must be an integer in [0, 2**32 - 1], got {seed}")
    if not 1 <= generations <= MAX_GENERATIONS:
        fail(f"--generations must be an integer in [1, {MAX_GENERATIONS}], got {generations}")
    if not 2 <= popsize <= MAX_POPSIZE:
        fail(f"--popsize must be an integer in [2, {MAX_POPSIZE}], got {popsize}")
    from walk3d.campaign.runner import MAX_WORKERS

    if workers is not None and not 1 <= workers <= MAX_WORKERS:
        fail(f"--workers must be an integer in [1, {MAX_WORKERS}], got {workers}")
    try:
        base = terms.canonical(base)
        if base in terms.BASES:
            raise ValueError(f"--base {base} has no weights to fit; use a preset such as natural")
        params = [make_parameter(p, base) for p in parameter]
        fit_trials = read_trials(trials)
    except (ValueError, DataFileError) as exc:
        fail(" ".join(str(exc).split()))
    check_output_folder(out)
    scheduler_option(scheduler)
    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
               TimeElapsedColumn())  # fmt: skip
    with Progress(*columns, console=console, transient=True) as progress:
        bar = progress.add_task("fitting", total=None)

        def on_progress(done: int, total: int, text: str) -> None:
            progress.update(bar, completed=done, total=total, description=text)

        try:
            result = run(fit_trials, params, out, base=base, generations=generations,
                         popsize=popsize, seed=seed, modes=tuple(descriptors or ("given",)),
                         held_out=tuple(hold_out or ()), workers=workers, scheduler=scheduler,
                         on_progress=on_progress)  # fmt: skip
        except (FitMismatch, ValueError) as exc:
            fail(" ".join(str(exc).split()))
        except OSError as exc:
            fail(f"cannot write {out}: {exc.strerror or exc}", code=EXIT_WRITE)
    table = Table(title=f"criterion fitted in {out}")
    for col in ("trial", "start", "best", ""):
        table.add_column(col)
    for key in result.per_trial["start"]:
        held = key.split("/")[0] in result.held_out
        start, best = result.per_trial["start"][key], result.per_trial["best"][key]
        table.add_row(key, f"{start:.3f}", f"{best:.3f}", "held out" if held else "")
    console.print(table)
    weights = terms.parse(result.best)
    console.print("best: " + ", ".join(f"{k}={weights[k]:g}" for k in sorted(weights)))
    console.print(f"mean score {result.best_score:.3f} (start {result.start_score:.3f}); "
                  f"walk3d predict --criterion {out}/criterion.toml")  # fmt: skip
