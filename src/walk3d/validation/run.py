"""One validation run: predictions against references, Tables 2 and 3, figures and CSV files.

References are files: cycle tables (``.csv``), trial storages (``.mot``/``.sto``, recognised
as IK, GRF or ID by :func:`walk3d.trials.trial.classify_storage`) and C3D files (``.c3d``,
each one complete trial: force platforms and Plug-in Gait angles, see
:func:`walk3d.trials.trial.load_c3d_trial`). Table 2 uses the first
cycle table when there is one, otherwise the trial files cut into cycles. Several trials are
told apart by their file names with the ``_ik``/``_grf``/``_id`` token removed
(``gait_1_ik.mot`` + ``gait_1_grf.mot`` → trial ``gait_1``); one file of each kind is always one
trial.

Table 3 collects, when available: each prediction's own criteria (``summary["objective"]``);
the criteria from the reference's measured inverse-dynamics moments
(:func:`walk3d.validation.criteria.criteria_from_reference`); and walk3d's inverse dynamics on
the measured kinematics fitted with walk3d's Fourier series
(:func:`walk3d.validation.measured.fit_measured_gait`), from the trial's IK (with the trial's
V, T, Td) or else from the cycle table's angles (with the prediction's V, T, Td).
"""

from __future__ import annotations

import json
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from typing import Any

from walk3d.body.model import build_body
from walk3d.io.atomic import atomic_folder, atomic_write_text
from walk3d.io.checks import input_problem, positive_numbers
from walk3d.io.cycle_table import CycleTable, read_cycle_table
from walk3d.io.errors import DataFileError
from walk3d.io.storage import read_storage
from walk3d.io.tables import write_csv_table
from walk3d.outputs import check_output_folder, write_errors
from walk3d.problem.settings import recorded_settings
from walk3d.results.labels import did_not_converge, invalid_reason
from walk3d.results.prediction import VALIDATION_FILES, VALIDATION_FOLDER, PredictedCycle
from walk3d.trials.c3d_trial import parse_axis
from walk3d.trials.kinematics import kinematics_from_storage, kinematics_from_table
from walk3d.trials.trial import Trial, classify_storage, load_c3d_trial, load_trial
from walk3d.validation.compare import Comparison, compare, cycle_timing
from walk3d.validation.criteria import criteria_from_reference, table3_rows
from walk3d.validation.figures import comparison_figures
from walk3d.validation.measured import GaitFit, fit_measured_gait
from walk3d.validation.reference import Reference, reference_from_table, trial_reference
from walk3d.validation.score import Score, check_scored, score, score_json

__all__ = ["VALIDATION_MARK", "Validation", "check_forward", "check_validation_folder",
           "load_references", "sort_references", "table2_rows", "validate"]  # fmt: skip

TABLE3_COLUMNS = ("source", "criterion", "component", "value", "percent", "unit")

VALIDATION_MARK = "table2.csv"
"""The file every validation folder holds: only such a folder is replaced by another."""


def check_validation_folder(
    out_dir: str | PathLike[str], option: str = "out_dir", home: str | PathLike[str] | None = None
) -> Path:
    """Refuse an output folder that is a file, cannot be written, is not an earlier validation
    of only walk3d's files (:data:`~walk3d.results.prediction.VALIDATION_FILES`) or lies in a
    walk3d result folder other than ``home`` (default: a result folder holding it directly as
    ``validation``, where walk3d validate writes): ValueError, one line. ``walk3d validate
    --out``'s check too."""
    out = Path(out_dir)
    if home is None and out.name == VALIDATION_FOLDER:
        home = out.parent
    return check_output_folder(out_dir, option, replaces=VALIDATION_MARK, own=VALIDATION_FILES,
                               home=home)  # fmt: skip


@dataclass(frozen=True)
class Validation:
    """Everything one run computed (see the module doc)."""

    reference: Reference
    comparisons: tuple[Comparison, ...]
    table2: list[dict[str, Any]]
    table2_columns: tuple[str, ...]
    table3: list[dict[str, Any]]
    fit: GaitFit | None = None
    fit_source: str | None = None
    notes: list[str] = field(default_factory=list)
    files: dict[str, Path] = field(default_factory=dict)
    score: Score | None = None
    """The first prediction's score (:mod:`walk3d.validation.score`; ``score.json``)."""


def _trial_key(path: Path) -> str:
    return re.sub(r"(^|[_\-.])(ik|grf|id|inverse_dynamics)($|[_\-.])", r"\1\3", path.stem,
                  flags=re.IGNORECASE).strip("_-.")  # fmt: skip


def sort_references(paths: Sequence[str | PathLike[str]]) -> tuple[list[Path], list[dict]]:
    """``(cycle tables, trials)``; each trial is ``{"ik": Storage, "grf": ..., "id": ...}``, or
    ``{"c3d": Path}`` for a C3D file (read by :func:`load_c3d_trial`).

    Raises:
        FileNotFoundError, DataFileError: unreadable files. ValueError: a file that is neither a
        cycle table nor an IK/GRF/ID storage, or trial files that cannot be paired.
    """
    tables, storages, c3d = [], [], []
    for raw in paths:
        path = Path(raw)
        if not path.exists():
            raise FileNotFoundError(f"reference file not found: {path}")
        why = input_problem(path)  # a FIFO would block its reader, after the other files
        if why:
            raise DataFileError(path, why)
        if path.suffix.lower() in (".csv", ".txt"):
            tables.append(path)
            continue
        if path.suffix.lower() == ".c3d":
            c3d.append({"c3d": path})
            continue
        storage = read_storage(path)
        kind = classify_storage(storage)
        if kind is None:
            raise ValueError(f"{path.name}: neither a cycle table nor an IK, GRF or ID storage")
        storages.append((kind, path, storage))
    if not storages:
        return tables, c3d
    kinds = [k for k, _, _ in storages]
    if all(kinds.count(k) <= 1 for k in set(kinds)):
        return tables, [{k: s for k, _, s in storages}, *c3d]
    groups: dict[str, dict] = {}
    for kind, path, storage in storages:
        group = groups.setdefault(_trial_key(path), {})
        if kind in group:
            raise ValueError(f"two {kind.upper()} files for trial {_trial_key(path)!r}")
        group[kind] = storage
    return tables, [*groups.values(), *c3d]


def table2_rows(
    comparisons: Sequence[Comparison], labels: Sequence[str | None] = ()
) -> tuple[tuple[str, ...], list[dict]]:
    """Columns and rows of Table 2 for one or several predictions (same reference). ``labels``:
    per prediction, why it is not a valid walking prediction (``not converged``, ``not
    walking``) or None; an ``ok`` status names the flagged ones, so no row reads as a valid
    comparison of a failed solve."""
    flagged = [f"{c.prediction_name} {lab}" if len(comparisons) > 1 else lab
               for c, lab in zip(comparisons, labels, strict=False) if lab]  # fmt: skip
    ok = f"ok ({'; '.join(flagged)})" if flagged else "ok"
    single = len(comparisons) == 1
    cols = [
        "group",
        "quantity",
        "label",
        "unit",
        "status",
        "n_cycles",
        "reference_sd",
        "reference_range",
    ]
    for c in comparisons:
        suffix = "" if single else f"_{c.prediction_name}"
        cols += [f"{k}{suffix}" for k in ("rmse", "rmse_of_range", "r", "r2")]
    rows = []
    for k, row in enumerate(comparisons[0].rows):
        q = row.quantity
        out = {
            "group": q.group, "quantity": q.name, "label": q.label, "unit": q.unit,
            "status": ok if row.status == "ok" else row.status,
            "n_cycles": row.n_cycles, "reference_sd": row.reference_sd,
            "reference_range": row.reference_range,
        }  # fmt: skip
        for c in comparisons:
            r = c.rows[k]
            suffix = "" if single else f"_{c.prediction_name}"
            out[f"rmse{suffix}"], out[f"r{suffix}"] = r.rmse, r.r
            out[f"rmse_of_range{suffix}"], out[f"r2{suffix}"] = r.rmse_of_range, r.r2
        rows.append(out)
    return tuple(cols), rows


def _label(summary: Any) -> str | None:
    """``not converged``, ``not walking`` or None (:mod:`walk3d.results.labels`)."""
    if not isinstance(summary, dict) or invalid_reason(summary) is None:
        return None
    return "not converged" if did_not_converge(summary) else "not walking"


def _subject(pred: PredictedCycle) -> tuple[float, float, str, list[str]]:
    inputs = recorded_settings(pred.summary) if isinstance(pred.summary, dict) else {}
    notes = []
    mass = float(inputs.get("mass", pred.body_mass))
    height = inputs.get("height")
    if not isinstance(height, (int, float)):
        height = 1.77
        notes.append("the prediction does not state the height: 1.77 m assumed for the body")
    sex = inputs.get("sex", "male") if inputs.get("sex") in ("male", "female") else "male"
    return mass, float(height), sex, notes


def check_forward(forward: str | None, references: Sequence[str | PathLike[str]]) -> None:
    """Refuse a ``forward`` that is no lab axis (:func:`walk3d.trials.c3d_trial.parse_axis`),
    or one given without a C3D reference, which alone it applies to (it would be ignored):
    ValueError, one line."""
    if forward is None:
        return
    parse_axis(forward)
    if not any(Path(r).suffix.lower() == ".c3d" for r in references):
        raise ValueError(f"forward {forward!r} is the walking direction in C3D references, and "
                         "none is given; leave it out")  # fmt: skip


def load_references(
    references: Sequence[str | PathLike[str]],
    mass: float,
    *,
    threshold: float = 20.0,
    speed: float | None = None,
    forward: str | None = None,
) -> tuple[Reference, list[Trial], list[CycleTable], list[Path]]:
    """``(reference, trials, tables, table_paths)`` of reference files (module doc): the first
    cycle table's reference, else the trials' cycles; ``mass`` (kg) turns forces into N/kg.
    ValueError when there is no reference file, or trials without a GRF file."""
    table_paths, trial_files = sort_references(references)
    trials: list[Trial] = [
        load_c3d_trial(t["c3d"], threshold=threshold, speed=speed, forward=forward)
        if "c3d" in t
        else load_trial(t.get("ik"), t.get("grf"), t.get("id"), threshold=threshold, speed=speed)
        for t in trial_files
    ]
    tables = [read_cycle_table(p) for p in table_paths]
    if tables:
        reference = reference_from_table(tables[0], mass=mass, name=table_paths[0].name)
    elif trials:
        if not any(t.descriptors for t in trials):
            raise ValueError("trial references need a GRF file (events cut the cycles)")
        reference = trial_reference(trials, mass)
    else:
        raise ValueError("no reference file")
    return reference, trials, tables, table_paths


def validate(
    predictions: Mapping[str, PredictedCycle],
    references: Sequence[str | PathLike[str]],
    out_dir: str | PathLike[str] | None = None,
    *,
    threshold: float = 20.0,
    speed: float | None = None,
    figures: bool = True,
    forward: str | None = None,
) -> Validation:
    """Run the comparison (module doc); write ``table2.csv``, ``table3.csv``,
    ``measured_fit.csv`` and the figures to ``out_dir`` when given, all or none: built in a
    temporary sibling, then in place of an earlier validation there (a folder with other files
    is refused with ValueError before any work; OutputWriteError when it cannot be written).
    ``forward`` is the lab axis the walker faces in C3D references (``"-y"``...; detected when
    None). ValueError for a ``threshold`` or ``speed`` that is not a finite positive number,
    whatever the references, before any work."""
    positive_numbers(threshold=threshold, speed=speed)
    check_forward(forward, references)
    if not predictions:
        raise ValueError("no prediction to validate")
    if out_dir is not None:
        check_validation_folder(out_dir)
    first = next(iter(predictions.values()))
    mass, height, sex, notes = _subject(first)
    loaded = load_references(references, mass, threshold=threshold, speed=speed, forward=forward)
    reference, trials, tables, table_paths = loaded
    check_scored(reference)  # before any write: nothing to compare with
    notes += list(reference.notes)
    comparisons = tuple(compare(p, reference, name) for name, p in predictions.items())
    cols2, rows2 = table2_rows(comparisons, [_label(p.summary) for p in predictions.values()])
    summary = first.summary if isinstance(first.summary, dict) else {}
    timed = next((t for t in trials if t.descriptors is not None), None)
    result = score(comparisons[0], summary, timed.descriptors.double_support if timed else None)

    rows3: list[dict] = []
    for name, pred in predictions.items():
        objective = pred.summary.get("objective") if isinstance(pred.summary, dict) else None
        if isinstance(objective, dict) and "C_tor" in objective and "C_en" in objective:
            rows3 += table3_rows(objective, f"prediction ({name})")
    body = build_body(mass, height, sex)
    period = timed.descriptors.period if (timed and not tables) else cycle_timing(first)[0]
    crit, missing = criteria_from_reference(reference, body, period)
    if crit["C_tor"]["total"] > 0:
        rows3 += table3_rows(crit, f"measurement: ID moments of {reference.name}")
        if missing:
            notes.append(f"Table 3 from measured moments leaves out {', '.join(missing)}")
    fit, fit_source = _measured_fit(body, trials, tables, table_paths, first, notes)
    if fit is not None:
        rows3 += table3_rows(fit.criteria, f"measurement: walk3d ID of fitted {fit_source}")

    files: dict[str, Path] = {}
    if out_dir is not None:
        out = Path(out_dir)
        with write_errors(out), atomic_folder(out) as tmp:  # all of it or nothing
            files["table2"] = write_csv_table(tmp / "table2.csv", cols2, rows2)
            if rows3:
                files["table3"] = write_csv_table(tmp / "table3.csv", TABLE3_COLUMNS, rows3)
            if fit is not None:
                rows = [{"dof": k, "rmse_vs_measured_deg": v,
                         "rmse_vs_fitted_deg": fit.fit_rmse_deg.get(k),
                         "projection_change_deg": fit.projection_change_deg.get(k)}
                        for k, v in fit.rmse_deg.items()]  # fmt: skip
                files["fit"] = write_csv_table(tmp / "measured_fit.csv", tuple(rows[0]), rows)
            files["score"] = tmp / "score.json"
            atomic_write_text(files["score"], json.dumps(score_json(result), indent=1) + "\n")
            if figures:
                files.update(comparison_figures(comparisons, tmp))
        files = {k: out / p.name for k, p in files.items()}
    return Validation(reference, comparisons, rows2, cols2, rows3, fit, fit_source, notes, files,
                      result)  # fmt: skip


def _measured_fit(body, trials, tables, table_paths, pred, notes):
    for t in trials:
        if t.ik is not None and t.descriptors is not None:
            d = t.descriptors
            kin = kinematics_from_storage(t.ik, "auto" if t.knee_sign is None else t.knee_sign)
            if kin.pelvis_angles is None:
                notes.append(f"{t.name}: no pelvis angles, so no walk3d ID of its kinematics")
                continue
            hs = d.events["right"].heel_strikes
            if hs.size == 0:
                continue
            fit = fit_measured_gait(kin, body, period=d.period, double_support=d.double_support,
                                    right_heel_strike=float(hs[0]), speed=d.speed)  # fmt: skip
            return fit, f"IK of {t.name}"
    if tables:
        period, t_hs = cycle_timing(pred)
        inputs = recorded_settings(pred.summary) if isinstance(pred.summary, dict) else {}
        speed = float(inputs.get("speed", 1.3))
        kin = kinematics_from_table(tables[0], period)
        if not any(k.startswith("hip_flexion") for k in kin.angles):
            return None, None
        if kin.pelvis_angles is None:  # the projection needs them, as for a trial's IK
            notes.append(f"{table_paths[0].name}: no pelvis angles, so no walk3d ID of its "
                         "angles")  # fmt: skip
            return None, None
        td = period / 2 - t_hs
        fit = fit_measured_gait(kin, body, period=period, double_support=td,
                                right_heel_strike=0.0, speed=speed)  # fmt: skip
        notes.append(f"fitted angles of {table_paths[0].name} with the prediction's T and Td")
        return fit, f"angles of {table_paths[0].name}"
    return None, None
