"""walk3d predict and walk3d compile: bad input is one line and exit code 2 (no solve or
compile is started); a prediction that did not converge is written, labelled and exits 1."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

BAD = [
    (["--speed", "0"], "speed"),
    (["--speed", "-1.2"], "speed"),
    (["--period", "0"], "period"),
    (["--period", "-1"], "period"),
    (["--double-support", "0"], "double-support"),
    (["--double-support", "-0.1"], "double-support"),
    (["--period", "1.08", "--double-support", "0.54"], "double-support duration must be 2%-30%"),
    (["--period", "0.1"], "period must be in [0.6, 2.5] s"),
    (["--period", "3", "--double-support", "0.3"], "period must be in [0.6, 2.5] s"),
    (["--double-support", "0.54"], "fits no predicted period"),
    (["--period", "abc"], "--period must be a positive number of seconds or auto"),
    (["--double-support", "inf"], "--double-support must be"),
    (["--speed", "nan"], "finite"),
    (["--mass", "3"], "mass"),
    (["--height", "4"], "height"),
    (["--criterion", "fun"], "criterion"),
    (["--criterion", "tor=1,bogus=1"], "unknown criterion term 'bogus'"),
    (["--criterion", "tor=1,accel=-2"], "criterion weight of accel"),
    (["--criterion", "accel=1"], "exactly one of tor and en"),
    (["--criterion", "/nonexistent/weights.toml"], "weights.toml"),
    (["--solver", "magic"], "solver"),
    (["--speed", "fast"], "speed"),
    (["--linear-solver", "ma99"], "linear_solver"),
    (["--perturbation", "-0.1"], "perturbation"),
    (["--perturbation", "2"], "perturbation"),
    (["--restarts", "-1"], "restarts"),
    (["--restarts", "11"], "restarts"),
    (["--max-iter", "0"], "max_iter"),
    (["--start", "nearby"], "start"),
    # what-if changes (issue #43)
    (["--strength", "ankle_x=0.5"], "unknown joint 'ankle_x'"),
    (["--strength", "ankle=0"], "strength factor of 'ankle' must be in [0.01, 10]"),
    (["--strength", "ankle=-1"], "must be in [0.01, 10]"),
    (["--strength", "ankle=1e300"], "must be in [0.01, 10], got 1e+300"),
    (["--strength", "ankle=1_0"], "ankle='1_0' is not a finite decimal number"),
    (["--strength", "neck_r=0.5"], "unknown joint 'neck_r'"),
    (["--strength", "ankle=0.5,ankle_l=0.4"], "names the same part twice"),
    (["--strength", "ankle"], "--strength takes NAME=VALUE"),
    (["--strength", "ankle=abc"], "not a finite decimal number"),
    (["--range", "ankle_dorsiflexion=5"], "--range takes DOF=MIN:MAX"),
    (["--range", "ankle_dorsiflexion=5:-5"], "is empty"),
    (["--range", "ankle_dorsiflexion=5:10"], "excludes standing"),
    (["--range", "knee_flexion=-5:500"], "is beyond ±180°"),
    (["--range", "knee_bend=-5:5"], "unknown DoF 'knee_bend'"),
    (["--added-mass", "torso=-3"], "added mass at 'torso'"),
    (["--added-mass", "backpack=3"], "unknown segment 'backpack'"),
    (["--added-mass", "torso=3,torso=4"], "names the same part twice"),
    (["--leg-length-difference", "0.5"], "length change of 'shank_r' must be within"),
    (["--leg-length-difference", "nan"], "length change of 'shank_r' must be a finite number"),
    # an HSL solver whose library cannot be loaded is refused before the solve starts
    (["--linear-solver", "ma57", "--hsl-library", "/nonexistent/libhsl.so"], "HSL solver ma57"),
    # ... and a library without an HSL solver, which MUMPS ignored (exit 0)
    (["--hsl-library", "/nonexistent/libhsl.so"], "hsl_library is the library of an HSL"),
]


@pytest.mark.parametrize("args,word", BAD)
def test_bad_input_exits_2_with_one_line(tmp_path, args, word):
    cmd = [sys.executable, "-m", "walk3d.cli", "predict", "--out", str(tmp_path / "o"), *args]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and word in lines[0], r.stderr
    assert "Traceback" not in r.stderr
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize(
    ("args", "env", "word"),
    [(["--mass", "3"], {}, "mass"), (["--speed", "0"], {}, "speed"),
     (["--calibration", "/nonexistent/calib.json"], {}, "calib.json"),
     ([], {"CC": "/nonexistent/cc"}, "no C compiler")],
)  # fmt: skip
def test_compile_bad_input_or_no_compiler_exits_2(tmp_path, args, env, word):
    cmd = [sys.executable, "-m", "walk3d.cli", "compile", *args]
    run_env = os.environ | {"WALK3D_CACHE_DIR": str(tmp_path)} | env
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=60, env=run_env)
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and word in lines[0], r.stderr
    assert not list(tmp_path.glob("lib-*"))


def test_campaign_refuses_an_unusable_hsl_solver_before_starting(tmp_path):
    out = tmp_path / "c"
    cmd = [sys.executable, "-m", "walk3d.cli", "campaign", "--starts", "2", "--out", str(out),
           "--linear-solver", "ma27", "--hsl-library", str(tmp_path / "libhsl.so")]  # fmt: skip
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "HSL solver ma27" in lines[0], r.stderr
    assert not out.exists()


@pytest.mark.parametrize(
    ("command", "kind", "word"),
    [("predict", "cut", "cut short"), ("predict", "fifo", "not a regular file (a FIFO)"),
     ("campaign", "cut", "cut short"), ("predict", "whole", "IPOPT could not use")],
)  # fmt: skip
def test_an_hsl_library_cut_short_or_a_fifo_is_one_line_not_a_crash(tmp_path, command, kind,
                                                                     word):  # fmt: skip
    """--hsl-library of a library cut short took the process down in the dynamic loader (bus
    error, exit 135, no message) and a FIFO blocked it for ever: one line, exit 2, nothing
    written. Negative control: a whole library (CasADi's, no HSL solver in it) passes the check
    and reaches IPOPT's probe, which refuses it for want of the solver."""
    import casadi as ca

    whole = next(Path(ca.__file__).parent.glob("_casadi*.so"))
    lib = tmp_path / "libhsl.so"
    if kind == "cut":
        lib.write_bytes(whole.read_bytes()[:300_000])
    elif kind == "fifo":
        os.mkfifo(lib)
    else:
        lib = whole
    out = tmp_path / "o"
    starts = ["--starts", "2"] if command == "campaign" else []
    cmd = [sys.executable, "-m", "walk3d.cli", command, "--out", str(out), *starts,
           "--linear-solver", "ma27", "--hsl-library", str(lib)]  # fmt: skip
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=180)
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and word in lines[0] and str(lib) in lines[0], r.stderr
    assert not out.exists()


@pytest.mark.solve
def test_a_prediction_that_did_not_converge_is_written_labelled_and_exits_1(tmp_path):
    """Three iterations per stage cannot converge: after its restart the start is written
    anyway, labelled as not converged everywhere, and the command exits with code 1."""
    out = tmp_path / "o"
    cmd = [sys.executable, "-m", "walk3d.cli", "predict", "--out", str(out), "--nodes", "6",
           "--max-iter", "3", "--threads", "1", "--period", "1.08",
           "--double-support", "0.16"]  # fmt: skip
    env = os.environ | {"OPENBLAS_NUM_THREADS": "1", "COLUMNS": "200"}
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=600, env=env)
    assert r.returncode == 1, r.stderr
    assert "Traceback" not in r.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["converged"] is False and summary["attempts"] == 2
    assert {st["attempt"] for st in summary["stages"]} == {0, 1}
    assert summary["status"] == summary["stages"][-1]["status"] != "Solve_Succeeded"
    assert "NO - not a valid prediction" in r.stdout and "2 standing starts" in r.stdout
    # which BLAS IPOPT ran on (walk3d.solve.blas), in the summary and the printed table
    assert summary["blas"].startswith(("scipy-openblas32 ", "CasADi's"))
    assert f"MUMPS on {summary['blas']}" in r.stdout
    for name in ("result.npz", "motion.mot", "grf.mot", "summary.png", "report.html"):
        assert (out / name).is_file(), name
    page = (out / "report.html").read_text(encoding="utf-8")  # written last, labelled too
    assert "NOT CONVERGED" in page and "report.html" in (out / "manifest.json").read_text()


@pytest.mark.parametrize("command", ["predict", "campaign"])
def test_an_output_folder_that_cannot_be_written_is_refused_before_any_solve(tmp_path, command):
    taken = tmp_path / "result.txt"
    taken.write_text("keep me")
    extra = ["--starts", "2"] if command == "campaign" else []
    for out, word in [(taken, "is an existing file"), (taken / "sub", "cannot be created")]:
        cmd = [sys.executable, "-m", "walk3d.cli", command, "--out", str(out), *extra]
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
        assert r.returncode == 2, r.stderr
        lines = r.stderr.strip().splitlines()
        assert len(lines) == 1 and word in lines[0] and "Traceback" not in r.stderr
    assert taken.read_text() == "keep me"


def test_an_unwritable_output_folder_names_the_reason(tmp_path, monkeypatch):
    import typer

    from walk3d.cli.common import check_output_folder

    check_output_folder(str(tmp_path / "new" / "deeper"))  # negative control: writable, passes
    assert not (tmp_path / "new").exists()  # the check creates nothing
    monkeypatch.setattr(os, "access", lambda *_a, **_k: False)  # as a non-root user would see
    with pytest.raises(typer.Exit) as info:
        check_output_folder(str(tmp_path / "new"))
    assert info.value.exit_code == 2


@pytest.mark.solve
def test_ctrl_c_stops_predict_with_one_line_exit_130_and_no_output(tmp_path):
    """SIGINT while the model builds or IPOPT iterates: a line, code 130, nothing written."""
    import signal
    import time

    out = tmp_path / "o"
    cmd = [sys.executable, "-m", "walk3d.cli", "predict", "--out", str(out), "--nodes", "8",
           "--criterion", "tor", "--threads", "1"]  # fmt: skip
    env = os.environ | {"OPENBLAS_NUM_THREADS": "1"}
    default = lambda: signal.signal(signal.SIGINT, signal.SIG_DFL)  # noqa: E731 (not inherited SIG_IGN)
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                         preexec_fn=default)  # fmt: skip
    time.sleep(12)
    p.send_signal(signal.SIGINT)
    t0 = time.perf_counter()
    _, err = p.communicate(timeout=120)
    assert p.returncode == 130, err
    assert err.strip().splitlines() == ["walk3d: interrupted"], err
    assert time.perf_counter() - t0 < 15  # IPOPT stops at its next iteration, no restart
    assert not out.exists()


@pytest.mark.solve
def test_paper_flag_gives_the_papers_case_and_auto_predicts_the_descriptors(tmp_path):
    """--paper: the paper's subject, V, T, Td and C_tor, nothing predicted; without it T and Td
    are predicted (``summary.json``'s ``descriptors``). Three iterations: not converged."""
    env = os.environ | {"OPENBLAS_NUM_THREADS": "1", "COLUMNS": "200"}
    fast = ["--nodes", "6", "--max-iter", "3", "--restarts", "0", "--threads", "1"]
    outs = {}
    for name, extra in [("paper", ["--paper"]), ("auto", ["--speed", "1.2", "--mass", "60"])]:
        out = tmp_path / name
        cmd = [sys.executable, "-m", "walk3d.cli", "predict", "--out", str(out), *fast, *extra]
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=600, env=env)
        assert r.returncode == 1 and "Traceback" not in r.stderr, r.stderr
        assert "descriptors" in r.stdout and "cadence" in r.stdout
        outs[name] = json.loads((out / "summary.json").read_text())
    paper, auto = outs["paper"], outs["auto"]
    assert paper["descriptors"]["predicted"] == [] and paper["settings"]["gait"]["free"] == []
    assert (paper["descriptors"]["period"], paper["descriptors"]["double_support"]) == (1.08, 0.16)
    assert paper["settings"]["model"]["criterion"] == "tor"
    assert paper["settings"]["gait"]["mass"] == 68.8 and paper["descriptors"]["speed"] == 1.3806
    assert auto["descriptors"]["predicted"] == ["period", "double_support"]
    assert auto["settings"]["gait"]["mass"] == 60 and auto["descriptors"]["speed"] == 1.2
    assert auto["settings"]["model"]["criterion"] != "tor"


@pytest.mark.parametrize("command", [["campaign", "--starts", "1"], ["sweep", "--speeds", "1.2"]])
@pytest.mark.parametrize(
    ("option", "words"),
    [
        (["--added-mass", "torso=-2"], "added mass at 'torso'"),
        (["--leg-length-difference", "0.3"], "'shank_r'"),
    ],
)
def test_campaign_and_sweep_refuse_bad_what_if_changes(tmp_path, command, option, words):
    out = tmp_path / "o"
    cmd = [sys.executable, "-m", "walk3d.cli", *command, "--out", str(out), *option]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and words in lines[0], r.stderr
    assert not out.exists()


def test_the_equal_steps_flag_reaches_the_settings():
    """``--equal-steps`` sets ``equal_steps``; without it the key is left out (the default)."""
    from walk3d.cli.changes import changes_option
    from walk3d.problem.settings import PredictionSettings

    assert changes_option(None, None, None, equal_steps=True) == {"equal_steps": True}
    assert changes_option(None, None, None) == {}
    s = PredictionSettings(**changes_option(None, None, "torso=2", equal_steps=True))
    assert s.model.equal_steps and s.model.changes.added_mass == (("torso", 2.0),)


def test_compile_hint_names_the_command_for_the_prediction():
    """The predict table's hint gives the compile command for this sex and criterion, and says
    when other model options must be repeated (each changes what is compiled)."""
    from walk3d import api
    from walk3d.cli.commands import compile_hint

    default = compile_hint(api.settings(1.3, sex="female"))
    assert "`walk3d compile --sex female`" in default and "options" not in default
    assert "--criterion tor`" in compile_hint(api.settings(1.3, criterion="tor"))
    assert "this model's options" in compile_hint(api.settings(1.3, load_ramp=0.0))


@pytest.mark.parametrize("summary, code", [
    ({"converged": True, "gait_checks": {"looks_like_walking": True}}, 0),
    ({"converged": True, "gait_checks": {"looks_like_walking": False}}, 4),
    ({"converged": False, "gait_checks": {"looks_like_walking": False}}, 1),
])  # fmt: skip
def test_exit_code_says_whether_the_written_gait_walks(summary, code):
    from walk3d.cli.common import exit_code

    assert exit_code(summary) == code


@pytest.mark.parametrize("summary, code, words", [
    ({"converged": False, "status": "Maximum_Iterations_Exceeded",
      "gait_checks": {"looks_like_walking": False}}, 1,
     "the solve did not converge (Maximum_Iterations_Exceeded): not a valid prediction"),
    ({"converged": True, "gait_checks": {"looks_like_walking": False}}, 4,
     "the gait does not look like walking (summary gait_checks)"),
    ({"converged": True, "gait_checks": {"looks_like_walking": True}}, 0, None),
])  # fmt: skip
def test_predict_warns_in_one_line_of_a_result_that_is_not_a_valid_walk(
    capsys, summary, code, words
):
    """predict --max-iter 3 exited 1 with "NO" in its table but no warning line, which compare,
    validate and animate print; a converged walk prints none (the control)."""
    from walk3d.cli.labels import predict_exit_code

    assert predict_exit_code("X", summary) == code
    err = capsys.readouterr().err
    if words is None:
        assert err == ""
    else:
        assert err.splitlines() == [f"walk3d: warning: X: {words}"]


@pytest.mark.solve
@pytest.mark.parametrize("bar_bw", [0.5, None])
def test_a_converged_gait_that_does_not_walk_exits_4_with_one_line(tmp_path, monkeypatch, bar_bw):
    """0.6 m/s from the atlas converges at once (the entry itself). With the humps' bar raised to
    0.5 body weight it does not look like walking: written and labelled, one line on stderr,
    exit 4; with walk3d's bar it walks and exits 0 (the control)."""
    from typer.testing import CliRunner

    from walk3d.cli import app
    from walk3d.results import gait_checks

    if bar_bw is not None:
        monkeypatch.setattr(gait_checks, "SLOW_HUMPS", ((0.0, bar_bw),))
    out = tmp_path / "o"
    r = CliRunner().invoke(app, ["predict", "--speed", "0.6", "--threads", "1",
                                 "--no-compile-later", "--out", str(out)])  # fmt: skip
    summary = json.loads((out / "summary.json").read_text())
    assert summary["converged"], r.stderr
    walks = summary["gait_checks"]["looks_like_walking"]
    assert walks == (bar_bw is None)
    assert r.exit_code == (0 if walks else 4), r.stderr
    if not walks:
        assert r.stderr.strip().splitlines() == [
            f"walk3d: warning: {out}: the gait does not look like walking (summary gait_checks)"
        ]
    else:
        assert "walk3d: warning:" not in r.stderr, r.stderr


@pytest.mark.solve
def test_sigterm_stops_predict_with_one_line_exit_143_and_nothing_left(tmp_path):
    """SIGTERM (a scheduler's, or ``timeout``'s) while IPOPT iterates: one line and exit 143,
    no result and no temporary folder beside it."""
    import signal
    import time

    out = tmp_path / "o"
    cmd = [sys.executable, "-m", "walk3d.cli", "predict", "--out", str(out), "--nodes", "8",
           "--criterion", "tor", "--threads", "1", "--no-compile-later"]  # fmt: skip
    env = os.environ | {"OPENBLAS_NUM_THREADS": "1"}
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    time.sleep(12)
    p.send_signal(signal.SIGTERM)
    t0 = time.perf_counter()
    _, err = p.communicate(timeout=120)
    assert p.returncode == 143, err
    # the last line is walk3d's; CasADi may warn first when the signal came while it built
    assert err.strip().splitlines()[-1] == "walk3d: terminated", err
    assert "Traceback" not in err
    assert time.perf_counter() - t0 < 15
    assert list(tmp_path.iterdir()) == []  # neither the result nor a .tmp_* folder
