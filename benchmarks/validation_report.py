"""Regenerate ``docs/validation.md``: walk3d against the Falisse et al. (2019) subject.

    python benchmarks/validation_report.py --tor out/falisse_tor --en out/falisse_en

Both prediction folders are optional: without them the measured-gait sections (descriptors,
calibration, Table 3 measurement columns, walk3d's inverse dynamics on the measured motion) are
written and Table 2's prediction columns say what to run. The subject: 62 kg (the data set's
model mass), 1.70 m and female (Falisse et al. 2019, J R Soc Interface 16:20190402,
supplementary material: "female; age: 35 years; height: 170 cm; mass: 62 kg"). Figures go to
``docs/validation/`` (``--figures``). Nothing here runs an optimization.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from walk3d.body.model import build_body  # noqa: E402
from walk3d.calibration.calibrate import calibrate_from_trial  # noqa: E402
from walk3d.calibration.figures import rollover_figure, transition_figure  # noqa: E402
from walk3d.io import read_cycle_table, read_storage  # noqa: E402
from walk3d.io.atomic import atomic_write_text  # noqa: E402
from walk3d.model import terms  # noqa: E402
from walk3d.problem.settings import recorded_settings  # noqa: E402
from walk3d.results.prediction import load_result  # noqa: E402
from walk3d.trials.descriptors import descriptors_from_trial  # noqa: E402
from walk3d.trials.kinematics import kinematics_from_table  # noqa: E402
from walk3d.validation.compare import compare  # noqa: E402
from walk3d.validation.criteria import criteria_from_reference  # noqa: E402
from walk3d.validation.figures import comparison_figures  # noqa: E402
from walk3d.validation.measured import fit_measured_gait, measured_prediction  # noqa: E402
from walk3d.validation.reference import reference_from_table  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
MASS, HEIGHT, SEX = 62.0, 1.70, "female"
PAPER = {  # paper Table 2: (C_en, C_tor) RMSE on its own subject
    "grf:grf_fore_aft": (1.00, 0.65), "grf:grf_vertical": (2.03, 1.79),
    "grf:grf_lateral": (0.65, 0.65), "moment:ankle_dorsiflexion": (0.57, 0.51),
    "moment:knee_flexion": (0.21, 0.49), "moment:hip_adduction": (0.38, 0.35),
    "moment:hip_rotation": (0.11, 0.09), "moment:hip_flexion": (0.33, 0.31),
    "moment:lumbar_bending": (0.51, 0.17), "moment:lumbar_rotation": (0.10, 0.05),
    "moment:lumbar_extension": (0.38, 0.36), "moment:neck_flexion": (0.03, 0.01),
    "angle:ankle_dorsiflexion": (7.46, 4.02), "angle:knee_flexion": (30.96, 7.64),
    "angle:hip_adduction": (9.37, 6.92), "angle:hip_rotation": (18.25, 12.89),
    "angle:hip_flexion": (8.11, 8.33), "angle:lumbar_bending": (3.11, 5.76),
    "angle:lumbar_rotation": (5.85, 6.14), "angle:lumbar_extension": (5.10, 3.02),
    "angle:arm_flex": (8.95, 7.45), "angle:elbow_flex": (19.26, 38.24),
    "angle:neck_flexion": (11.55, 2.56),
}  # fmt: skip
PRESET = terms.DEFAULT_PRESET
HEADLINE = {"grf:grf_vertical": 1.79, "angle:knee_flexion": 7.64, "angle:hip_flexion": 8.33}
PAPER_TABLE3 = {"C_en": (227.14, 89, 9, 2), "C_tor": (8.47, 46, 38, 16)}


def _f(v, digits=2) -> str:
    return "—" if v is None or (isinstance(v, float) and math.isnan(v)) else f"{v:.{digits}f}"


def _rel(a, b) -> str:
    if a is None or b is None or math.isnan(a) or math.isnan(b) or b == 0:
        return "—"
    return f"{100 * (a - b) / b:+.0f} %"


def predict_commands(d, data: Path) -> list[str]:
    """The three predictions, run from the repository root (data path relative to it)."""
    rel = Path(os.path.relpath(data.resolve(), REPO))
    ik, grf = rel / "gait_1_ik.mot", rel / "gait_1_grf.mot"
    common = f"--mass {MASS:g} --height {HEIGHT:g} --sex {SEX}"
    return [f"walk3d predict --from-trial {ik} --grf {grf} {common} --criterion {c} "
            f"--out out/falisse_{c}" for c in ("tor", "en", PRESET)]  # fmt: skip


def _predictions(args) -> dict:
    out = {}
    for key, folder in (("C_en", args.en), ("C_tor", args.tor), (PRESET, args.preset)):
        if folder is not None:
            out[key] = load_result(folder)
    return out


def _table2(preds: dict, comps: dict, floor) -> list[str]:
    lines = [
        "| quantity | unit | measured SD | paper C_en | paper C_tor | walk3d C_en | walk3d C_tor "
        f"| walk3d {PRESET} | C_tor vs C_en | walk3d ID of measured motion |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for row in floor.rows:
        q = row.quantity
        p_en, p_tor = PAPER.get(q.key, (None, None))
        r = {k: comps[k].row(q.key).rmse if k in comps and row.status == "ok" else None
             for k in ("C_en", "C_tor", PRESET)}  # fmt: skip
        lines.append(
            f"| {q.label} | {q.unit} | {_f(row.reference_sd)} | {_f(p_en)} | {_f(p_tor)} "
            f"| {_f(r['C_en'])} | {_f(r['C_tor'])} | {_f(r[PRESET])} "
            f"| {_rel(r['C_tor'], r['C_en'])} | "
            + (_f(row.rmse) if row.status == "ok" else row.status)
            + " |"
        )
    return lines


def _table2_fit(comps: dict, floor) -> list[str]:
    """RMSE as a fraction of the measured range, r and R² per criterion."""
    keys = [k for k in ("C_en", "C_tor", PRESET) if k in comps]
    head = (
        "| quantity | measured range | "
        + " | ".join(f"{k} RMSE/range | {k} r | {k} R²" for k in keys)
        + " |"
    )
    lines = [head, "|---|---|" + "---|" * (3 * len(keys))]
    for row in floor.rows:
        if row.status != "ok":
            continue
        cells = []
        for k in keys:
            c = comps[k].row(row.quantity.key)
            cells += [_f(c.rmse_of_range), _f(c.r), _f(c.r2)]
        span = comps[keys[0]].row(row.quantity.key).reference_range if keys else None
        lines.append(f"| {row.quantity.label} | {_f(span)} | " + " | ".join(cells) + " |")
    return lines


def _table3(rows: list[tuple[str, dict]]) -> list[str]:
    lines = ["| source | criterion | total | z (sagittal) | x (frontal) | y (transverse) |",
             "|---|---|---|---|---|---|"]  # fmt: skip
    for crit in ("C_en", "C_tor"):
        tot, z, x, y = PAPER_TABLE3[crit]
        lines.append(f"| paper, measurement (own subject) | {crit} | {tot} | {z} % | {x} % "
                     f"| {y} % |")  # fmt: skip
        for label, c in rows:
            t = c[crit]["total"]
            cells = [f"{100 * c[crit][k] / t:.0f} % ({c[crit][k]:.3g})" for k in "zxy"]
            lines.append(f"| {label} | {crit} | {t:.4g} | " + " | ".join(cells) + " |")
    return lines


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tor", type=Path, help="prediction folder under C_tor")
    ap.add_argument("--en", type=Path, help="prediction folder under C_en")
    ap.add_argument("--preset", type=Path, help=f"prediction folder under the {PRESET} preset")
    ap.add_argument("--data", type=Path, default=REPO.parent / "shared/data/falisse2019")
    ap.add_argument("--out", type=Path, default=REPO / "docs/validation.md")
    ap.add_argument("--figures", type=Path, default=None, help="default: <out dir>/validation")
    args = ap.parse_args(argv)
    data = args.data
    needed = ["gait_1_ik.mot", "gait_1_grf.mot", "cycle_right_leg_mean_sd.csv"]
    if not all((data / n).is_file() for n in needed):
        print(f"validation_report: the Falisse 2019 data is not in {data}", file=sys.stderr)
        return 2
    figs = args.figures or args.out.parent / "validation"
    rel = os.path.relpath(figs, args.out.parent)
    body = build_body(MASS, HEIGHT, SEX)
    ik = read_storage(data / "gait_1_ik.mot")
    d = descriptors_from_trial(ik, data / "gait_1_grf.mot")
    cal = calibrate_from_trial(data / "gait_1_ik.mot", data / "gait_1_grf.mot", body, None)
    rollover_figure(cal.rollover_samples, cal.calibration.rollover(), body.rollover,
                    figs / "rollover.png")  # fmt: skip
    transition_figure(cal.transition, figs / "transition.png")
    table = read_cycle_table(data / "cycle_right_leg_mean_sd.csv")
    reference = reference_from_table(table, mass=MASS, name="Falisse 2019, 11 trials")
    fit = fit_measured_gait(kinematics_from_table(table, d.period), body, period=d.period,
                            double_support=d.double_support, right_heel_strike=0.0,
                            speed=d.speed)  # fmt: skip
    floor = compare(measured_prediction(fit, "Falisse mean cycle"), reference,
                    "walk3d ID of measured motion")  # fmt: skip
    comparison_figures([floor], figs, prefix="measured_")
    crit_ref, _ = criteria_from_reference(reference, body, d.period)
    preds = _predictions(args)
    comps = {k: compare(p, reference, f"prediction {k}") for k, p in preds.items()}
    if comps:
        comparison_figures(list(comps.values()), figs, prefix="prediction_")
    t3 = [(f"walk3d prediction {k}", p.summary["objective"]) for k, p in preds.items()
          if isinstance(p.summary.get("objective"), dict)]  # fmt: skip
    t3 += [("measurement: OpenSim ID moments, walk3d strengths", crit_ref),
           ("measurement: walk3d ID of fitted measured motion", fit.criteria)]  # fmt: skip
    text = _document(args, d, cal, fit, floor, preds, comps, t3, rel, data)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(args.out, text)
    print(f"wrote {args.out} and figures in {figs}")
    return 0


MOMENTS = (
    "Joint moments are internal moments as OpenSim's inverse dynamics reports them: each "
    "coordinate's generalized force in N m per kg of body mass, positive when it would "
    "drive the coordinate positive (hip flexor, knee flexor, ankle dorsiflexor). A "
    "prediction's moments are the columns of its `inverse_dynamics.sto` "
    "(`hip_flexion_r_moment`, `knee_angle_r_moment`, `ankle_angle_r_moment`) divided by its "
    "body mass. A measured `knee_angle_moment` takes the sign of the knee angle "
    "(gait2392-family models, this subject's included, are negative in flexion, so it "
    "flips), Winter's extensor-positive moments flip, and storages in N m are divided by "
    "the prediction's body mass (validate a prediction of the measured subject). Both sides "
    "are read over the same 0–100 % from right heel strike. The sagittal hip, knee and "
    "ankle rows (r and RMSE in N m/kg) are issue #41's moment figures: `python "
    "benchmarks/realism.py` prints them for the Falisse prediction against the 11-trial "
    "mean, trial `gait_1` and Winter. The shared yardstick `../shared/tools/realism.py` has "
    "no moment rows; with its heel strike (0–1 sample later, docs/criteria.md) and its knee "
    "sign, `inverse_dynamics.sto` gives the same numbers "
    "(`tests/validation/test_moment_rows.py`)."
)
"""docs/validation.md's paragraph on the joint-moment rows."""


def _document(args, d, cal, fit, floor, preds, comps, t3, rel, data) -> str:
    c = cal.calibration
    q = c.quality["rollover"]
    r = c.ratios
    lines = [
        "# Validation against measured walking (Falisse et al. 2019 subject)",
        "",
        "Generated by `python benchmarks/validation_report.py"
        + (f" --tor {args.tor}" if args.tor else "")
        + (f" --en {args.en}" if args.en else "")
        + (f" --preset {args.preset}" if args.preset else "")
        + "`; do not edit by hand.",
        "",
        "Reference: `falisse2019/cycle_right_leg_mean_sd.csv` (mean ± SD of 11 overground trials "
        "of one subject, right leg, 0 % = right heel strike; MIT licence, Falisse et al. 2019, "
        "J R Soc Interface 16:20190402). Subject: 62 kg, 1.70 m, female (the paper's "
        "supplementary material). The paper validated on its own subject (68.8 kg, 1.77 m); its "
        "numbers are quoted for scale, not as a like-for-like comparison.",
        "",
        "## Descriptors (trial `gait_1`)",
        "",
        f"V = {d.speed:.4f} m/s, T = {d.period:.4f} s ({d.period_method}), "
        f"Td = {d.double_support:.4f} s, stance {100 * d.stance_fraction:.1f} % of the cycle "
        f"({'; '.join(d.notes)}). The 11-trial mean walks a little faster (about 1.32 m/s, "
        "cycle about 1.05 s); the reference is compared in % of cycle.",
        "",
        "Predictions for this page (run on a free machine, then rerun this script):",
        "",
        "```bash",
        *predict_commands(d, data),
        "python benchmarks/validation_report.py --tor out/falisse_tor --en out/falisse_en "
        f"--preset out/falisse_{PRESET}",
        "```",
        "",
    ]
    lines += ["## Table 2: RMSE against the 11-trial mean", ""]
    if not preds:
        lines += ["**No prediction folders were given**: the walk3d C_en / C_tor columns are "
                  "empty until the commands above have been run.", ""]  # fmt: skip
    else:
        for k, p in preds.items():
            conv = p.summary.get("converged")
            inp = recorded_settings(p.summary) | {"seed": p.summary.get("seed")}
            folder = {"C_en": args.en, "C_tor": args.tor, PRESET: args.preset}[k]
            lines.append(f"* {k}: `{folder}`, converged: "
                         f"{'yes' if conv else 'NO: not a valid prediction'}; V = "
                         f"{inp.get('speed', float('nan')):.4f} m/s, T = "
                         f"{inp.get('period', float('nan')):.4f} s, Td = "
                         f"{inp.get('double_support', float('nan')):.4f} s, seed "
                         f"{inp.get('seed')}")  # fmt: skip
        lines.append("")
    lines += _table2(preds, comps, floor) + [""]
    if comps:
        lines += ["### Fit per criterion: RMSE as a fraction of the measured range, r and R²",
                  "", *_table2_fit(comps, floor), ""]  # fmt: skip
    lines += _verdict(comps)
    lines += [
        "The last column drives walk3d's inverse dynamics with the measured motion itself (the "
        "mean angles fitted with walk3d's Fourier series, below): the error walk3d's own model "
        "would keep even with a perfect prediction of the joint angles.",
        "",
        "Figures (measured mean ± SD band, prediction lines): "
        + (", ".join(f"[{g}]({rel}/prediction_{g}.png)" for g in ("grf", "moments", "angles"))
           if comps else "none yet") + ". walk3d ID of the measured motion: "
        + ", ".join(f"[{g}]({rel}/measured_{g}.png)" for g in ("grf", "moments", "angles")) + ".",
        "",
        MOMENTS,
        "",
        "## Table 3: criteria and their x/y/z split",
        "",
    ]  # fmt: skip
    lines += _table3(t3) + [""]
    worst = max(fit.rmse_deg.items(), key=lambda kv: kv[1])
    lines += [
        "C_tor uses walk3d's strengths (`body/data/parameters.toml`), not the paper's, so only "
        "the split, not the total, compares with the paper. The two measurement rows differ "
        "because walk3d's inverse dynamics on measured motion is dominated by heel-strike "
        "transients (next section); the OpenSim-moment row is the one to trust.",
        "",
        "## The measured motion through walk3d's model",
        "",
        f"Fourier fit of the mean angles (T = {d.period:.4f} s): largest error against the "
        f"measured angles {worst[1]:.2f}° ({worst[0]}); the series' own error against the "
        f"angles they were fitted to is at most {max(fit.fit_rmse_deg.values()):.2f}°. Stance "
        "legs are first projected onto walk3d's pure-pitch stance foot (the measured foot rolls "
        "and yaws), which moves the stance-leg angles by (RMS over stance, deg): "
        + ", ".join(f"{k} {v:.1f}" for k, v in fit.projection_change_deg.items()) + ". "
        f"Double-support contact residual {1000 * fit.evaluation.contact_residual_m:.0f} mm, "
        f"root-switch continuity residual {1000 * fit.evaluation.continuity_residual_m:.0f} mm.",
        "",
        "Where it is poor: the ground reaction right after each heel strike. walk3d computes "
        "the motion from the stance foot and switches root at heel strike; the measured motion "
        "does not close walk3d's double-support loop exactly, so the new root gives a different "
        "body acceleration, and the transition function hands that reaction to the trailing "
        "foot. The fore-aft force and the ankle and knee moments then spike in double support "
        "(see the `measured_*` figures). A prediction does not suffer from this, because the "
        "optimizer enforces the closed loop.",
        "",
        "## Calibration from `gait_1` (Figs. 2 and 3)",
        "",
        f"Roll-over: {q['stances']} stances, foot rotation {q['theta_range_deg'][0]:.0f}° to "
        f"{q['theta_range_deg'][1]:.0f}°, spline RMS {1000 * q['rms_m']:.1f} mm; the ankle "
        f"drifts {1000 * q['flat_drift_m']:.0f} mm while the foot is flat, which measures how "
        "far walk3d's de Leva segment lengths are from the subject's: walk3d's thigh is "
        f"{body_lengths()} [Figure]({rel}/rollover.png).",
        "",
        f"Transition ratios (right-foot signs): μx = {r.mu_x:.3f}, μz = {r.mu_z:.3f}, "
        f"ϖx = {r.varpi_x:.3f}, ϖy = {r.varpi_y:.3f}. RMSE of Eqs. 6–8 against the trailing "
        "foot's plate in double support (N/kg, N m/kg): "
        + ", ".join(f"{k} {v:.3f}" for k, v in cal.transition.rmse.items())
        + "; with walk3d's default heel-strike ratios: "
        + ", ".join(f"{k} {v:.3f}" for k, v in cal.transition.rmse_heel_strike_ratios.items())
        + f". [Figure]({rel}/transition.png). The cubic exponential unloads the trailing foot "
        "earlier than the plate shows (one double support on two plates in this trial).",
        "",
        "The predictions above use walk3d's default roll-over and ratios. `walk3d calibrate "
        "--ik IK.mot --grf GRF.mot --out calib.json` writes this calibration, and `walk3d "
        "predict --calibration calib.json` predicts with it (not run for this page).",
        "",
    ]  # fmt: skip
    return "\n".join(lines)


def body_lengths() -> str:
    """walk3d's thigh and shank against the subject's scaled OpenSim model (subject1.osim of
    antoinefalisse/3dpredictsim: knee 0.3969 m below the hip, ankle 0.4157 m below the knee)."""
    from walk3d.body.anthropometry import scaled_de_leva

    d = scaled_de_leva(MASS, HEIGHT, SEX)
    return (f"{d['thigh'].length:.3f} m against 0.397 m, its shank {d['shank'].length:.3f} m "
            "against 0.416 m (knee and ankle centres of the subject's scaled OpenSim model, "
            "`OpenSimModel/subject1/subject1.osim` in antoinefalisse/3dpredictsim).")  # fmt: skip


def _verdict(comps: dict) -> list[str]:
    if "C_tor" not in comps:
        return []
    out = ["Against the paper's C_tor headline values (on its own subject):", ""]
    for key, paper in HEADLINE.items():
        row = comps["C_tor"].row(key)
        word = "better" if row.rmse < paper else "worse"
        out.append(f"* {row.quantity.label}: {_f(row.rmse)} {row.quantity.unit} vs {paper} "
                   f"({word})")  # fmt: skip
    poor = [r for r in comps["C_tor"].rows if r.status == "ok" and r.quantity.key in PAPER
            and r.rmse > 1.5 * PAPER[r.quantity.key][1]]  # fmt: skip
    if poor:
        names = ", ".join(f"{r.quantity.label} ({r.quantity.group})" for r in poor)
        out.append(f"* more than 1.5 x the paper's C_tor RMSE: {names}")
    return out + [""]


if __name__ == "__main__":
    sys.exit(main())
