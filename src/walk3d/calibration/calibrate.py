"""``walk3d calibrate``: a trial's roll-over and transition ratios into a calibration file.

:func:`calibrate_from_trial` reads the IK and GRF files, derives the descriptors, fits the
roll-over and the transition ratios (:mod:`walk3d.calibration.fit`), writes the JSON file
(:func:`walk3d.io.write_calibration`) and the two figures (``<stem>_rollover.png``,
``<stem>_transition.png``) beside it. :func:`load_calibration` reads a file back.

Using a calibration in a prediction: ``walk3d predict --calibration FILE`` (and ``campaign``,
``compile``) puts the file's roll-over and ratios into the settings (``rollover_s``,
``rollover_ankle``, ``transition_ratios``), from which the solver builds its body and its
double-support split. In code, :func:`walk3d.calibration.fit.apply_calibration` returns
the body model with the calibrated roll-over; the ratios go to
:func:`walk3d.contact.transition.apply_ratios`.
"""

from __future__ import annotations

from dataclasses import dataclass
from os import PathLike
from pathlib import Path

import numpy as np

from walk3d.body.model import BodyModel
from walk3d.calibration.figures import rollover_figure, transition_figure
from walk3d.calibration.fit import (
    Calibration,
    TransitionCheck,
    fit_rollover_from_trial,
    fit_transition,
)
from walk3d.io.angle_units import check_storage_angles
from walk3d.io.calibration import read_calibration, write_calibration
from walk3d.io.checks import positive_numbers
from walk3d.io.storage import read_storage
from walk3d.outputs import check_output_file, json_holds, replace_files, write_errors
from walk3d.trials.descriptors import descriptors_from_trial, foot_loads
from walk3d.trials.kinematics import kinematics_from_storage

__all__ = ["CalibrationResult", "calibrate_from_trial", "check_calibration_out", "figure_paths",
           "load_calibration"]  # fmt: skip


def figure_paths(out: str | PathLike[str]) -> tuple[Path, Path]:
    """The roll-over and transition figures written beside the calibration file ``out``."""
    path = Path(out)
    return (path.with_name(f"{path.stem}_rollover.png"),
            path.with_name(f"{path.stem}_transition.png"))  # fmt: skip


def check_calibration_out(
    out: str | PathLike[str],
    ik: str | PathLike[str] | None,
    grf: str | PathLike[str] | None,
    figures: bool = True,
    option: str = "out",
) -> None:
    """Refuse, before any work, a calibration file ``out`` that is not a ``.json`` walk3d may
    write (:func:`walk3d.outputs.check_output_file`): the trial's ``ik`` or ``grf`` file, a
    file in a walk3d result folder, an existing file that is not a walk3d calibration; or
    whose figures (:func:`figure_paths`) exist without an earlier calibration ``out`` that
    they would belong to. ValueError, one line naming ``option``."""
    dash = "--" if option.startswith("--") else ""
    inputs = {f"{dash}ik": ik, f"{dash}grf": grf}
    check_output_file(out, option, ".json", inputs=inputs,
                      existing=("walk3d calibration", _is_calibration))  # fmt: skip
    earlier = Path(out).is_file()  # a walk3d calibration, checked above: its figures are
    for figure in figure_paths(out) if figures else ():
        check_output_file(figure, "the figure", inputs=inputs)  # none a device or FIFO either
        if figure.exists() and not earlier:
            raise ValueError(f"{option} {out}: the figure {figure} written beside it exists, "
                             f"with no earlier calibration {Path(out).name} it belongs to; "
                             f"move it or name another {option}")  # fmt: skip


def _is_calibration(path: Path) -> bool:
    return json_holds(path, "walk3d_calibration")


@dataclass(frozen=True)
class CalibrationResult:
    calibration: Calibration
    transition: TransitionCheck
    path: Path | None
    figures: tuple[Path, ...]
    rollover_samples: tuple[np.ndarray, np.ndarray]
    """Pooled stance samples ``(s, ankle (n, 3))`` behind the roll-over fit (Fig. 2)."""


def calibrate_from_trial(
    ik: str | PathLike[str],
    grf: str | PathLike[str],
    body: BodyModel,
    out: str | PathLike[str] | None = None,
    *,
    threshold: float = 20.0,
    speed: float | None = None,
    figures: bool = True,
) -> CalibrationResult:
    """Calibrate ``body``'s subject from one trial; write ``out`` (a ``.json`` file,
    :func:`check_calibration_out`) and its figures when given, all or none (built aside, then
    moved into place: :func:`walk3d.outputs.replace_files`; OutputWriteError when they cannot
    be written). ValueError for a ``threshold`` or ``speed`` that is not a finite positive
    number, before any work."""
    positive_numbers(threshold=threshold, speed=speed)
    if out is not None:  # every file it writes: an input, a user's file... refused now
        check_calibration_out(out, ik, grf, figures)
    ik_s = read_storage(ik)
    check_storage_angles(ik_s)  # angles in another unit than the header's
    loads = foot_loads(grf)
    desc = descriptors_from_trial(ik_s, loads, threshold=threshold, speed=speed)
    kin = kinematics_from_storage(ik_s)
    rollover, quality, samples = fit_rollover_from_trial(body, kin, desc.events)
    check = fit_transition(body, kin, loads, desc.events, body.mass, threshold)
    measured_s = (float(samples[0].min()), float(samples[0].max()))
    values = np.column_stack(rollover.evaluate(np.array(rollover.knots))[0])
    ankle = tuple((float(x), float(y), float(z)) for x, y, z in values)
    cal = Calibration(
        rollover_s=tuple(float(k) for k in rollover.knots),
        rollover_ankle=ankle,
        measured_s_range=measured_s,
        ratios=check.ratios,
        subject={"mass_kg": body.mass, "height_m": body.height, "sex": body.sex},
        descriptors=desc.as_dict(),
        quality={
            "rollover": quality,
            "transition_rmse": check.rmse,
            "transition_rmse_heel_strike_ratios": check.rmse_heel_strike_ratios,
            "transition_units": "forces N/kg, moments N m/kg about the trailing ankle",
            "knee_sign": kin.knee_sign,
        },
        source={"ik": str(ik), "grf": str(grf), "threshold_N": threshold},
    )
    path, figs = None, []
    if out is not None:
        path = Path(out)
        with write_errors(path), replace_files(path.parent, last=path.name) as tmp:
            write_calibration(tmp / path.name, cal.to_dict())  # moved last, after its figures
            if figures:
                roll, transition = (tmp / f.name for f in figure_paths(path))
                figs.append(rollover_figure(samples, rollover, body.rollover, roll))
                figs.append(transition_figure(check, transition))
        figs = [path.parent / f.name for f in figs]
    return CalibrationResult(cal, check, path, tuple(figs), samples)


def load_calibration(path: str | PathLike[str]) -> Calibration:
    """Read a calibration file (checked by :func:`walk3d.io.read_calibration`)."""
    return Calibration.from_dict(read_calibration(path))
