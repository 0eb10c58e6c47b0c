"""One prediction end to end: settings -> solve -> full-cycle evaluation -> result folder."""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

import numpy as np

from walk3d.body.model import BodyModel
from walk3d.constants import __version__
from walk3d.io.errors import OutputWriteError
from walk3d.model import terms
from walk3d.problem import layout, similarity
from walk3d.problem.settings import PredictionSettings, body_for
from walk3d.results.asymmetry import asymmetry_or_none
from walk3d.results.evaluate import evaluate_cycle, make_prediction
from walk3d.results.gait_checks import realism_figures, walking_checks
from walk3d.results.prediction import PredictedCycle, check_result_folder, save_prediction
from walk3d.solve import SOLVE_REVISION, blas
from walk3d.solve.landing import LANDING, landing_of


def _solved_as(settings: PredictionSettings) -> dict:
    """The reference subject whose problem was solved (:mod:`walk3d.problem.similarity`)."""
    return {
        "mass_kg": similarity.REFERENCE_MASS_KG,
        "height_m": similarity.REFERENCE_HEIGHT_M,
        "length_scale": similarity.length_scale(settings),
        "note": "stages[].objective and max_constraint_violation are in this problem's units "
        "(lengths divided by length_scale); everything else is the subject's",
    }


def descriptor_summary(settings: PredictionSettings) -> dict:
    """Speed, period, double support, stride length (SI), cadence (steps/min), stance fraction,
    and which of them were ``predicted``."""
    g = settings.gait
    return {"speed": g.speed, "period": g.period, "double_support": g.double_support,
            "stride_length": g.stride_length, "cadence": 120.0 / g.period,
            "stance_fraction": 0.5 + g.double_support / g.period,
            "predicted": list(g.free)}  # fmt: skip


def with_predicted(
    settings: PredictionSettings, found: dict[str, float], handover: bool | None = None
) -> PredictionSettings:
    """The settings with the predicted descriptors in place of their first guess (still listed
    in ``gait.free``) and, when given, the ``handover`` the cycle was solved with, for
    evaluating and reporting the cycle."""
    if handover is not None and handover != settings.model.handover:
        model = settings.model.model_copy(update={"handover": handover})
        settings = settings.model_copy(update={"model": model})
    if not settings.gait.free:
        return settings
    gait = settings.gait.model_copy(
        update={k: v for k, v in found.items() if k in settings.gait.free}
    )
    return settings.model_copy(update={"gait": gait})


def _start_of(stages: list[dict]) -> str:
    """Where the solve started: the last stage's start, before any handover or full-cycle
    stage."""
    starts = [r.get("start", "standing") for r in stages
              if r.get("start") != LANDING and r.get("stage") != "full cycle"]  # fmt: skip
    return starts[-1] if starts else "standing"


def _predicted_by(settings: PredictionSettings, stages: list[dict]) -> dict:
    """How predicted descriptors were found: ``atlas`` (blended from the atlas's free-landing
    optima, :mod:`walk3d.solve.landing`) or ``solve``; nothing when none is predicted."""
    if not settings.gait.free:
        return {}
    atlas = bool(stages) and stages[-1].get("descriptors_from") == "atlas"
    return {"predicted_by": "atlas" if atlas else "solve"}


def _problem(full: bool, x: np.ndarray) -> str:
    if not full:
        return "half cycle"
    if np.size(x) != layout.N_XF:
        return "half cycle: the full-cycle solve did not run (the half cycle did not converge)"
    return "full cycle"


def summarize(
    settings: PredictionSettings,
    seed: int,
    outcome,
    ev,
    solver: str,
    full: bool = False,
) -> dict:
    """The JSON summary of a prediction (SI units, criteria exact, smoothed for reference).
    ``body_mass_kg`` includes any what-if added mass; forces per body weight use it.
    ``full``: whether the full-cycle problem was asked for (``problem`` says which one the cycle
    is; its ``X`` is ``coefficients.x``)."""
    mass = float(body_for(settings).mass)
    coefficients = {
        "layout": "walk3d.problem.layout: 15 Fourier series x 11 coefficients, then the "
        "half step width (m)"
        + (
            "; twice, X = [x_R, x_L], on the full cycle, x_L's width entry being the step "
            "shift d (m): right step V T / 2 + d, left V T / 2 - d"
            if np.size(outcome.x) == layout.N_XF
            else ""
        ),
        "x": [float(v) for v in outcome.x],
    }
    if getattr(outcome, "split", None) is not None:  # walk3d.contact.free_split
        coefficients["split"] = np.asarray(outcome.split, float).tolist()
    return {
        "walk3d_version": __version__,
        "solve_revision": SOLVE_REVISION,
        "solved_as": _solved_as(settings),
        "settings": settings.model_dump(),
        "descriptors": descriptor_summary(settings) | _predicted_by(settings, outcome.stages),
        "seed": seed,
        "start": _start_of(outcome.stages),
        "landing": landing_of(outcome),
        "method": solver,
        "converged": bool(outcome.converged),
        "status": outcome.status,
        "iterations": outcome.iterations,
        "attempts": outcome.attempts,
        "wall_time_s": round(outcome.wall_time_s, 3),
        "stages": outcome.stages,
        "compiled_derivatives": list(outcome.compiled_derivatives),
        "blas": blas.status().describe(),
        "criterion_preset": terms.preset_name(settings.model.criterion),
        "objective": ev.criteria,
        "objective_smoothed": ev.criteria_smoothed,
        "max_constraint_violation": outcome.max_constraint_violation,
        "double_support_contact_residual_m": ev.contact_residual_m,
        "root_switch_continuity_residual_m": ev.continuity_residual_m,
        "body_mass_kg": mass,
        "stride_length_m": ev.stride_length_m,
        "stride_length_target_m": settings.gait.stride_length,
        "step_width_m": ev.step_width_m,
        "cycle_violations": ev.cycle_violations,
        "asymmetry": asymmetry_or_none(ev.prediction_arrays, mass),
        "problem": _problem(full, outcome.x),
        "coefficients": coefficients,
        "gait_checks": walking_checks(
            ev.prediction_arrays,
            settings.gait.period,
            settings.gait.double_support,
            mass,
            settings.gait.speed,
        )
        | realism_figures(ev.prediction_arrays, mass, ev.step_width_m),
    }


def predict(
    settings: PredictionSettings,
    seed: int = 0,
    solver: str = "ipopt",
    out_dir: str | Path | None = None,
    figure: bool = True,
    on_stage: Callable[[str], None] | None = None,
    warm_from: np.ndarray | None = None,
    animate: bool = False,
    on_outcome: Callable[[object], None] | None = None,
) -> PredictedCycle:
    """Predict one gait cycle; write the result folder when ``out_dir`` is given.
    ``warm_from``: another prediction's decision vector (the subject's, ``summary.json``'s
    ``coefficients``) to start from instead of standing (:func:`walk3d.solve.starts.solve_warm`;
    the settings must predict a descriptor). ``animate``: also write ``animation.mp4``
    (:func:`write_result`). ``on_outcome``: called with the solve's
    :class:`~walk3d.solve.ipopt.SolveOutcome` (its multipliers: ``walk3d track``)."""
    from walk3d.solve import run_solver
    from walk3d.solve.landing import solve_with_landing
    from walk3d.solve.starts import solve_warm

    if out_dir is not None:
        check_result_folder(out_dir)
    warm = threading.Thread(target=_warm_up_plots, name="walk3d-plots", daemon=True)
    if out_dir is not None and figure:
        warm.start()
    if warm_from is None:

        def first(given: PredictionSettings):
            return run_solver(given, seed, solver, on_stage=on_stage)
    else:
        x_ref = similarity.subject_x(layout.half_cycle_x(warm_from),
                                     1.0 / similarity.length_scale(settings))  # fmt: skip

        def first(given: PredictionSettings):
            return solve_warm(given, x_ref, solver, on_stage=on_stage)

    full = settings.model.full_cycle or settings.model.changes.one_sided
    half = (settings.replace(full_cycle=False, equal_steps=False,
                             changes=settings.model.changes.half_cycle())
            if full else settings)  # fmt: skip
    outcome = solve_with_landing(half, first, solver, on_stage,
                                 seed if warm_from is None else None)  # fmt: skip
    settings = with_predicted(settings, outcome.descriptors, outcome.handover)
    if full and outcome.converged:
        outcome = _full_cycle(settings, outcome, on_stage)
    if on_outcome:
        on_outcome(outcome)
    if on_stage:
        on_stage("evaluating the cycle")
    body = body_for(settings)
    ev = evaluate_cycle(body, settings, outcome.x, split=getattr(outcome, "split", None))
    summary = summarize(settings, seed, outcome, ev, solver, full)
    pred = make_prediction(ev.prediction_arrays, summary)
    if out_dir is not None:
        if warm.is_alive():
            warm.join()  # Matplotlib's font objects are not for two threads at once
        write_result(pred, out_dir, figure, body, animate=animate)
    return pred


def _full_cycle(settings: PredictionSettings, outcome, on_stage):
    """The full-cycle solve from the half cycle's converged ``outcome``: the merged outcome,
    whose ``x`` is the full cycle's ``X``."""
    from walk3d.solve.full_cycle import solve_full_cycle

    fc = solve_full_cycle(settings.replace(free=()), outcome, on_stage)
    return replace(outcome, x=fc.x, converged=fc.converged, status=fc.record["status"],
                   iterations=outcome.iterations + fc.record["iterations"],
                   wall_time_s=outcome.wall_time_s + fc.record["wall_time_s"],
                   stages=[*outcome.stages, fc.record], duals=None,
                   max_constraint_violation=fc.record["max_constraint_violation"])  # fmt: skip


def _warm_up_plots() -> None:
    """:func:`walk3d.plots.warm_up`, quietly: the figure itself reports any real failure."""
    try:
        from walk3d.plots import warm_up

        warm_up()
    except Exception:  # noqa: BLE001 (the summary figure later raises what matters)
        pass


def write_result(
    pred: PredictedCycle,
    out_dir: str | Path,
    figure: bool = True,
    body: BodyModel | None = None,
    animate: bool = False,
) -> Path:
    """Write the result folder atomically, with ``summary.png`` when ``figure`` and
    ``animation.mp4`` (two cycles, :func:`walk3d.plots.write_animation`) when ``animate``, all
    listed in the manifest; ``body`` is the body model ``pred`` was evaluated with (default:
    from its settings). ``report.html`` is added to the complete folder by
    :func:`walk3d.report.writer.write_report_or_warn`.

    Raises:
        ValueError: ``out_dir`` is an existing file or a folder of other files
            (:func:`check_result_folder`), an array walk3d could not read back
            (:func:`walk3d.results.readback.readable_arrays`), or ``animate`` and the summary's
            period is not the time axis's (:func:`walk3d.plots.animation.cycle_period`);
            nothing is written.
        OutputWriteError: the folder could not be written; nothing is left behind.
    """
    check_result_folder(out_dir)
    if animate:
        from walk3d.plots.animation import cycle_period

        cycle_period(pred)  # refused before anything is written

    def add_figure(folder: Path) -> None:
        from walk3d.plots import summary_figure, write_animation

        if figure:
            summary_figure(pred, folder / "summary.png")
        if animate:
            write_animation(pred, folder / "animation.mp4", body=body)

    try:
        extra = add_figure if figure or animate else None
        folder = save_prediction(pred, out_dir, extra=extra, body=body)
    except OSError as exc:
        raise OutputWriteError(out_dir, exc) from exc
    return folder
