"""``walk3d track``: walk3d's own problem, every constraint kept, with the criterion replaced
by the deviation from a measured gait and a small weight left on the criterion, so that the
tracked gait is the cheapest one close to the data (docs/tracking.md).

The measured side is :func:`walk3d.validation.target.tracking_target` (the quantities of
``walk3d validate``); :func:`tracking_spec` turns it into the ``track`` criterion term's target
(:class:`walk3d.model.tracking.Tracking`); :func:`track` solves and evaluates it as
``walk3d predict`` does, and :func:`tracking_rows` and :func:`binding` say how close it came and
which constraints held it back.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from walk3d.body.model import BodyModel
from walk3d.constants import G
from walk3d.decimals import decimal
from walk3d.model import terms
from walk3d.model.tracking import Tracking, fit_series
from walk3d.problem.settings import PredictionSettings, body_for
from walk3d.results.prediction import PredictedCycle
from walk3d.validation.compare import on_percent
from walk3d.validation.projection import joint_quaternion_from_angles
from walk3d.validation.target import TrackingTarget

__all__ = ["MISS_DEG", "RELAX", "TRACK_WEIGHT", "Tracked", "audit", "binding", "only_dofs",
           "relaxations", "track", "track_settings", "tracking_rows", "tracking_spec",
           "write_tracking"]  # fmt: skip

TRACK_WEIGHT = 100.0
"""Weight of the track term against the criterion's own (1): on the shared trials the criterion
is 7–11 % of the objective at the end, enough to choose among gaits near the data; 1000 moved
the Falisse tracking by under 0.2° (docs/tracking.md)."""
MISS_DEG = 3.0
"""A DoF tracked worse than this RMSE, deg, gets the constraints that bind there listed."""


RELAX = {
    "loop": ("loop_tolerance", 1.0, "m"),
    "foot-flat": ("foot_flat_tolerance", np.pi / 180, "deg"),
    "heel-rise": ("heel_rise", 1.0, "of stance"),
}
"""``--relax`` names: the settings field each sets, the factor to SI, and the unit given."""


def relaxations(items: list[str]) -> dict[str, float]:
    """Settings fields from ``--relax NAME=VALUE`` items (:data:`RELAX`; ``loop=0.03,foot-flat=20``
    also). Raises ValueError with one line for an unknown name, a bad or repeated value."""
    out: dict[str, float] = {}
    for part in (p.strip() for item in items for p in str(item).split(",")):
        name, eq, value = part.partition("=")
        if name.strip() not in RELAX or not eq:
            raise ValueError(f"--relax takes NAME=VALUE with NAME one of {', '.join(RELAX)}; "
                             f"got {part!r}")  # fmt: skip
        field, factor, unit = RELAX[name.strip()]
        v = decimal(value)  # float() would read 1_0 as 10
        if math.isnan(v) and value.strip().lower() != "nan":
            raise ValueError(f"--relax {name}: {value!r} is not a number ({unit})")
        if not np.isfinite(v) or v < 0:
            raise ValueError(f"--relax {name} must be a finite number >= 0 ({unit}), got {value}")
        if field in out:
            raise ValueError(f"--relax {name} is given twice")
        out[field] = v * factor
    return out


def only_dofs(target: TrackingTarget, names: list[str]) -> TrackingTarget:
    """``target`` with only the DoFs ``names`` measured (a DoF name, or one without its side
    suffix for both sides: ``knee_flexion``). Raises ValueError for no name, a name that is not
    a DoF or that the target does not measure."""
    from dataclasses import replace

    if not names:
        raise ValueError("--only names no DoF (e.g. knee_flexion)")
    keep = np.zeros(len(target.dof_names), dtype=bool)
    for name in names:
        hit = [i for i, d in enumerate(target.dof_names) if name in (d, d[:-2])]
        if not hit:
            raise ValueError(f"--only: {name!r} is not a DoF (e.g. knee_flexion, hip_flexion_r)")
        if not target.angle_mask[hit].any():
            raise ValueError(f"--only: the trial does not measure {name}")
        keep[hit] = True
    return replace(target, angle_mask=np.asarray(target.angle_mask) & keep)


def tracking_spec(target: TrackingTarget, body: BodyModel) -> Tracking:
    """The ``track`` term's target from a measured cycle: each measured DoF's coordinate
    ``2 sin(θ/2)`` (hinges, ankle axes) or twice the joint quaternion's vector part along the
    axis (ball joints), as a Fourier series over the cycle from right heel strike."""
    tau = np.zeros_like(target.angles)
    i = 0
    for joint in body.joints:
        cols = slice(i, i + joint.n_dof)
        if joint.kind == "ball":
            q = joint_quaternion_from_angles(joint, target.angles[:, cols])
            q = q * np.where(q[:, :1] < 0, -1.0, 1.0)  # w ≥ 0, as walk3d's coordinates
            tau[:, cols] = 2.0 * q[:, 1:] @ np.asarray(joint.axes, dtype=float).T
        else:
            tau[:, cols] = 2.0 * np.sin(target.angles[:, cols] / 2.0)
        i += joint.n_dof
    keep = target.percent < 100.0  # 100 % repeats 0 %
    coef = fit_series(target.percent[keep] / 100.0, tau[keep])
    return Tracking(coefficients=tuple(map(tuple, coef)),
                    weights=tuple(float(m) for m in target.angle_mask),
                    source=target.source)  # fmt: skip


def track_settings(
    target: TrackingTarget,
    *,
    mass: float,
    height: float,
    sex: str,
    criterion: str = terms.DEFAULT_PRESET,
    weight: float = TRACK_WEIGHT,
    **options,
) -> PredictionSettings:
    """Settings that track ``target``: V, T and Td from it (``options`` may give them), the
    ``criterion`` plus ``track`` at ``weight``. Raises ValueError when the target lacks a
    descriptor that is not given."""
    gait = {"speed": target.speed, "period": target.period,
            "double_support": target.double_support}  # fmt: skip
    given = {k: options.pop(k, None) for k in list(gait)}
    gait.update({k: v for k, v in given.items() if v is not None})
    missing = [k for k, v in gait.items() if v is None]
    if missing:
        raise ValueError(f"{target.source}: no {', '.join(missing)} in the trial; give "
                         f"{', '.join('--' + k.replace('_', '-') for k in missing)}")  # fmt: skip
    s = PredictionSettings(**gait, mass=mass, height=height, sex=sex, **options)
    spec = tracking_spec(target, body_for(s))
    weights = {**terms.parse(criterion), "track": weight}
    return s.replace(criterion=",".join(f"{k}={w:g}" for k, w in weights.items()),
                     tracking=spec)  # fmt: skip


@dataclass(frozen=True)
class Tracked:
    """A tracking's outcome: the cycle, the table of how close it came, and the constraints
    that bind where it missed."""

    prediction: PredictedCycle
    rows: list[dict]
    binding: list[dict]


def tracking_rows(pred: PredictedCycle, target: TrackingTarget) -> list[dict]:
    """RMSE per measured DoF (deg, as ``walk3d validate`` aligns a prediction) and per measured
    ground-reaction component of the right foot (N/kg), with the peak of each series."""
    angles = on_percent(pred, np.asarray(pred.joint_angle))
    rows = []
    for i, dof in enumerate(target.dof_names):
        if target.angle_mask[i]:
            d = np.degrees(angles[:, i] - target.angles[:, i])
            rows.append({"quantity": dof, "unit": "deg", "rmse": float(np.sqrt(np.mean(d**2))),
                         "max_abs": float(np.max(np.abs(d)))})  # fmt: skip
    if target.grf is not None:
        force = _aligned_grf(pred)
        for k, axis in enumerate(("fore-aft", "vertical", "lateral")):
            if target.grf_mask[0, k]:
                d = (force[:, k] - target.grf[:, 0, k]) * G
                rows.append({"quantity": f"grf_r {axis}", "unit": "N/kg",
                             "rmse": float(np.sqrt(np.mean(d**2))),
                             "max_abs": float(np.max(np.abs(d)))})  # fmt: skip
    return rows


def _aligned_grf(pred: PredictedCycle) -> np.ndarray:
    """(101, 3) the right foot's ground reaction in body weights."""
    mass = float(pred.summary.get("body_mass_kg") or np.sum(pred.segment_mass))
    return on_percent(pred, np.asarray(pred.grf_force)[:, 0, :]) / (mass * G)


def binding(outcome: object, settings: PredictionSettings, top: int = 8) -> list[dict]:
    """The constraints with the largest multipliers at the end of the solve (``outcome``, a
    :class:`~walk3d.solve.ipopt.SolveOutcome` with multipliers): node rows by kind, summed over
    the nodes (``nodes`` lists where), and variable bounds. The lifting rows ``Y = A x`` are
    definitions, not constraints of the motion, and are left out."""
    from walk3d.problem import similarity
    from walk3d.solve.solver import build_solver

    duals = getattr(outcome, "duals", None)
    if not duals:
        return []
    ref, _ = similarity.reference_problem(settings)
    solver = build_solver(ref)
    rows = solver.stage_rows["free" if settings.gait.free else "full"]
    names = [*np.array(solver.layout.g_names(), dtype=object)[rows],
             *solver.layout.z_names(solver.body.dof_names)]  # fmt: skip
    lam = np.concatenate([np.ravel(duals["lam_g"]), np.ravel(duals["lam_x"])])
    groups: dict[str, dict] = {}
    for name, value in zip(names, lam, strict=True):
        if value == 0 or name.startswith(("lift ", "x ", "slack ")):
            continue
        kind, _, rest = name.partition(" ")
        node, _, what = rest.partition(" ")
        key = what if kind in ("node", "Y") else name
        g = groups.setdefault(key, {"kind": "bound" if kind == "Y" else "row", "name": key,
                                    "multiplier": 0.0, "nodes": set()})  # fmt: skip
        g["multiplier"] += abs(float(value))
        if kind in ("node", "Y"):
            g["nodes"].add(int(node))
    out = sorted(groups.values(), key=lambda g: -g["multiplier"])[:top]
    return [g | {"nodes": " ".join(map(str, sorted(g["nodes"])))} for g in out]


def track(
    target: TrackingTarget,
    *,
    mass: float,
    height: float,
    sex: str,
    seed: int = 0,
    on_stage: Callable[[str], None] | None = None,
    **options,
) -> Tracked:
    """Track ``target`` (:func:`track_settings`'s settings) and evaluate it: the cycle, its
    :func:`tracking_rows` and, when a DoF misses by more than :data:`MISS_DEG`, the
    :func:`binding` constraints."""
    from walk3d.pipeline import predict

    settings = track_settings(target, mass=mass, height=height, sex=sex, **options)
    kept: dict = {}
    pred = predict(settings, seed, on_stage=on_stage,
                   on_outcome=lambda o: kept.setdefault("outcome", o))  # fmt: skip
    return _tracked(pred, target, settings, kept.get("outcome"))


def write_tracking(
    target: TrackingTarget,
    settings: PredictionSettings,
    out_dir: str | Path,
    seed: int = 0,
    on_stage: Callable[[str], None] | None = None,
) -> Tracked:
    """Track with ``settings`` (:func:`track_settings`) and write the result folder with
    ``tracking.csv`` and, when a DoF missed, ``binding.csv``, both listed in its manifest."""
    from walk3d.io.atomic import atomic_write_text
    from walk3d.pipeline import predict
    from walk3d.report.writer import write_report_or_warn
    from walk3d.results.prediction import record_file

    kept: dict = {}
    pred = predict(settings, seed, out_dir=out_dir, on_stage=on_stage,
                   on_outcome=lambda o: kept.setdefault("outcome", o))  # fmt: skip
    tracked = _tracked(pred, target, settings, kept.get("outcome"))
    out = Path(out_dir)
    files = {"tracking.csv": _csv(tracked.rows, ("quantity", "unit", "rmse", "max_abs"))}
    if tracked.binding:
        files["binding.csv"] = _csv(tracked.binding, ("kind", "name", "multiplier", "nodes"))
    for name, text in files.items():
        atomic_write_text(out / name, text)
        record_file(out, name)
    write_report_or_warn(out)
    return tracked


def _csv(rows: list[dict], columns: tuple[str, ...]) -> str:
    lines = [",".join(columns)]
    for r in rows:
        lines.append(",".join(f"{r[c]:.6g}" if isinstance(r[c], float) else str(r[c])
                              for c in columns))  # fmt: skip
    return "\n".join(lines) + "\n"


def _tracked(pred, target, settings, outcome) -> Tracked:
    rows = tracking_rows(pred, target)
    missed = any(r["unit"] == "deg" and r["rmse"] > MISS_DEG for r in rows)
    return Tracked(pred, rows, binding(outcome, settings) if missed else [])


def _recorded(folder: Path) -> tuple[PredictionSettings, np.ndarray, np.ndarray | None]:
    """The settings, coefficients ``x`` and free split ``(K, 6)`` (or None) a complete result
    folder's summary records; DataFileError (one line) without usable settings, or without the
    half or full cycle's coefficients as finite numbers."""
    from walk3d.io.checks import finite_number, read_json_object
    from walk3d.io.errors import DataFileError
    from walk3d.problem import layout
    from walk3d.problem.settings import first_error, recorded_settings
    from walk3d.results.prediction import check_complete

    check_complete(folder)
    path = folder / "summary.json"
    summary = read_json_object(path, "walk3d summary")
    recorded = recorded_settings(summary)
    if not recorded:  # defaults would evaluate the coefficients of another problem
        raise DataFileError(path, "records no settings: not a walk3d summary")
    try:
        own = PredictionSettings(**recorded)
    except (TypeError, ValueError, AttributeError) as exc:
        raise DataFileError(path, f"unusable settings: {first_error(exc)}") from None
    coefficients = summary.get("coefficients")
    x = coefficients.get("x") if isinstance(coefficients, dict) else None
    if not isinstance(x, list) or len(x) not in (layout.N_X, layout.N_XF):
        raise DataFileError(path, f"coefficients.x is not a list of {layout.N_X} or "
                            f"{layout.N_XF} numbers (the half or full cycle's)")  # fmt: skip
    split = coefficients.get("split")
    k = own.model.split_terms
    if split is not None or k:
        flat = np.ravel(np.array(split if split is not None else [], dtype=object))
        if flat.size != 6 * k:
            raise DataFileError(path, f"coefficients.split is not {k} rows of 6 numbers "
                                "(model.split_terms)")  # fmt: skip
        split = np.array([finite_number(path, v, "each of coefficients.split") for v in flat])
    split = None if split is None or not split.size else split.reshape(-1, 6)
    return own, np.array([finite_number(path, v, "each of coefficients.x") for v in x]), split


def _evaluated(folder: str | Path, settings: PredictionSettings | None = None):
    """A result folder's cycle evaluated again from its coefficients, under ``settings`` (its
    own by default), with its settings; a DataFileError names the folder."""
    from walk3d.io.errors import DataFileError
    from walk3d.results.evaluate import evaluate_cycle

    try:
        own, x, split = _recorded(Path(folder))
    except DataFileError as exc:
        raise DataFileError(exc.path, f"{exc.reason} (in {folder})", exc.line) from None
    use = own if settings is None else settings.replace(**own.gait.model_dump())
    return evaluate_cycle(body_for(use), use, x, split=split), use


def audit(tracked: str | Path, predicted: str | Path) -> dict:
    """The cost audit (:mod:`walk3d.results.audit`) of a tracked gait against a prediction,
    both charged by the prediction's criterion: ``terms`` (per phase), ``limb_work`` and
    ``bursts`` for each, and the criterion's weighted totals."""
    from walk3d.results import audit as au

    ev_p, s_p = _evaluated(predicted)
    if s_p.model.tracking is not None:  # a tracking as the reference: its criterion alone
        weights = {k: w for k, w in terms.parse(s_p.model.criterion).items() if k != "track"}
        plain = s_p.replace(
            tracking=None,
            loop_tolerance=0.0,
            criterion=",".join(f"{k}={w:g}" for k, w in weights.items()),
        )
        ev_p, s_p = _evaluated(predicted, plain)
    model = s_p.model.model_copy(update={"tracking": None})
    ev_t, s_t = _evaluated(tracked, s_p.model_copy(update={"model": model}))
    out: dict = {"criterion": s_p.model.criterion, "terms": {}, "limb_work": {}, "bursts": {}}
    evs = {"tracked": (ev_t, s_t), "predicted": (ev_p, s_p)}
    g = s_p.gait
    out["terms"] = au.term_table({k: e for k, (e, _) in evs.items()}, s_p.model.criterion,
                                 g.period, g.double_support)  # fmt: skip
    body = body_for(s_p)
    for label, (e, s) in evs.items():
        gs = s.gait
        out["limb_work"][label] = au.limb_work(e, gs.period, gs.double_support)
        out["bursts"][label] = au.power_bursts(e, body.dof_names,
                                               tuple(j.name for j in body.joints), gs.period,
                                               gs.double_support)  # fmt: skip
        out[f"C_weighted {label}"] = e.criteria["C_weighted"]["total"]
    return out
