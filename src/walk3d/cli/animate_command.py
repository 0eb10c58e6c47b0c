"""``walk3d animate DIR``: an MP4 of the predicted walk (3D, side and front views)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from walk3d.cli.common import EXIT_WRITE, app, check_output_file, console, fail


@app.command(short_help="Write an MP4 of a result's walk: 3D, side and front views.")
def animate(
    pred_dir: Annotated[str, typer.Argument(help="Prediction folder (walk3d predict --out).")],
    cycles: Annotated[int, typer.Option("--cycles", help="Gait cycles shown.", min=1, max=50)] = 2,
    fps: Annotated[
        int, typer.Option("--fps", help="Frames per second (real speed).", min=1, max=120)
    ] = 30,
    out: Annotated[
        str | None, typer.Option("--out", help="MP4 file (default: DIR/animation.mp4).")
    ] = None,
) -> None:
    """Write an H.264 MP4 of the walk in DIR at real speed: the body as sticks in a 3D view,
    a side view and a front view, each foot's ground reaction as an arrow from its centre of
    pressure (1 m per body weight) while loaded, CYCLES gait cycles, each a stride further on.
    Written aside and then moved into place (a deleted DIR/animation.mp4 is made again), and
    listed in DIR's manifest. A result that did not converge or does not walk is labelled in
    every frame and named in a warning line. An existing --out is replaced only if walk3d wrote
    it (the comment in its metadata, or a view its folder's manifest lists). Exit code 2 for a
    folder that is not a complete result (or whose summary's period is not its time axis's
    span) or a bad --out (such a user's file too), 3 if the
    video cannot be written (nothing is changed)."""
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
    )

    from walk3d.cli.labels import warn_if_invalid
    from walk3d.io.errors import DataFileError
    from walk3d.outputs import write_errors
    from walk3d.plots.animation import cycle_period
    from walk3d.plots.video import is_walk3d_video, write_animation
    from walk3d.results.osim_model import prediction_body
    from walk3d.results.prediction import load_result
    from walk3d.results.views import is_listed_view, write_view

    folder = Path(pred_dir)
    target = Path(out) if out is not None else folder / "animation.mp4"
    kind = ("walk3d video", lambda p: is_walk3d_video(p) or is_listed_view(p))  # not a user's
    check_output_file(str(target), suffix=".mp4", home=folder, existing=kind)
    inside = target.parent.resolve() == folder.resolve() and target.name == "animation.mp4"
    try:
        pred = load_result(folder, remade=(target.name,) if inside else ())
        body = prediction_body(pred)
        cycle_period(pred)  # a summary period that is not the time axis's: refused before work
    except (OSError, DataFileError, ValueError, KeyError) as exc:
        fail(f"cannot animate {pred_dir}: {' '.join(str(exc).split())}")
    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
               TimeElapsedColumn())  # fmt: skip
    try:
        with Progress(*columns, console=console, transient=True) as bar:
            task = bar.add_task("walk3d: rendering", total=None)

            def step(i: int, n: int) -> None:
                bar.update(task, completed=i, total=n)

            def render(path: Path) -> None:
                write_animation(pred, path, cycles=cycles, fps=fps, body=body, on_frame=step)

            if inside:
                write_view(folder, target.name, render)
            else:
                with write_errors(target):
                    render(target)
    except OSError as exc:
        fail(" ".join(str(exc).split()), code=EXIT_WRITE)
    except ValueError as exc:
        fail(f"cannot animate {pred_dir}: {' '.join(str(exc).split())}")
    console.print(f"walk3d animate -> {target} ({target.stat().st_size / 1e6:.2f} MB, "
                  f"{cycles} cycles at {fps} fps)", markup=False, highlight=False)  # fmt: skip
    warn_if_invalid(pred_dir, pred.summary)  # also written in the video's frames
