"""``walk3d validate`` and ``walk3d calibrate`` (issue 5: measured trials)."""

from __future__ import annotations

import os
import sys
from typing import Annotated

import typer

from walk3d.cli.common import (
    EXIT_WRITE,
    BeltSpeed,
    Height,
    Mass,
    PlateThreshold,
    Sex,
    app,
    console,
    fail,
    input_file,
    positive_options,
)


@app.command(short_help="Compare a prediction with measured walking.")
def validate(
    pred_dir: Annotated[str, typer.Argument(help="Prediction folder (walk3d predict --out).")],
    reference: Annotated[
        list[str],
        typer.Option(
            "--reference",
            help="Cycle table .csv, trial IK/GRF/ID storages or C3D files (repeat).",
            callback=input_file,
        ),
    ],
    out: Annotated[
        str | None, typer.Option("--out", help="Output folder (default PRED_DIR/validation).")
    ] = None,
    threshold: PlateThreshold = 20.0,
    speed: BeltSpeed = None,
    forward: Annotated[
        str | None,
        typer.Option("--forward", help="Lab axis the walker faces in C3D files (+x, -y...)."),
    ] = None,
) -> None:
    """Compare a prediction with measured walking: Table 2 (RMSE and r per quantity), Table 3
    (criteria and their x/y/z split) and figures, written to --out all together, in place of
    an earlier validation there. A prediction that did not converge or does not walk is named
    in a warning line, and its score's failure printed. Exit code 2 for bad input (also an
    --out that is a file, a folder holding files walk3d did not write or lies in another walk3d
    result folder), 3 if the folder cannot be written (nothing is changed)."""
    from walk3d.cli.labels import warn_if_invalid
    from walk3d.cli.warning_lines import warning_lines
    from walk3d.io.errors import DataFileError, OutputWriteError
    from walk3d.results.labels import did_not_converge
    from walk3d.results.prediction import VALIDATION_FOLDER, load_result
    from walk3d.validation.run import check_validation_folder
    from walk3d.validation.run import validate as run
    from walk3d.validation.score import SCORED, scored_name
    from walk3d.validation.tables import table2, table3

    positive_options(threshold=threshold, speed=speed)  # whatever the references
    try:
        pred = load_result(pred_dir)  # the reader of walk3d verify, report and animate
    except (OSError, ValueError) as exc:
        fail(f"cannot read the prediction {pred_dir}: {' '.join(str(exc).split())}")
    target = out if out is not None else os.path.join(pred_dir, VALIDATION_FOLDER)
    try:
        check_validation_folder(target, "--out", home=pred_dir)  # not in another result
        check_validation_folder(target, "--out")  # in DIR only as DIR/validation (run()'s rule)
    except ValueError as exc:
        fail(str(exc))
    try:
        with console.status("walk3d: validating"), warning_lines():  # never numpy's form
            v = run(
                {"prediction": pred}, reference, target,
                threshold=threshold, speed=speed, forward=forward,
            )  # fmt: skip
    except OutputWriteError as exc:
        fail(str(exc), code=EXIT_WRITE)
    except (OSError, DataFileError, ValueError, KeyError) as exc:
        fail(" ".join(str(exc).split()))
    reason = warn_if_invalid(pred_dir, pred.summary)
    mark = " (NOT CONVERGED)" if did_not_converge(pred.summary) else " (NOT WALKING)"
    console.print(table2(v, f"Table 2: {pred_dir} vs {v.reference.name}{mark if reason else ''}"))
    figs = v.score.figures if v.score is not None else {}
    if "knee_loading_peak_deg" in figs:
        console.print(
            f"knee peak in loading (0-40 %): {figs['knee_loading_peak_deg']:.1f} deg, "
            f"measured {figs['knee_loading_peak_measured_deg']:.1f} deg",
            markup=False,
        )
    if v.score is not None and v.score.partial:
        names = ", ".join(scored_name(key) for key in v.score.missing)
        sys.stderr.write(f"walk3d: warning: the reference lacks scored quantities ({names}): "
                         "the score is partial, over the others only, and not comparable with "
                         "a full one\n")  # fmt: skip
    partial = f"PARTIAL, without {len(v.score.missing)} of {len(SCORED)} scored quantities; " if (
        v.score is not None and v.score.partial) else ""  # fmt: skip
    if v.score is not None and v.score.failed is not None:
        console.print(f"score {v.score.total:.3f} ({partial}failed: {v.score.failed}; "
                      "score.json)", markup=False)  # fmt: skip
    elif v.score is not None:
        console.print(f"score {v.score.total:.3f} ({partial}the yardstick's errors over their "
                      "bars, 1 = at the bar; score.json)", markup=False)  # fmt: skip
    if v.table3:
        console.print(table3(v.table3))
    if v.fit is not None:
        worst = max(v.fit.rmse_deg.items(), key=lambda kv: kv[1])
        console.print(
            f"fit of the measured angles ({v.fit_source}): largest RMSE {worst[1]:.2f} deg "
            f"({worst[0]}); per DoF in measured_fit.csv",
            markup=False,
        )
    for note in v.notes:
        console.print(f"note: {note}", markup=False)
    console.print(f"written to {target}: " + ", ".join(p.name for p in v.files.values()),
                  markup=False)  # fmt: skip


@app.command(short_help="Fit the foot roll-over and transition ratios to a trial.")
def calibrate(
    ik: Annotated[
        str, typer.Option("--ik", help="IK .mot of a measured trial.", callback=input_file)
    ],
    grf: Annotated[
        str, typer.Option("--grf", help="GRF .mot of the same trial.", callback=input_file)
    ],
    out: Annotated[
        str,
        typer.Option(
            "--out",
            help="Calibration file to write (.json), with its figures "
            "OUT_rollover.png and OUT_transition.png beside it.",
        ),
    ],
    mass: Mass = 68.8,
    height: Height = 1.77,
    sex: Sex = "male",
    threshold: PlateThreshold = 20.0,
    speed: BeltSpeed = None,
) -> None:
    """Fit the stance-foot roll-over and the double-support transition ratios to a trial and
    write them to a calibration file, with the figures OUT_rollover.png and
    OUT_transition.png beside it: all three or none. Exit code 2 for bad input (also an --out
    that is not .json, is the trial's file, lies in a walk3d result folder or is a file other
    than an earlier calibration, or figures there without one), 3 if they cannot be written
    (nothing is changed)."""
    from walk3d.body.model import build_body
    from walk3d.calibration.calibrate import calibrate_from_trial, check_calibration_out
    from walk3d.calibration.tables import calibration_table
    from walk3d.io.errors import DataFileError, OutputWriteError

    positive_options(mass=mass, height=height, threshold=threshold, speed=speed)  # before work
    try:  # the API's check: not an input, a result's file, a user's file or their figures
        check_calibration_out(out, ik, grf, option="--out")
    except ValueError as exc:
        fail(str(exc))
    if sex not in ("male", "female"):
        fail(f"--sex must be 'male' or 'female', got {sex!r}")
    try:
        body = build_body(mass, height, sex)
    except ValueError as exc:
        fail(str(exc))
    try:
        with console.status("walk3d: calibrating"):
            result = calibrate_from_trial(ik, grf, body, out, threshold=threshold, speed=speed)
    except OutputWriteError as exc:
        fail(str(exc), code=EXIT_WRITE)
    except (OSError, DataFileError, ValueError) as exc:
        fail(" ".join(str(exc).split()))
    console.print(calibration_table(result, f"walk3d calibrate -> {out}"))
    console.print("units: forces N/kg, moments N m/kg; figures: " +
                  ", ".join(str(p) for p in result.figures), markup=False)  # fmt: skip
