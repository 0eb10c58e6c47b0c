"""``walk3d atlas build``: the atlas files of :mod:`walk3d.solve.atlas`, made by ``walk3d sweep``.

For a sex and a criterion preset, the reference subject (68.8 kg, 1.77 m) is swept over speed
with the period and double support predicted, from standing at 1.3 m/s and outwards from
neighbours (:mod:`walk3d.campaign.sweep`); every speed that converged and looks like walking
becomes an entry. Only walk3d's own predictions go in, never measured data.

Other periods. A prediction with T and Td given starts from the atlas entries at its speed,
whose optima are at walk3d's own, predicted T and Td. When the given period differs by some
percent, the optimum moves far (a period 10 % longer raised the criterion by 29 % at 1.7 m/s),
and the solve from the entries' primal-dual points took 41 iterations. Blending two optima that
bracket the given period, as two speeds are blended, took 18 (docs/solver.md). So each entry
with a primal-dual point (:func:`write_warm`) also gets the handover
optimum at its period and double support times each of :data:`PERIOD_FACTORS`: Td scales with T,
so the double-support nodes of the regular grid, and with them the stage's rows, stay the
entry's.
"""

from __future__ import annotations

import datetime as dt
import json
from collections.abc import Callable, Collection
from dataclasses import replace
from pathlib import Path

import casadi as ca
import numpy as np

from walk3d.constants import __version__
from walk3d.io.atomic import atomic_path, atomic_write_text
from walk3d.model import terms
from walk3d.problem import descriptors, layout, similarity
from walk3d.problem.settings import PredictionSettings
from walk3d.solve import SOLVE_REVISION
from walk3d.solve.atlas import ATLAS_DIR, FORMAT, POINT_KEYS, atlas_path, settings_key

__all__ = ["ATLAS_SPEEDS", "PERIOD_FACTORS", "add_handover", "atlas_settings", "build_atlas",
           "check_atlas_paths", "fingerprint", "write_atlas", "write_periods",
           "write_warm"]  # fmt: skip

ATLAS_SPEEDS = "0.4:2.2:0.1"
"""Reference-subject speeds, m/s: subjects of 1.5-2.0 m walking 0.43-2.0 m/s map inside
(V / √(h / 1.77 m)), slow clinical walkers to fast walking."""


def atlas_settings(sex: str, criterion: str, nodes: int = 20) -> PredictionSettings:
    """The reference subject's settings the atlas of ``sex`` and ``criterion`` solves: the
    descriptors predicted with the free landing (the first of :mod:`walk3d.solve.landing`'s two
    solves, which the atlas starts), started from standing (an atlas is not built from an
    atlas)."""
    t, td = descriptors.first_guess(1.3, similarity.REFERENCE_HEIGHT_M)
    return PredictionSettings(
        mass=similarity.REFERENCE_MASS_KG, height=similarity.REFERENCE_HEIGHT_M, sex=sex,
        criterion=criterion, speed=1.3, period=t, double_support=td, free=descriptors.NAMES,
        nodes=nodes, start="standing", handover=False,
    )  # fmt: skip


def fingerprint(settings: PredictionSettings, entry: dict) -> dict:
    """The given-descriptor NLP's objective and constraint norm at ``entry``'s start (its
    coefficients at its speed, period and double support; W0 and slacks made consistent by
    :func:`walk3d.solve.ipopt.full_stage_start`). Any change of the model, the criterion or
    the rows changes them."""
    from walk3d.solve.ipopt import build_solver, full_stage_start, lifted_z
    from walk3d.solve.solver import forget_solvers

    given = settings.replace(speed=entry["speed"], period=entry["period"],
                             double_support=entry["double_support"], free=())  # fmt: skip
    solver = build_solver(given)
    z = full_stage_start(solver, lifted_z(solver, np.asarray(entry["x"], dtype=float)))
    prob = solver.nlp_problem("full")
    f, g = ca.Function("walk3d_fingerprint", [prob["x"]], [prob["f"], prob["g"]])(z)
    forget_solvers()
    return {"speed": entry["speed"], "objective": float(f),
            "constraint_norm": float(np.linalg.norm(np.array(g)))}  # fmt: skip


ENTRY_TOLERANCE = 1e-6
"""Largest constraint violation of an entry at its start: IPOPT converges to 1e-8 (``tol``),
so an entry that is its problem's optimum is well within it."""


def violation(settings: PredictionSettings, entry: dict) -> float:
    """The free-descriptor NLP's largest constraint violation (bounds on ``z`` and ``g``) at
    ``entry``'s start: at most :data:`ENTRY_TOLERANCE` when the entry is that problem's optimum."""
    from walk3d.solve.ipopt import build_solver, full_stage_start, lifted_z
    from walk3d.solve.progress import bound_violation

    t, td = entry["period"], entry["double_support"]
    trial = settings.replace(speed=entry["speed"], period=t, double_support=td)
    solver = build_solver(trial)
    z = full_stage_start(solver, lifted_z(solver, np.asarray(entry["x"], dtype=float), (t, td)))
    b = solver.nlp_bounds("free")
    g = np.array(solver.constraints(z)).ravel()
    return max(bound_violation(z, b.lbz, b.ubz), bound_violation(g, b.lbg, b.ubg))


def _entries(summaries: list[dict], preset: str) -> list[dict]:
    from walk3d.campaign.sweep import per_metre, walks

    return [{"speed": s["descriptors"]["speed"], "period": s["descriptors"]["period"],
             "double_support": s["descriptors"]["double_support"],
             "criterion_per_metre": per_metre(s, preset), "iterations": s["iterations"],
             "x": [float(f"{v:.12g}") for v in s["coefficients"]["x"]]}
            for s in summaries if walks(s)]  # fmt: skip


def check_atlas_paths(
    work_dir: str | Path, out_dir: str | Path | None, names: Collection[str]
) -> None:
    """Refuse, before any sweep, a ``work_dir`` that is a file, cannot be written or holds
    anything but sweep folders (:func:`walk3d.outputs.check_folder_of_folders`), and an
    ``out_dir`` (the package's atlas folder by default) that is a file or cannot be written, or
    where an atlas file of ``names`` (``sex-preset``) cannot be: ValueError, one line."""
    from walk3d.outputs import (
        check_folder_of_folders,
        check_output_file,
        check_output_folder,
        check_outside_results,
    )

    for option, folder in (("--work", work_dir), ("--out", out_dir)):
        if folder:
            check_outside_results(folder, option)
    check_folder_of_folders(work_dir, "--work", "sweep.json")
    root = check_output_folder(Path(out_dir) if out_dir else ATLAS_DIR, "--out")
    if any((root / name).exists() for name in ("summary.json", "manifest.json", "sweep.json")):
        raise ValueError(f"--out {root} is a walk3d result or sweep folder, not an atlas folder; "
                         "use a new folder")  # fmt: skip
    for name in names:
        check_output_file(root / f"{name}.json", "--out")


def build_atlas(
    sex: str,
    criterion: str,
    work_dir: str | Path,
    speeds: str = ATLAS_SPEEDS,
    out_dir: str | Path | None = None,
    seed: int = 0,
    on_progress: Callable[[str, int, int], None] | None = None,
) -> tuple[Path, int, int]:
    """Sweep (or resume the sweep in ``work_dir``) and write the atlas file of ``sex`` and the
    preset ``criterion`` to ``out_dir`` (the package's by default). Returns the file, the
    entries written and the speeds swept.

    Raises:
        ValueError: ``criterion`` is not a named preset, ``speeds`` does not parse, a folder
            is refused (:func:`check_atlas_paths`; all before the sweep), or no speed walked.
    """
    from walk3d.campaign.sweep import parse_speeds, run_sweep

    preset = terms.preset_name(criterion)
    if preset is None:
        raise ValueError(f"--criterion {criterion}: the atlas holds named presets only "
                         f"({', '.join(terms.PRESETS)})")  # fmt: skip
    grid = parse_speeds(speeds)
    check_atlas_paths(work_dir, out_dir, [f"{sex}-{preset}"])
    work = Path(work_dir) / f"{sex}-{preset}"
    run_sweep(atlas_settings(sex, preset), grid, work, seed, on_progress=on_progress)
    path, n = write_atlas(sex, preset, work, grid, out_dir, seed)
    add_handover(path, on_progress)
    write_periods(path, on_progress=on_progress)
    return path, n, len(grid)


def write_atlas(
    sex: str,
    preset: str,
    work: Path,
    grid: np.ndarray,
    out_dir: str | Path | None = None,
    seed: int = 0,
) -> tuple[Path, int]:
    """Write the atlas file of ``sex`` and ``preset`` from the sweep folder ``work`` (speeds
    ``grid``); returns the file and its number of entries."""
    from walk3d.campaign.sweep import speed_folder
    from walk3d.results.prediction import load_result
    from walk3d.solve.solver import forget_solvers

    settings = atlas_settings(sex, preset)
    summaries = [load_result(speed_folder(work, float(v))).summary for v in grid]
    entries = _entries(summaries, preset)
    if not entries:
        raise ValueError(f"no speed of {work} walked: no atlas written")
    for e in entries:
        worst = violation(settings, e)
        forget_solvers()
        if worst > ENTRY_TOLERANCE:
            raise ValueError(f"the entry at {e['speed']} m/s violates its problem by {worst:.2g}: "
                             "sweep again (`walk3d atlas build`)")  # fmt: skip
    middle = min(entries, key=lambda e: abs(e["speed"] - 1.3))
    data = {
        "format": FORMAT, "sex": sex, "preset": preset, "solve_revision": SOLVE_REVISION,
        "walk3d_version": __version__, "casadi_version": ca.__version__,
        "built": dt.datetime.now(dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"), "seed": seed,
        "reference": {"mass_kg": similarity.REFERENCE_MASS_KG,
                      "height_m": similarity.REFERENCE_HEIGHT_M},
        "settings": settings_key(settings), "fingerprint": fingerprint(settings, middle),
        "note": "walk3d's own predictions (free period and double support) of the reference "
                "subject; x: walk3d.problem.layout",
        "entries": entries,
    }  # fmt: skip
    path = atlas_path(sex, preset, Path(out_dir) if out_dir else ATLAS_DIR)
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(path, json.dumps(data, indent=1) + "\n")
    return path, len(entries)


HANDOVER_MAX_ITER = 300
"""Iteration limit of an entry's handover solve from its free-landing optimum: at 1.3 and 1.4 m/s
(male) they took 74 and 107 iterations."""


def add_handover(path: Path, on_progress: Callable[[str, int, int], None] | None = None) -> int:
    """Give each entry of the atlas file ``path`` its ``x_handover``: the optimum of the
    default problem (the handover, ``ModelSettings.handover``) at the entry's speed, period and
    double support, solved from the entry's free-landing optimum. These are the starts of the
    one-solve default (:func:`walk3d.solve.landing.solve_with_landing`). Entries that already
    have one are kept; an entry whose solve does not converge upright gets none. Returns the
    number of entries with one."""
    from walk3d.solve.atlas import read_atlas
    from walk3d.solve.solver import forget_solvers
    from walk3d.solve.starts import solve_warm

    data = json.loads(path.read_text())
    atlas = read_atlas(path)
    base = atlas_settings(atlas.sex, atlas.preset).replace(handover=True, free=())
    entries, points = data["entries"], {}
    for k, e in enumerate(entries):
        if on_progress:
            on_progress(f"handover at {e['speed']:.2f} m/s", k, len(entries))
        if "x_handover" in e:
            continue
        given = base.replace(speed=e["speed"], period=e["period"],
                             double_support=e["double_support"])  # fmt: skip
        out = solve_warm(given, np.asarray(e["x"], dtype=float), origin="the free landing",
                         max_iter=HANDOVER_MAX_ITER)  # fmt: skip
        if out.converged:
            e["x_handover"] = [float(f"{v:.12g}") for v in out.x]
            e["handover_iterations"] = out.iterations
            points[e["speed"]] = _warm_point(given, out)
        forget_solvers()
        atomic_write_text(path, json.dumps(data, indent=1) + "\n")  # resumable
    write_warm(path, points)
    return sum("x_handover" in e for e in entries)


def _warm_point(given: PredictionSettings, out) -> dict[str, np.ndarray] | None:
    """The primal-dual point where the handover solve ``out`` of ``given`` ended: ``z``,
    ``lam_x``, ``lam_g`` on every row (zero on the rows its stage solver drops) and that ``rows``
    mask; None without multipliers."""
    from walk3d.solve.ipopt import build_solver

    if not out.converged or out.duals is None:
        return None
    solver = build_solver(given)
    kept = solver.stage_rows["full"]
    mask = np.zeros(solver.nlp_bounds("full").lbg.size, dtype=bool)
    mask[kept] = True
    lam_g = np.zeros(mask.size)
    lam_g[kept] = out.duals["lam_g"]
    return {"z": out.z, "lam_x": out.duals["lam_x"], "lam_g": lam_g, "rows": mask}


def write_warm(path: Path, points: dict[float, dict | None] | None = None) -> Path:
    """Write the atlas file's primal-dual starts (:func:`walk3d.solve.atlas.warm_path`): for
    each entry with ``x_handover``, the handover NLP's variables and multipliers at that
    optimum (:func:`_warm_point`), from ``points`` (by speed, from the solves that found them)
    or solved again from it at the entry's V, T and Td. A start from the atlas blends them
    (docs/starts.md)."""
    from walk3d.solve.atlas import read_atlas, warm_path
    from walk3d.solve.solver import forget_solvers
    from walk3d.solve.starts import solve_warm

    atlas, points = read_atlas(path), dict(points or {})
    base = atlas_settings(atlas.sex, atlas.preset).replace(handover=True, free=())
    rows: dict[str, list] = {k: [] for k in ("speeds", "z", "lam_x", "lam_g", "rows")}
    for k, v in enumerate(atlas.speeds):
        if atlas.x_handover is None or not np.isfinite(atlas.x_handover[k]).all():
            continue
        if float(v) not in points:
            given = base.replace(speed=float(v), period=float(atlas.periods[k]),
                                 double_support=float(atlas.double_supports[k]))  # fmt: skip
            out = solve_warm(given, atlas.x_handover[k], origin="its handover optimum",
                             max_iter=HANDOVER_MAX_ITER)  # fmt: skip
            points[float(v)] = _warm_point(given, out)
            forget_solvers()
        if points[float(v)] is not None:
            rows["speeds"].append(v)
            for key, value in points[float(v)].items():
                rows[key].append(value)
    target = warm_path(path)
    with atomic_path(target, suffix=".npz") as tmp:
        np.savez_compressed(tmp, **{k: np.asarray(v) for k, v in rows.items()})
    return target


PERIOD_FACTORS = (0.9, 1.1)
"""Periods of the extra optima, as factors of each entry's own: published cadences for a
speed lie within about ±10 % of walk3d's predicted ones (the five sets of
``benchmarks/one_solve.py``: −7.5 % to +10.6 %)."""
PERIOD_MAX_ITER = 150
"""Iteration limit of one such solve from the entry's own primal-dual point (they took 35-60)."""


def write_periods(
    path: Path,
    factors: tuple[float, ...] = PERIOD_FACTORS,
    on_progress: Callable[[str, int, int], None] | None = None,
) -> Path:
    """Solve and write the atlas file ``path``'s optima at other periods (module docstring,
    :func:`walk3d.solve.atlas.periods_path`): for each entry of its warm file and each factor
    f, the handover problem at the entry's V, f T and f Td with IPOPT's warm start, first from
    the entry's own primal-dual point, then, where that failed, from the nearest speed's optimum
    at the same f, then by continuation through (1 + f) / 2; where only the half-way solve
    converges, its optimum is kept at that factor (``reached``). A solve that does not converge
    upright, or whose rows differ from the entry's, leaves NaN. Points already in a file of the
    same speeds and factors are kept (resumable). Returns the file written."""
    from walk3d.solve.atlas import load_warm, periods_path, read_atlas

    atlas = read_atlas(path)
    warm = load_warm(atlas)
    if warm is None:
        raise ValueError(f"{path} has no primal-dual points: build them first (walk3d atlas build)")
    target = periods_path(path)
    out = _kept_periods(target, warm, factors)
    base = atlas_settings(atlas.sex, atlas.preset).replace(handover=True, free=())
    speeds = warm["speeds"]
    todo = [(n, m) for n in range(speeds.size) for m in range(len(factors))
            if not np.isfinite(out["z"][n, m]).all()]  # fmt: skip
    for step, (n, m) in enumerate(todo):
        v, f = float(speeds[n]), factors[m]
        if on_progress:
            on_progress(f"{v:.2f} m/s at {f:g} T", step, len(todo))
        k = int(np.flatnonzero(np.isclose(atlas.speeds, v))[0])

        t, td = float(atlas.periods[k]), float(atlas.double_supports[k])

        def at(c: float, v: float = v, t: float = t, td: float = td) -> PredictionSettings:
            return base.replace(speed=v, period=t * c, double_support=td * c)

        own = {key: warm[key][n] for key in POINT_KEYS}
        near = [j for j in np.argsort(np.abs(speeds - v), kind="stable") if j != n
                and np.isfinite(out["z"][j, m]).all()
                and np.array_equal(warm["rows"][j], warm["rows"][n])][:1]  # fmt: skip
        rows = warm["rows"][n]
        for start in [own] + [{key: out[key][j, m] for key in POINT_KEYS} for j in near]:
            point = _period_point(at(f), start, rows)
            if point is not None:
                break
        reached = f
        if point is None:  # continuation: half-way first, then from there, else half-way
            half = _period_point(at((1.0 + f) / 2.0), own, rows)
            point = half and _period_point(at(f), half, rows)
            if point is None and half is not None:
                point, reached = half, (1.0 + f) / 2.0
        if point is not None:
            for key in POINT_KEYS:
                out[key][n, m] = point[key]
            out["reached"][n, m] = reached
    with atomic_path(target, suffix=".npz") as tmp:
        np.savez_compressed(tmp, speeds=speeds, factors=np.asarray(factors), **out)
    return target


def _kept_periods(target: Path, warm: dict, factors: tuple[float, ...]) -> dict[str, np.ndarray]:
    """The points of an earlier ``target`` when it has the same speeds and factors, else NaN."""
    from walk3d.solve.atlas import load_periods_file

    shape = (warm["speeds"].size, len(factors))
    out = {k: np.full((*shape, warm[k].shape[1]), np.nan) for k in POINT_KEYS}
    out["reached"] = np.full(shape, np.nan)
    old = load_periods_file(target)
    if (old is not None and np.array_equal(old["speeds"], warm["speeds"])
            and np.allclose(old["factors"], factors)
            and all(old[k].shape == out[k].shape for k in POINT_KEYS)):  # fmt: skip
        out = {k: np.array(old[k], dtype=float) for k in (*POINT_KEYS, "reached")}
    return out


def _period_point(given: PredictionSettings, start: dict, mask: np.ndarray) -> dict | None:
    """The handover optimum of ``given`` from the primal-dual point ``start`` (all rows), or
    None when it did not converge upright or its stage rows are not ``mask``."""
    from walk3d.solve.ipopt import build_solver, warm_stage
    from walk3d.solve.solver import forget_solvers

    solver = build_solver(given)
    point = None
    if np.array_equal(solver.stage_rows["full"], np.flatnonzero(mask)):
        stage = replace(solver.plan["full"], max_iter=PERIOD_MAX_ITER)
        begin = {"z": start["z"], "lam_x": start["lam_x"], "lam_g": start["lam_g"][mask],
                 "rows": np.flatnonzero(mask)}  # fmt: skip
        done = warm_stage(solver, stage, start["z"][: layout.N_X], 1.0, warm=begin)
        point = _warm_point(given, done)
    forget_solvers()
    return point
