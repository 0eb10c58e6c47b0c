"""``walk3d atlas``: build and list the atlas of starts (:mod:`walk3d.solve.atlas`)."""

from __future__ import annotations

from typing import Annotated

import typer

from walk3d.cli.common import EXIT_WRITE, app, console, fail
from walk3d.cli.warning_lines import warning_lines
from walk3d.model.terms import DEFAULT_PRESET

atlas_app = typer.Typer(no_args_is_help=True, help="The atlas of walk3d's own solutions that "
                        "predictions start from (docs/starts.md).")  # fmt: skip
app.add_typer(atlas_app, name="atlas", short_help="The atlas of starts: build it, list its files.")


@atlas_app.command("build", short_help="Sweep the reference subject and write atlas files.")
def build(
    work: Annotated[str, typer.Option("--work", help="Folder of the sweeps (created or resumed).")],
    sex: Annotated[str, typer.Option("--sex", help="male, female or both.")] = "both",
    criterion: Annotated[
        str, typer.Option("--criterion", help="Named presets, comma-separated.")
    ] = DEFAULT_PRESET,
    speeds: Annotated[
        str, typer.Option("--speeds", help="Reference-subject speeds, start:stop:step, m/s.")
    ] = "0.4:2.2:0.1",  # campaign.atlas.ATLAS_SPEEDS (that module loads CasADi)
    out: Annotated[
        str | None,
        typer.Option("--out", help="Atlas folder (default: the package's)."),
    ] = None,
    seed: Annotated[int, typer.Option("--seed", help="Random start of the first speed.")] = 0,
) -> None:
    """Sweep the reference subject (68.8 kg, 1.77 m) over speed with T and Td predicted, for
    each sex and preset, and write one atlas file each from the speeds that walk. Rerunning
    resumes the sweeps. Exit code 0 when every file was written, 2 for bad input, 3 if a file
    could not be written."""
    from walk3d.campaign.atlas import build_atlas, check_atlas_paths
    from walk3d.campaign.sweep import SweepMismatch, parse_speeds
    from walk3d.model import terms

    sexes = ("male", "female") if sex == "both" else (sex,)
    presets = tuple(p.strip() for p in criterion.split(",") if p.strip())
    if any(x not in ("male", "female") for x in sexes):
        fail(f"--sex {sex}: expected male, female or both")
    if not presets or any(terms.preset_name(p) is None for p in presets):
        fail(f"--criterion {criterion}: expected named presets ({', '.join(terms.PRESETS)})")
    try:
        parse_speeds(speeds)
        check_atlas_paths(work, out, [f"{sx}-{p}" for sx in sexes for p in presets])
    except ValueError as exc:
        fail(str(exc))
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    with Progress(TextColumn("{task.description}"), BarColumn(), TimeElapsedColumn(),
                  console=console, transient=True) as bar, warning_lines():  # fmt: skip
        for sx in sexes:
            for preset in presets:
                task = bar.add_task(f"atlas {sx} {preset}", total=None)

                def progress(msg: str, done: int, total: int, task=task, sx=sx, p=preset) -> None:
                    bar.update(task, completed=done, total=total,
                               description=f"atlas {sx} {p}: {msg}"[:80])  # fmt: skip

                try:
                    path, n, of = build_atlas(sx, preset, work, speeds, out, seed, progress)
                except (ValueError, SweepMismatch) as exc:
                    fail(str(exc))
                except OSError as exc:
                    fail(f"could not write the atlas: {exc}", code=EXIT_WRITE)
                console.print(f"{path}: {n} of {of} speeds walk", markup=False)


@atlas_app.command("show", short_help="List the package's atlas files.")
def show(
    check: bool = typer.Option(
        True, "--check/--no-check", help="Check that each entry walks (a few seconds)."
    ),
) -> None:
    """List the package's atlas files: sex, preset, speeds and Td/T, solve revision, the entries
    with a handover optimum (and with a primal-dual start) for the one-solve default, those with
    optima at other periods (for a given T), how many of the free-landing and handover optima
    look like walking, and whether this walk3d can use them; a file that is not an atlas
    (damaged, stray) is flagged in its row."""
    import numpy as np
    from rich.table import Table

    from walk3d.solve.atlas import ATLAS_DIR, load_periods, load_warm, read_atlas

    t = Table(title=f"walk3d atlas ({ATLAS_DIR})")
    cols = ("sex", "preset", "speeds m/s", "Td/T", "entries", "handover (warm)", "other periods",
            "walk (handover)", "revision", "usable")  # fmt: skip
    for col in cols:
        t.add_column(col)
    for path in sorted(ATLAS_DIR.glob("*.json")):
        sex, _, preset = path.stem.partition("-")
        try:
            a = read_atlas(path)
        except (ValueError, OSError) as exc:  # another format, damaged, or a stray file
            why = " ".join(str(exc).split())
            t.add_row(sex, preset or "-", *["-"] * 7, f"no: not a usable atlas ({why})")
            continue
        ho = 0 if a.x_handover is None else int(np.isfinite(a.x_handover).all(axis=1).sum())
        warm, levels = load_warm(a), load_periods(a)
        other = "-" if levels is None else ", ".join(
            f"{f:g} T: {int(np.isfinite(levels['z'][:, m, 0]).sum())}"
            + _half_way(levels["reached"][:, m], f)
            for m, f in enumerate(levels["factors"]))  # fmt: skip
        frac = a.double_supports / a.periods
        t.add_row(sex, preset, f"{a.speeds[0]:.2f}-{a.speeds[-1]:.2f}",
                  f"{frac.min():.3f}-{frac.max():.3f}", str(len(a.speeds)),
                  f"{ho} ({0 if warm is None else warm['speeds'].size})", other,
                  _walking(a, ho) if check else "-", str(a.solve_revision),
                  "yes" if a.current else "no: rebuild")  # fmt: skip
    console.print(t)


def _walking(atlas, handover: int) -> str:
    """``k (m)``: how many free-landing (and handover) optima look like walking, with the
    speeds of those that do not."""
    from walk3d.campaign.atlas_checks import walking_entries

    try:
        free, ho = walking_entries(atlas), walking_entries(atlas, handover=True)
    except ValueError as exc:  # a file in atlas format for an unknown sex or preset
        return f"cannot check: {' '.join(str(exc).split())}"
    out = f"{int(free.sum())} ({int(ho.sum())} of {handover})"
    fails = [f"{v:.1f}" for v, ok in zip(atlas.speeds, free, strict=True) if not ok]
    return out + (f"; not: {', '.join(fails)} m/s" if fails else "")


def _half_way(reached, factor: float) -> str:
    """`` (k half-way)`` when k levels were kept at the half-way factor, else empty."""
    import numpy as np

    k = int((np.isfinite(reached) & ~np.isclose(reached, factor)).sum())
    return f" ({k} half-way)" if k else ""
