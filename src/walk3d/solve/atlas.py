"""The atlas: walk3d's own converged predictions, used as starts near a walking optimum.

One file per sex and criterion preset in ``atlas_data/`` holds, for the reference subject of
:mod:`walk3d.problem.similarity` (68.8 kg, 1.77 m), the optimum of the free-descriptor problem
(period and double support predicted) at each speed of a sweep: its decision vector, T and Td.
Any mass and stature map onto it through dynamic similarity, so one file serves every subject
of that sex and criterion. ``walk3d atlas build`` makes the files (:mod:`walk3d.campaign.atlas`);
they hold no measured data.

A start for speed V (the reference subject's) blends the two entries that bracket V linearly
(the coefficients are phase-based, so a blend of two walking cycles is a walking cycle), or
takes the nearest entry outside the atlas's speeds (:func:`candidates` lists the tries). An
entry may also hold ``x_handover``, the handover problem's optimum at its V, T and Td: a
handover problem starts from those (:func:`walk3d.campaign.atlas.add_handover`). A
criterion without its own file starts from the default preset's. An atlas made by another solve
revision, or for other model or grid settings, is never used: no start, and the reason.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

import numpy as np

from walk3d.io.checks import finite_number, increasing, read_json_object, require_finite
from walk3d.io.errors import DataFileError
from walk3d.model import terms
from walk3d.model.settings import keyed_fields, opt_in
from walk3d.problem import descriptors, layout
from walk3d.problem.settings import PredictionSettings
from walk3d.solve.revision import SOLVE_REVISION

__all__ = ["ATLAS_DIR", "FORMAT", "Atlas", "AtlasStart", "atlas_path", "candidates",
           "load_atlas", "load_periods", "load_periods_file", "period_weights", "POINT_KEYS",
           "read_atlas", "settings_key", "start_for"]  # fmt: skip

ATLAS_DIR = Path(__file__).resolve().parent / "atlas_data"
"""Where the package's atlas files are (package data)."""
FORMAT = 3
"""Version of the file layout below (3: every entry is on the one free grid of its node count,
:func:`walk3d.problem.descriptors.free_grid`)."""
MAX_EXTRAPOLATION = 0.35
"""Largest distance (m/s, reference subject) from the atlas's speeds at which its nearest entry
is still used as a start; farther, the start is standing."""


@dataclass(frozen=True)
class Atlas:
    """One atlas file: entries sorted by speed, in the reference subject's units."""

    sex: str
    preset: str
    solve_revision: int
    settings: dict
    """:func:`settings_key` of the problem the entries solve."""
    speeds: np.ndarray
    """m/s."""
    periods: np.ndarray
    double_supports: np.ndarray
    """s."""
    x: np.ndarray
    """(n, N_X) decision vectors (:mod:`walk3d.problem.layout`)."""
    x_handover: np.ndarray | None
    """(n, N_X) optima of the default problem (the handover) at each entry's V, T and Td, NaN
    rows where an entry has none; None when the file has none
    (:func:`walk3d.campaign.atlas.add_handover`)."""
    fingerprint: dict
    """The given-descriptor NLP's objective and constraint norm at one entry's start
    (:func:`walk3d.campaign.atlas.fingerprint`): a test compares them with the current
    model's, so an atlas that no longer matches the model is caught."""
    path: Path

    @property
    def current(self) -> bool:
        """Whether this walk3d's solve revision made it."""
        return self.solve_revision == SOLVE_REVISION


@dataclass(frozen=True)
class AtlasStart:
    """A start from the atlas: decision vector and descriptors (reference subject's units)."""

    x: np.ndarray
    period: float
    double_support: float
    speeds: tuple[float, ...]
    """The entries used (one or two), m/s."""
    weights: tuple[float, ...]
    preset: str
    """The criterion preset of the atlas file."""
    warm: dict[str, np.ndarray] | None = field(default=None, compare=False, repr=False)
    """The blended primal-dual point of the entries' handover solves (``z``, ``lam_x``, ``lam_g``
    and the stage ``rows`` they belong to, :func:`load_warm`), when both entries have one."""
    landing: str = "free"
    """Which optima ``x`` blends: ``free`` (the entries' own, free landing) or ``handover``
    (:attr:`Atlas.x_handover`, used for a handover problem when both entries have one)."""
    period_ratio: float | None = None
    """The given period over the entries' blended one, when ``warm`` blends the entries' optima
    at other periods (:func:`load_periods`); None otherwise. ``x`` stays the entries' own blend:
    a primal start alone from those optima took more iterations (docs/starts.md)."""

    def describe(self) -> dict:
        out = {"atlas_speeds": list(self.speeds), "atlas_weights": list(self.weights),
               "atlas_preset": self.preset, "atlas_landing": self.landing}  # fmt: skip
        if self.period_ratio is not None:
            out["atlas_period_ratio"] = round(self.period_ratio, 6)
        return out


def settings_key(settings: PredictionSettings) -> dict:
    """What an atlas entry depends on besides speed: the model settings (criterion included)
    but those at their off value (:func:`walk3d.model.settings.keyed_fields`, as in atlases
    made before the setting existed), the sex and the time grid (its kind only when it is the
    phase grid, whose handover points are another problem's)."""
    model = keyed_fields(settings.model, mode="json")
    model["criterion"] = terms.preset_name(settings.model.criterion) or model["criterion"]
    grid = {"grid": "phase"} if settings.solver.grid == "phase" else {}
    return {"sex": settings.gait.sex, "model": model, "nodes": settings.solver.nodes,
            "ds_intervals": descriptors.ds_intervals(settings.solver.nodes),
            "heel_strike_nodes": settings.solver.heel_strike_nodes} | grid  # fmt: skip


def atlas_path(sex: str, preset: str, root: Path | None = None) -> Path:
    return (root or ATLAS_DIR) / f"{sex}-{preset}.json"


@cache
def _read(path: Path, mtime_ns: int) -> Atlas:
    return read_atlas(path)


def read_atlas(path: Path) -> Atlas:
    """One atlas file, checked: its format, and every entry's finite speed, period, double
    support and :data:`walk3d.problem.layout.N_X` coefficients, speeds distinct.

    Raises:
        DataFileError: malformed or of another format (a ValueError).
    """
    data = read_json_object(path, "walk3d atlas file")
    if data.get("format") != FORMAT:
        raise DataFileError(path, f"atlas format {data.get('format')!r:.20}, expected {FORMAT}")
    entries, settings = data.get("entries"), data.get("settings")
    if not isinstance(entries, list) or not entries or not all(isinstance(e, dict)
                                                              for e in entries):  # fmt: skip
        raise DataFileError(path, "no list of atlas entries")
    if not (isinstance(data.get("sex"), str) and isinstance(data.get("preset"), str)
            and isinstance(settings, dict) and isinstance(data.get("solve_revision"), int)
            and isinstance(data.get("fingerprint", {}), dict)):  # fmt: skip
        raise DataFileError(path, "sex, preset, settings or solve_revision missing or malformed")
    cols = {k: [finite_number(path, e.get(k), f"entry {i}'s {k}") for i, e in enumerate(entries)]
            for k in ("speed", "period", "double_support")}  # fmt: skip
    order = np.argsort(cols["speed"], kind="stable")
    speeds = increasing(path, "the entries' speeds", np.asarray(cols["speed"])[order])
    x = require_finite(path, "the entries' coefficients", [entries[i].get("x") for i in order])
    if x.ndim != 2 or x.shape[1] != layout.N_X:
        raise DataFileError(path, f"entries must hold {layout.N_X} coefficients")
    x_ho = None
    if any("x_handover" in e for e in entries):
        rows = [entries[i].get("x_handover", [np.nan] * layout.N_X) for i in order]
        try:
            x_ho = np.asarray(rows, dtype=float)
        except (TypeError, ValueError):
            x_ho = np.zeros(0)
        unset = np.isnan(x_ho).all(axis=1, keepdims=True) if x_ho.ndim == 2 else False
        if x_ho.shape != x.shape or not np.all(np.isfinite(x_ho) | unset):
            raise DataFileError(path, f"x_handover must hold {layout.N_X} finite coefficients")
    return Atlas(
        sex=data["sex"], preset=data["preset"], solve_revision=data["solve_revision"],
        settings=settings, speeds=speeds, periods=np.asarray(cols["period"])[order],
        double_supports=np.asarray(cols["double_support"])[order], x=x, x_handover=x_ho,
        fingerprint=data.get("fingerprint", {}), path=path,
    )  # fmt: skip


def load_atlas(sex: str, preset: str, root: Path | None = None) -> Atlas | None:
    """The atlas file for ``sex`` and ``preset``, or None if there is none."""
    path = atlas_path(sex, preset, root)
    if not path.is_file():
        return None
    return _read(path, path.stat().st_mtime_ns)


def _usable(atlas: Atlas, ref: PredictionSettings) -> str | None:
    """Why ``atlas`` cannot start ``ref`` (None: it can). An atlas of another criterion, or
    solved with or without the handover or the passive joints, serves when everything else
    matches."""
    if not atlas.current:
        return (f"the atlas {atlas.path.name} was made by solve revision {atlas.solve_revision}, "
                f"not {SOLVE_REVISION}: rebuild it with `walk3d atlas build`")  # fmt: skip
    ours = settings_key(ref)
    theirs = {**atlas.settings, "model": dict(atlas.settings.get("model", {}))}
    ours["model"]["criterion"] = theirs["model"].get("criterion")
    for key in (ours, theirs):
        for flag in opt_in():
            key["model"].pop(flag, None)
    if theirs != ours:
        return f"the atlas {atlas.path.name} solves other model or grid settings"
    return None


def _find(ref: PredictionSettings, root: Path | None) -> tuple[Atlas | None, str]:
    """The atlas of ``ref``'s sex and criterion preset, else that of its sex and the default
    preset (a start for any criterion: the paper's C_tor from the ``natural`` atlas reached a
    lower optimum than 40 standing starts, docs/starts.md); or None and why."""
    preset = terms.preset_name(ref.model.criterion)
    for name in dict.fromkeys(p for p in (preset, terms.DEFAULT_PRESET) if p):
        try:
            found = load_atlas(ref.gait.sex, name, root=root)
        except (ValueError, KeyError, OSError) as exc:  # another format, or damaged
            return None, f"{exc}: rebuild it with `walk3d atlas build`"
        if found is not None:
            return found, ""
    return None, f"no atlas for {ref.gait.sex}"


def start_for(
    ref: PredictionSettings, root: Path | None = None
) -> tuple[AtlasStart | None, str | None]:
    """The first of :func:`candidates` for ``ref``, or None and the reason."""
    found, why = candidates(ref, root)
    return (found[0] if found else None), why


def candidates(
    ref: PredictionSettings, root: Path | None = None, tries: int = 3
) -> tuple[list[AtlasStart], str | None]:
    """Up to ``tries`` atlas starts for the reference subject's settings ``ref``
    (:func:`walk3d.problem.similarity.reference_problem`), best first: the blend of the two
    entries bracketing its speed, then single entries by distance in speed; or none and the
    reason. Why several: two neighbouring entries can lie on different local optima, and a
    given period may be reachable from one and not the other (docs/starts.md)."""
    atlas, why = _find(ref, root)
    if atlas is None:
        return [], why
    why = _usable(atlas, ref)
    if why is not None:
        return [], why
    v, speeds = ref.gait.speed, atlas.speeds
    near = np.argsort(np.abs(speeds - v), kind="stable")
    if abs(v - speeds[near[0]]) > MAX_EXTRAPOLATION:
        return [], f"{v:.2f} m/s is outside the atlas's {speeds[0]:.2f}-{speeds[-1]:.2f}"
    found: list[list[tuple[int, float]]] = []
    if speeds[0] < v < speeds[-1]:
        hi = int(np.searchsorted(speeds, v))
        w = float((v - speeds[hi - 1]) / (speeds[hi] - speeds[hi - 1]))
        if 0.0 < w < 1.0:
            found.append([(hi - 1, 1.0 - w), (hi, w)])
    found += [[(int(i), 1.0)] for i in near if abs(v - speeds[i]) <= MAX_EXTRAPOLATION]
    period = None if ref.gait.free else ref.gait.period
    return [_blend(atlas, pairs, ref.model.handover, period) for pairs in found[:tries]], None


def warm_path(atlas_file: Path) -> Path:
    """The atlas file's primal-dual starts: ``<sex>-<preset>-warm.npz`` beside it."""
    return atlas_file.with_name(atlas_file.stem + "-warm.npz")


POINT_KEYS = ("z", "lam_x", "lam_g")
"""The arrays of a primal-dual point: the NLP's variables and the multipliers of its bounds and
rows."""


@cache
def _read_npz(path: Path, mtime_ns: int, keys: tuple[str, ...], optional: tuple[str, ...] = ()):
    try:
        with np.load(path) as data:
            return {k: data[k] for k in keys} | {k: data[k] for k in optional if k in data}
    except (OSError, ValueError, KeyError):  # damaged or of another layout: not used
        return None


def _load_npz(
    path: Path, keys: tuple[str, ...], optional: tuple[str, ...] = ()
) -> dict[str, np.ndarray] | None:
    """The arrays ``keys`` (and those of ``optional`` it has) of the file ``path``, read once
    per modification; None without a readable file holding them."""
    return _read_npz(path, path.stat().st_mtime_ns, keys, optional) if path.is_file() else None


def load_warm(atlas: Atlas) -> dict[str, np.ndarray] | None:
    """The primal-dual points of the entries' handover solves, or None without a readable file
    (:func:`walk3d.campaign.atlas.add_handover`): by entry (``speeds``), ``z``, ``lam_x``, and
    ``lam_g`` on all rows with the mask ``rows`` of those its stage solver kept."""
    return _load_npz(warm_path(atlas.path), ("speeds", *POINT_KEYS, "rows"))


def _warm_blend(
    atlas: Atlas, pairs: list[tuple[int, float]], ratio: float = 1.0
) -> tuple[dict[str, np.ndarray] | None, bool]:
    """The blend of the warm points of ``pairs`` (atlas indices) when both have one for the
    same stage rows: ``z``, ``lam_x``, ``lam_g`` (on those rows) and the ``rows``; with a
    period ``ratio`` ≠ 1, each entry's point is first blended between its optima at the
    periods that bracket it (:func:`load_periods`). Also whether those were used."""
    warm = load_warm(atlas)
    if warm is None:
        return None, False
    at = [np.flatnonzero(np.isclose(warm["speeds"], atlas.speeds[i])) for i, _ in pairs]
    if not all(a.size == 1 for a in at):
        return None, False
    mask = warm["rows"][at[0][0]]
    if any(not np.array_equal(warm["rows"][a[0]], mask) for a in at):
        return None, False
    points = [{k: warm[k][a[0]] for k in POINT_KEYS} for a in at]
    levels = load_periods(atlas) if abs(ratio - 1.0) > PERIOD_TOLERANCE else None
    entries = zip(pairs, points, strict=True)
    moved = [] if levels is None else [_at_periods(levels, atlas.speeds[i], p, ratio)
                                       for (i, _), p in entries]  # fmt: skip
    used = bool(moved) and all(p is not None for p in moved)
    points = moved if used else points
    out = {k: sum(wt * p[k] for p, (_, wt) in zip(points, pairs, strict=True)) for k in POINT_KEYS}
    return out | {"lam_g": out["lam_g"][mask], "rows": np.flatnonzero(mask)}, used


PERIOD_TOLERANCE = 1e-3
"""A given period within this fraction of the entries' blended one starts from the entries'
own optima (the default prediction's case: it is solved at the atlas's period)."""


def periods_path(atlas_file: Path) -> Path:
    """The entries' optima at other periods: ``<sex>-<preset>-periods.npz`` beside the file."""
    return atlas_file.with_name(atlas_file.stem + "-periods.npz")


def load_periods(atlas: Atlas) -> dict[str, np.ndarray] | None:
    """The handover optima of each entry at its period and double support times each of
    ``factors`` (:func:`walk3d.campaign.atlas.write_periods`): by entry (``speeds``)
    and factor, the primal-dual points ``z``, ``lam_x`` and ``lam_g`` on all rows (NaN where a
    solve failed), on the stage rows of the entry's own point, and the factor each was solved at
    (``reached``: the half-way factor where only that converged); None without a readable file."""
    return load_periods_file(periods_path(atlas.path))


def load_periods_file(path: Path) -> dict[str, np.ndarray] | None:
    """The contents of a periods file (:func:`load_periods`), or None without a readable one;
    a file without ``reached`` has each finite level at its nominal factor."""
    out = _load_npz(path, ("speeds", "factors", *POINT_KEYS), optional=("reached",))
    if out is None or "reached" in out:
        return out
    finite = np.isfinite(out["z"]).all(axis=2)
    return out | {"reached": np.where(finite, out["factors"][None, :], np.nan)}


def period_weights(factors: np.ndarray, ratio: float) -> list[tuple[int, float]]:
    """Linear weights on ``factors`` (indices) for the period ``ratio``: the two factors that
    bracket it, or the nearest end outside them (no extrapolation)."""
    order = np.argsort(factors)
    f = np.asarray(factors, dtype=float)[order]
    r = float(np.clip(ratio, f[0], f[-1]))
    hi = int(np.clip(np.searchsorted(f, r), 1, f.size - 1))
    u = (r - f[hi - 1]) / (f[hi] - f[hi - 1])
    return [(int(order[hi - 1]), 1.0 - u), (int(order[hi]), u)]


def _at_periods(
    levels: dict[str, np.ndarray], speed: float, own: dict[str, np.ndarray], ratio: float
) -> dict[str, np.ndarray] | None:
    """An entry's point at the period ``ratio``, blended from its own (factor 1) and its
    points at the factors ``levels`` reached; None when the entry has no finite points there."""
    j = np.flatnonzero(np.isclose(levels["speeds"], speed))
    if j.size != 1:
        return None
    pts = [own] + [
        {k: levels[k][j[0], m] for k in POINT_KEYS} for m in range(levels["factors"].size)
    ]
    reached = levels["reached"][j[0]]
    factors = np.concatenate([[1.0], np.where(np.isfinite(reached), reached, levels["factors"])])
    wts = [(m, w) for m, w in period_weights(factors, ratio) if w > 0.0]
    if not all(np.isfinite(pts[m][k]).all() for m, _ in wts for k in POINT_KEYS):
        return None
    return {k: sum(w * pts[m][k] for m, w in wts) for k in POINT_KEYS}


def _blend(
    atlas: Atlas, pairs: list[tuple[int, float]], handover: bool = False,
    period: float | None = None,
) -> AtlasStart:  # fmt: skip
    """The start blending ``pairs`` (atlas index, weight); for a handover problem of a given
    ``period`` (s, reference subject), the entries' optima nearest that period."""

    def blend(values: np.ndarray):
        return sum(wt * values[i] for i, wt in pairs)

    xs, landing, warm, ratio = atlas.x, "free", None, None
    if handover and atlas.x_handover is not None:
        if all(np.isfinite(atlas.x_handover[i]).all() for i, _ in pairs):
            xs, landing = atlas.x_handover, "handover"
            r = 1.0 if period is None else period / float(blend(atlas.periods))
            warm, used = _warm_blend(atlas, pairs, r)
            ratio = r if used else None
    return AtlasStart(
        x=np.asarray(blend(xs), dtype=float), landing=landing, warm=warm, period_ratio=ratio,
        period=float(blend(atlas.periods)),
        double_support=float(blend(atlas.double_supports)),
        speeds=tuple(float(atlas.speeds[i]) for i, _ in pairs),
        weights=tuple(round(wt, 6) for _, wt in pairs), preset=atlas.preset,
    )  # fmt: skip
