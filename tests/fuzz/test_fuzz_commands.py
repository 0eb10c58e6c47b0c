"""The fuzz set (``python -m pytest -m fuzz``): damaged input files through every command that
reads them, in this process, each under a time limit.

Each case takes one valid seed file (:data:`SEEDS`: measured trials and tables from the shared
data, a result folder and other files made without a solve), damages it in one way
(:mod:`fuzz_mutations`, drawn from the case's name) and runs ``walk3d validate``, ``calibrate``,
``verify``, ``animate``, ``report``, ``compare``, ``track``, ``audit``, ``predict``
(``--calibration``, ``--criterion``, ``--from-trial``) or ``fit-criterion`` on it, or the TRC
and C3D trial readers. It passes when the command ends in an allowed exit code (0 or 2;
``verify`` also 1) with no traceback and, on failure, one ``walk3d: error:`` line, within
:data:`fuzz_run.LIMIT_S`. The solves of ``predict``, ``track`` and ``fit-criterion`` are
replaced by a check that no NaN or infinite value reaches them: no case solves. Each command
also runs on each undamaged seed (:data:`CONTROLS`), and must succeed there.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from fuzz_mutations import KINDS, case_rng, mutate
from fuzz_run import INTERNAL, LIMIT_S, check_outcome, log_case, non_finite, run_cli, time_limit
from helpers import replace_result_file, shared_data_dir

pytestmark = pytest.mark.fuzz

SEEDS: dict[str, tuple[str, str, str]] = {
    "ik": ("table", "shared", "falisse2019/gait_1_ik.mot"),
    "grf": ("table", "shared", "falisse2019/gait_1_grf.mot"),
    "id": ("table", "shared", "falisse2019/gait_1_id.sto"),
    "table": ("table", "shared", "falisse2019/cycle_right_leg_mean_sd.csv"),
    "winter": ("table", "shared", "winter/Winter_normal.csv"),
    "trc": ("table", "shared", "opensim_subject01/subject01_walk1.trc"),
    "ik01": ("table", "shared", "opensim_subject01/subject01_walk1_ik.mot"),
    "grf01": ("table", "shared", "opensim_subject01/subject01_walk1_grf.mot"),
    "c3d": ("c3d", "made", "walk_01.c3d"),
    "calibration": ("json", "made", "calib.json"),
    "criterion": ("toml", "made", "weights.toml"),
    "trials": ("toml", "made", "trials.toml"),
    "summary": ("json", "result", "summary.json"),
    "npz": ("npz", "result", "result.npz"),
    "manifest": ("json", "result", "manifest.json"),
    "motion": ("table", "result", "motion.mot"),
    "grf_mot": ("table", "result", "grf.mot"),
    "grf_xml": ("xml", "result", "grf.xml"),
    "id_sto": ("table", "result", "inverse_dynamics.sto"),
    "osim": ("xml", "result", "model.osim"),
    "tracking_csv": ("table", "tracked", "tracking.csv"),
    "binding_csv": ("table", "tracked", "binding.csv"),
    "audit_json": ("json", "tracked", "audit.json"),
    "campaign_json": ("json", "campaign", "campaign.json"),
    "record_json": ("json", "campaign", "starts/seed_000000/record.json"),
    "ranking_csv": ("table", "campaign", "ranking.csv"),
    "best_summary": ("json", "campaign", "best/summary.json"),
}
"""seed: (format of :data:`fuzz_mutations.KINDS`, where it comes from, its path there)."""
FOLDERS = ("result", "tracked", "campaign")
"""Where seeds are files of a folder, damaged in a copy of it."""

PLAN = (
    ("validate", "ik", 15), ("validate", "grf", 15), ("validate", "id", 15),
    ("validate", "table", 15), ("validate", "c3d", 22), ("validate", "summary", 11),
    ("validate", "npz", 13), ("validate", "manifest", 11),
    ("calibrate", "ik", 15), ("calibrate", "grf", 15), ("calibrate", "ik01", 15),
    ("calibrate", "grf01", 15),
    ("track", "ik", 15), ("track", "grf", 15), ("track", "table", 15),
    ("verify", "summary", 11), ("verify", "npz", 13), ("verify", "manifest", 11),
    ("verify", "motion", 15), ("verify", "grf_mot", 15), ("verify", "grf_xml", 10),
    ("verify", "id_sto", 15), ("verify", "osim", 10),
    ("animate", "summary", 11), ("animate", "npz", 13), ("animate", "manifest", 11),
    ("report", "summary", 11), ("report", "npz", 13), ("report", "manifest", 11),
    ("report", "table", 15), ("report", "winter", 15),
    ("report", "tracking_csv", 15), ("report", "binding_csv", 15), ("report", "audit_json", 11),
    ("report", "campaign_json", 11), ("report", "record_json", 11), ("report", "ranking_csv", 15),
    ("report", "best_summary", 11),
    ("compare", "summary", 11), ("compare", "npz", 13), ("compare", "manifest", 11),
    ("audit", "summary", 11), ("audit", "npz", 13), ("audit", "manifest", 11),
    ("predict", "calibration", 22), ("predict", "criterion", 22), ("predict", "ik", 15),
    ("predict", "grf", 15), ("fit-criterion", "trials", 22),
    ("read_trc", "trc", 30), ("load_c3d_trial", "c3d", 22),
)  # fmt: skip
"""(command, seed, number of cases): the cases cycle through the seed format's mutations."""

CASES = [(command, seed, KINDS[SEEDS[seed][0]][(row + i) % len(KINDS[SEEDS[seed][0]])], i)
         for row, (command, seed, n) in enumerate(PLAN) for i in range(n)]  # fmt: skip
"""(command, seed, mutation, index); each row of :data:`PLAN` starts one mutation further."""
CONTROLS = sorted({(command, seed, "none", 0) for command, seed, _ in PLAN})
"""Each command on each undamaged seed: it must succeed, so that a refusal in the cases is
the mutation's doing."""
ALLOWED = {"verify": (0, 1, 2)}
"""Exit codes besides 0 and 2 (bad input): verify's 1 is a replay outside its bars."""
TRIO = {"ik": "falisse2019/gait_1_ik.mot", "grf": "falisse2019/gait_1_grf.mot",
        "id": "falisse2019/gait_1_id.sto"}  # fmt: skip
SUBJECT01 = {"ik01": "opensim_subject01/subject01_walk1_ik.mot",
             "grf01": "opensim_subject01/subject01_walk1_grf.mot"}  # fmt: skip
"""The treadmill trial: its belt speed is given (1.12 m/s, the shared data's README)."""


def _seed_file(seed: str, made: dict[str, Path], request) -> Path:  # noqa: ANN001
    _, source, rel = SEEDS[seed]
    if source == "shared":
        return request.getfixturevalue("data_dir") / rel
    return made[source] / rel if source in FOLDERS else made[seed]


def _place(seed: str, data: bytes, tmp: Path, made: dict[str, Path]) -> Path:
    """The damaged file in the case's folder: in a copy of the result folder (its manifest
    updated, unless the manifest is the damaged file), else at ``tmp/data/<its path>``."""
    _, source, rel = SEEDS[seed]
    if source in FOLDERS:
        work = Path(shutil.copytree(made[source], tmp / "pred"))
        inside = work / rel
        if inside.name in _listed(inside.parent / "manifest.json"):
            replace_result_file(inside.parent, inside.name, data)
        else:  # the manifest itself, or a file no manifest lists
            inside.write_bytes(data)
        return work
    path = tmp / "data" / rel
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(data)
    return path


def _listed(manifest: Path) -> set[str]:
    """The files a result folder's manifest lists (none without a manifest)."""
    if not manifest.is_file():
        return set()
    return set(json.loads(manifest.read_text(encoding="utf-8"))["files"])


def _trial(seed: str, target: Path, request) -> dict[str, Path]:  # noqa: ANN001
    """The Falisse trial's IK, GRF and ID files (the treadmill's IK and GRF for its seeds),
    ``target`` in place of the damaged one."""
    shared = request.getfixturevalue("data_dir")
    if seed in SUBJECT01:
        files = {k[:-2]: shared / rel for k, rel in SUBJECT01.items()}
        return files | {seed[:-2]: target}
    files = {k: shared / rel for k, rel in TRIO.items()}
    return files | ({seed: target} if seed in files else {})


def _args(command: str, seed: str, i: int, target: Path, tmp: Path, made, request) -> list:  # noqa: ANN001
    """The command line of a case (``target``: the damaged file, or the folder holding it)."""
    from_result = SEEDS[seed][1] in FOLDERS
    pred, good = (target if from_result else made["result"]), made["result"]
    if command == "validate":  # the damaged file of a trial with the others, or alone
        refs = list(_trial(seed, target, request).values()) if seed in TRIO else \
            [made["table"] if from_result else target]  # fmt: skip
        refs = [target] if seed in TRIO and i % 3 == 2 else refs
        return ["validate", pred, *[a for r in refs for a in ("--reference", r)], "--out",
                tmp / "validation"]  # fmt: skip
    if command in ("calibrate", "track") or (command == "predict" and seed in TRIO):
        t = _trial(seed, target, request)
        if command == "calibrate":
            subject = ["--mass", "72.6", "--speed", "1.12"] if seed in SUBJECT01 else \
                ["--mass", "62"]  # fmt: skip
            return ["calibrate", "--ik", t["ik"], "--grf", t["grf"], "--out", tmp / "c.json",
                    *subject]  # fmt: skip
        if command == "predict":
            return ["predict", "--out", tmp / "p", "--from-trial", t["ik"], "--grf", t["grf"]]
        given = ["--table", target, "--speed", "1.3", "--period", "1.05", "--double-support",
                 "0.12"] if seed == "table" else ["--ik", t["ik"], "--grf", t["grf"]]  # fmt: skip
        return ["track", "--out", tmp / "t", "--mass", "62", *given]
    if command == "verify":
        return ["verify", pred, "--timeout", "30"]
    if command == "animate":
        return ["animate", pred, "--cycles", "1", "--fps", "4",
                *(["--out", tmp / "a.mp4"] if i % 2 else [])]  # fmt: skip
    if command == "report":
        data = ["--data", tmp / "data"] if not from_result else []
        out = ["--out", tmp / "r.html"] if i % 2 or not from_result else []
        return ["report", pred, *out, *data]
    if command == "compare":
        pair = [pred, good] if i % 2 == 0 else [good, pred]
        return ["compare", *pair, *(["--out", tmp / "cmp"] if i % 3 == 0 else [])]
    if command == "audit":
        pair = [pred, good] if i % 2 == 0 else [good, pred]
        return ["audit", *pair, "--out", tmp / "audit.json"]
    if command == "predict":
        option = "--calibration" if seed == "calibration" else "--criterion"
        return ["predict", "--out", tmp / "p", option, target]
    return ["fit-criterion", target, "--parameter", "impact", "--out", tmp / "fit"]


def _no_solve(monkeypatch) -> None:  # noqa: ANN001
    """The solves of predict, track and fit-criterion replaced by a check of their inputs."""
    import typer

    import walk3d.fitting.run
    import walk3d.pipeline
    import walk3d.tracking

    def solve(*args, **kwargs) -> None:
        bad = non_finite(args[:2]) + non_finite(
            {k: v for k, v in kwargs.items() if k not in ("on_stage", "on_progress")}
        )
        assert not bad, f"NaN or infinite values reach the solve: {bad[:5]}"
        raise typer.Exit(0)

    monkeypatch.setattr(walk3d.pipeline, "predict", solve)
    monkeypatch.setattr(walk3d.tracking, "write_tracking", solve)
    monkeypatch.setattr(walk3d.fitting.run, "fit_criterion", solve)


def _read(command: str, path: Path, name: str) -> None:
    """A reader on the damaged file: its result, or one line naming the file (DataFileError)
    or, for a C3D trial whose events do not give a gait (ValueError), what is missing."""
    from walk3d.io import DataFileError, read_trc
    from walk3d.trials.trial import load_c3d_trial

    reader = {"read_trc": read_trc, "load_c3d_trial": load_c3d_trial}[command]
    with time_limit(LIMIT_S, name):
        try:
            reader(path)
        except DataFileError as exc:
            assert "\n" not in str(exc) and str(exc).startswith(path.name), str(exc)
            assert not INTERNAL.search(str(exc)), str(exc)
        except ValueError as exc:
            assert command == "load_c3d_trial" and "\n" not in str(exc), str(exc)
            assert not INTERNAL.search(str(exc)), str(exc)


@pytest.mark.parametrize(("command", "seed", "kind", "index"), CONTROLS + CASES,
                         ids=[f"{c}-{s}-{k}-{i}" for c, s, k, i in CONTROLS + CASES])  # fmt: skip
def test_a_damaged_file_ends_in_a_result_or_one_line(
    command, seed, kind, index, made_seeds, memory_cap, request, tmp_path, monkeypatch
):
    name = f"{command}-{seed}-{kind}-{index}"
    valid = _seed_file(seed, made_seeds, request).read_bytes()
    data = valid if kind == "none" else mutate(valid, SEEDS[seed][0], kind, case_rng(name))
    target = _place(seed, data, tmp_path, made_seeds)
    if command in ("read_trc", "load_c3d_trial"):
        _read(command, target, name)
        return
    monkeypatch.setenv("WALK3D_SHARED_DATA", str(shared_data_dir()))  # report's bands
    _no_solve(monkeypatch)
    outcome = run_cli(_args(command, seed, index, target, tmp_path, made_seeds, request), name)
    log_case(name, outcome)
    check_outcome(outcome, ((0, 1) if command == "verify" else (0,)) if kind == "none" else
                  ALLOWED.get(command, (0, 2)))  # fmt: skip
