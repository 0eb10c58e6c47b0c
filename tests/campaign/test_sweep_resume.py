"""walk3d sweep resumed: what a folder holds is checked before any solve. A speed folder with
another speed's or problem's prediction is refused, a damaged one is solved again, a bad
sweep.json is one line and exit code 2. The solves are scripted (no optimization)."""

import csv
import hashlib
import json
import re
import shutil

import numpy as np
import pytest

from walk3d.campaign.sweep import SweepMismatch, run_sweep, speed_folder
from walk3d.campaign.sweep_folder import check_arrays
from walk3d.problem import descriptors
from walk3d.problem.settings import PredictionSettings
from walk3d.results.prediction import MANIFEST, RESULT_FILES

SPEEDS = np.array([1.2, 1.4])
SETTINGS = PredictionSettings(speed=1.2, period=1.1, double_support=0.12,
                              free=descriptors.NAMES, criterion="tor", nodes=8)  # fmt: skip


class Fake:
    def __init__(self, summary):
        self.summary = summary


def fake_summary(settings):
    """A summary with what the sweep reads, recording ``settings``; its period is the speed's
    own (shorter when faster, as solved ones are), not the first guess it was given."""
    g = settings.gait
    period = round(1.3 - 0.2 * g.speed, 9)
    return {"settings": settings.model_dump(mode="json"),
            "descriptors": {"speed": g.speed, "period": period,
                            "double_support": g.double_support,
                            "stride_length": g.speed * period, "cadence": 120 / period,
                            "stance_fraction": 0.5 + g.double_support / period,
                            "predicted": list(g.free)},
            "converged": True, "status": "Solve_Succeeded", "start": "standing",
            "iterations": 7, "wall_time_s": 1.0, "coefficients": {"x": [g.speed]},
            "gait_checks": {"looks_like_walking": True}, "objective": {}}  # fmt: skip


def write_fake(pred, folder):
    """A complete result folder (manifest and the files it lists) around ``pred.summary``."""
    folder.mkdir(parents=True, exist_ok=True)
    for name in RESULT_FILES:
        (folder / name).write_text("x\n")
    d = pred.summary.get("descriptors") if isinstance(pred.summary, dict) else None
    period = (d or {}).get("period")
    period = period if isinstance(period, float) else 1.0
    with open(folder / "result.npz", "wb") as fh:  # the same size at any speed
        np.savez(fh, time=np.linspace(0.0, period, 11))
    (folder / "summary.json").write_text(json.dumps(pred.summary))
    files = {p.name: p.stat().st_size for p in folder.iterdir() if p.name != MANIFEST}
    digest = hashlib.sha256((folder / "result.npz").read_bytes()).hexdigest()
    (folder / MANIFEST).write_text(json.dumps({"files": files, "sha256": {"result.npz": digest}}))
    return folder


@pytest.fixture
def solves(monkeypatch):
    """Scripted solves: each returns a walking summary of the settings it was given and is
    recorded by speed; the figure is not drawn."""
    import walk3d.pipeline
    import walk3d.plots.sweep

    calls = []

    def predict(settings, seed, solver, on_stage=None, warm_from=None):
        calls.append(settings.gait.speed)
        return Fake(fake_summary(settings))

    monkeypatch.setattr(walk3d.pipeline, "predict", predict)
    monkeypatch.setattr(walk3d.pipeline, "write_result", write_fake)
    monkeypatch.setattr(walk3d.plots.sweep, "sweep_figure", lambda *a, **k: None)
    return calls


def _table(out):
    with open(out / "sweep.csv") as fh:
        return [float(r["speed"]) for r in csv.DictReader(fh)]


def _place(out, speed, settings):
    """Replace the folder of ``speed`` by a prediction of ``settings``."""
    folder = speed_folder(out, speed)
    for p in folder.iterdir():
        p.unlink()
    write_fake(Fake(fake_summary(settings)), folder)


def test_a_finished_sweep_resumes_without_solving(tmp_path, solves):
    out = tmp_path / "s"
    assert run_sweep(SETTINGS, SPEEDS, out).ran == 2 and set(solves) == {1.2, 1.4}
    solves.clear()
    again = run_sweep(SETTINGS, SPEEDS, out)
    assert (again.ran, again.skipped, solves) == (0, 2, []) and _table(out) == [1.2, 1.4]


@pytest.mark.parametrize(
    ("change", "words"),
    [({"speed": 1.3806}, "is at 1.3806 m/s, not 1.2 m/s"),
     ({"sex": "female"}, "was solved with sex 'female', not 'male'"),
     ({"mass": 80.0}, "was solved with mass 80.0"),
     ({"height": 1.6}, "was solved with height 1.6"),
     ({"criterion": "en"}, "was solved with criterion"),
     ({"nodes": 10}, "was solved with nodes 10, not 8"),
     ({"free": ()}, "was solved with free ()")],
)  # fmt: skip
def test_a_speed_folder_of_another_problem_is_refused_before_any_solve(
    tmp_path, solves, change, words
):
    """A 1.3806 m/s result in speeds/v_1.200 was taken and tabulated as 1.38 m/s where 1.2
    was asked for; now the sweep refuses it (it may be someone's result) and solves nothing."""
    out = tmp_path / "s"
    run_sweep(SETTINGS, SPEEDS, out)
    _place(out, 1.2, SETTINGS.replace(**change))
    solves.clear()
    with pytest.raises(SweepMismatch, match="v_1.200 holds a prediction that") as info:
        run_sweep(SETTINGS, SPEEDS, out)
    assert words in str(info.value) and "\n" not in str(info.value)
    assert solves == [] and _table(out) == [1.2, 1.4]  # nothing solved or rewritten


@pytest.mark.parametrize("stored", [{"handover": False}, {"max_iter": 5, "threads": 3}])
def test_a_speed_folder_of_the_same_problem_is_resumed(tmp_path, solves, stored):
    """Negative control: the handover's fallback to the free landing, or settings that only
    change how it was solved, are the same problem."""
    out = tmp_path / "s"
    run_sweep(SETTINGS, SPEEDS, out)
    _place(out, 1.2, SETTINGS.replace(**stored))
    solves.clear()
    assert run_sweep(SETTINGS, SPEEDS, out).skipped == 2 and solves == []


@pytest.mark.parametrize(
    "damage",
    [lambda f: f.write_text(f.read_text()[:40]),  # truncated: the manifest's size is wrong
     lambda f: (f.parent / MANIFEST).unlink(),
     lambda f: shutil.copyfile(f.parent.parent / "v_1.400" / "result.npz",  # swapped arrays
                               f.parent / "result.npz")],
)  # fmt: skip
def test_a_damaged_speed_folder_is_solved_again_with_a_warning(tmp_path, solves, damage):
    out = tmp_path / "s"
    run_sweep(SETTINGS, SPEEDS, out)
    damage(speed_folder(out, 1.2) / "summary.json")
    solves.clear()
    with pytest.warns(RuntimeWarning, match=r"v_1.200 cannot be read .*solving 1.2 m/s again"):
        report = run_sweep(SETTINGS, SPEEDS, out)
    assert (report.ran, report.skipped, solves) == (1, 1, [1.2]) and _table(out) == [1.2, 1.4]
    again = run_sweep(SETTINGS, SPEEDS, out)  # control: the solved-again folder is whole
    assert again.skipped == 2


def _rewrite_manifests(out, swap, digests):
    """Swap the two speeds' ``result.npz`` (when ``swap``), then delete the manifests' digests
    (``"drop"``: as a walk3d before digests wrote them) or make them the files' own
    (``"rewrite"``)."""
    a, b = (speed_folder(out, v) / "result.npz" for v in SPEEDS)
    if swap:
        data = a.read_bytes()
        a.write_bytes(b.read_bytes())
        b.write_bytes(data)
    for npz in (a, b):
        manifest = json.loads((npz.parent / MANIFEST).read_text())
        if digests == "drop":
            del manifest["sha256"]
        else:
            manifest["sha256"]["result.npz"] = hashlib.sha256(npz.read_bytes()).hexdigest()
        (npz.parent / MANIFEST).write_text(json.dumps(manifest))


@pytest.mark.parametrize(
    ("swap", "digests", "words"),
    [(True, "drop", "holds no digest of result.npz"),
     (False, "drop", "holds no digest of result.npz"),
     (True, "rewrite", "its result.npz is not its summary's: the arrays' cycle runs 0 to")],
    ids=["swapped-no-digest", "no-digest", "swapped-digest-rewritten"],
)  # fmt: skip
def test_arrays_not_tied_to_their_summary_are_solved_again(tmp_path, solves, swap, digests,
                                                           words):  # fmt: skip
    """Arrays swapped between the two speeds, with the manifests' digests deleted or rewritten,
    were resumed ("0 speeds solved, 2 resumed"); a folder without digests cannot show that its
    arrays are its summary's either. Each is solved again, with one warning."""
    out = tmp_path / "s"
    run_sweep(SETTINGS, SPEEDS, out)
    _rewrite_manifests(out, swap, digests)
    solves.clear()
    with pytest.warns(RuntimeWarning) as caught:
        report = run_sweep(SETTINGS, SPEEDS, out)
    assert (report.ran, report.skipped, sorted(solves)) == (2, 0, [1.2, 1.4])
    messages = [str(w.message) for w in caught if w.category is RuntimeWarning]
    assert len(messages) == 2 and all(words in m and "\n" not in m for m in messages), messages
    solves.clear()
    again = run_sweep(SETTINGS, SPEEDS, out)  # control: the solved-again folders are whole
    assert (again.skipped, solves) == (2, []) and _table(out) == [1.2, 1.4]


def test_intact_arrays_with_their_digest_rewritten_are_resumed(tmp_path, solves):
    """Negative control: rewriting each manifest's digest with its own file's changes nothing."""
    out = tmp_path / "s"
    run_sweep(SETTINGS, SPEEDS, out)
    _rewrite_manifests(out, False, "rewrite")
    solves.clear()
    assert run_sweep(SETTINGS, SPEEDS, out).skipped == 2 and solves == []


def test_a_real_result_folder_is_tied_to_its_summary(tmp_path):
    """On walk3d predict's own files (the atlas's 1.3 m/s solution) the arrays pass; under a
    summary of another period, or without the manifest's digest, they do not."""
    from result_support import result_folder

    folder = result_folder(tmp_path / "r")
    summary = json.loads((folder / "summary.json").read_text())
    check_arrays(folder, summary)  # control
    other = json.loads((folder / "summary.json").read_text())
    other["descriptors"]["period"] *= 1 + 1e-6
    with pytest.raises(ValueError, match="its result.npz is not its summary's"):
        check_arrays(folder, other)
    manifest = json.loads((folder / MANIFEST).read_text())
    (folder / MANIFEST).write_text(json.dumps({"files": manifest["files"]}))
    with pytest.raises(ValueError, match="holds no digest of result.npz"):
        check_arrays(folder, summary)


def test_a_summary_the_sweep_cannot_tabulate_is_solved_again(tmp_path, solves):
    """Valid JSON, manifest in order, but not a prediction's summary."""
    out = tmp_path / "s"
    run_sweep(SETTINGS, SPEEDS, out)
    write_fake(Fake([1, 2, 3]), speed_folder(out, 1.2))
    solves.clear()
    with pytest.warns(RuntimeWarning, match="v_1.200 cannot be read"):
        assert run_sweep(SETTINGS, SPEEDS, out).ran == 1 and solves == [1.2]


@pytest.mark.parametrize(
    ("text", "words"),
    [("{garbage", "sweep.json cannot be read"), ("[1,2,3]", "not a walk3d sweep file"),
     ('{"settings": 3}', "not a walk3d sweep file"), ("", "cannot be read"),
     ("[" * 100000, "sweep.json cannot be read (invalid JSON")],
    ids=["garbage", "list", "settings", "empty", "nested"],
)  # fmt: skip
def test_a_bad_sweep_json_is_refused(tmp_path, solves, text, words):
    """Nested too deep, it raised RecursionError; now one line like any damage."""
    out = tmp_path / "s"
    out.mkdir()
    (out / "sweep.json").write_text(text)
    with pytest.raises(SweepMismatch, match=re.escape(words)) as info:
        run_sweep(SETTINGS, SPEEDS, out)
    assert solves == [] and "\n" not in str(info.value)


def test_a_speed_summary_nested_too_deep_is_solved_again(tmp_path, solves):
    """summary.json of '[' * 100000 with the manifest in order raised RecursionError."""
    out = tmp_path / "s"
    run_sweep(SETTINGS, SPEEDS, out)
    folder = speed_folder(out, 1.2)
    (folder / "summary.json").write_text("[" * 100000)
    files = {p.name: p.stat().st_size for p in folder.iterdir() if p.name != MANIFEST}
    (folder / MANIFEST).write_text(json.dumps({"files": files}))
    solves.clear()
    with pytest.warns(RuntimeWarning, match=r"v_1.200 cannot be read .*invalid JSON"):
        assert run_sweep(SETTINGS, SPEEDS, out).ran == 1 and solves == [1.2]


@pytest.mark.parametrize("text", ["{trunc", "[" * 100000, "[1, 2]"], ids=["cut", "nested", "list"])
def test_a_damaged_second_pass_record_means_the_tries_are_made_again(tmp_path, solves, text):
    out = tmp_path / "s"
    run_sweep(SETTINGS, np.array([1.2, 1.3, 1.4]), out)
    (out / "second_pass.json").write_text(text)
    solves.clear()
    with pytest.warns(RuntimeWarning, match="second_pass.json cannot be read .*made again"):
        report = run_sweep(SETTINGS, np.array([1.2, 1.3, 1.4]), out)
    assert solves == [1.3, 1.3]  # 1.3 once more from each neighbour
    assert (report.ran, report.skipped, report.tries) == (0, 3, 2)  # counted, not hidden
    assert set(json.loads((out / "second_pass.json").read_text())) == {"1.300<1.200",
                                                                        "1.300<1.400"}  # fmt: skip


def _cli(capsys, *args):
    from walk3d.cli import main

    with pytest.raises(SystemExit) as info:
        main(["sweep", "--nodes", "8", "--criterion", "tor", *map(str, args)])
    return info.value.code, capsys.readouterr().err.strip().splitlines()


def test_cli_resume_errors_are_one_line_and_exit_2(tmp_path, solves, capsys):
    out = tmp_path / "s"
    assert _cli(capsys, "--speeds", "1.2,1.4", "--out", out) == (0, [])
    _place(
        out,
        1.2,
        PredictionSettings(
            **json.loads((speed_folder(out, 1.2) / "summary.json").read_text())["settings"]
        ).replace(speed=1.3806),
    )
    code, err = _cli(capsys, "--speeds", "1.2,1.4", "--out", out)
    assert code == 2 and len(err) == 1 and "is at 1.3806 m/s, not 1.2 m/s" in err[0]
    (out / "sweep.json").write_text("{garbage")
    code, err = _cli(capsys, "--speeds", "1.2,1.4", "--out", out)
    assert code == 2 and len(err) == 1 and "sweep.json cannot be read" in err[0]
    (out / "sweep.json").write_text("[1,2,3]")
    code, err = _cli(capsys, "--speeds", "1.2,1.4", "--out", out)
    assert code == 2 and len(err) == 1 and "not a walk3d sweep file" in err[0]


def test_cli_solves_a_truncated_speed_again_with_one_warning_line(tmp_path, solves, capsys):
    out = tmp_path / "s"
    assert _cli(capsys, "--speeds", "1.2,1.4", "--out", out) == (0, [])
    summary = speed_folder(out, 1.2) / "summary.json"
    summary.write_text(summary.read_text()[:40])
    solves.clear()
    code, err = _cli(capsys, "--speeds", "1.2,1.4", "--out", out)
    assert code == 0 and solves == [1.2] and "Traceback" not in "\n".join(err)
    assert len(err) == 1 and err[0].startswith("walk3d: warning:") and "v_1.200" in err[0]


def _no_solve(monkeypatch):
    """Make any solve or write fail the test: a refusal must come before both."""
    import walk3d.pipeline

    def fail(*args, **kwargs):
        raise AssertionError("a solve or write started")

    monkeypatch.setattr(walk3d.pipeline, "predict", fail)
    monkeypatch.setattr(walk3d.pipeline, "write_result", fail)


@pytest.mark.parametrize(
    ("make", "words"),
    [(lambda f: f.write_text("mine\n"), "v_1.200 is an existing file"),
     (lambda f: (f.mkdir(), (f / "thesis.txt").write_text("mine\n")), "folder of other files"),
     (lambda f: (shutil.rmtree(f.parent), f.parent.write_text("mine\n")), "speeds is a file"),
     (lambda f: (write_fake(Fake(fake_summary(SETTINGS)), f), (f / "summary.json").unlink()),
      "no summary.json")],
    ids=["file", "thesis", "speeds-file", "no-summary"],
)  # fmt: skip
def test_a_speed_path_walk3d_did_not_write_is_refused_before_any_solve(
    tmp_path, solves, monkeypatch, capsys, make, words
):
    """They were solved (after 'solving again'), then the write traced back; now exit 2, one
    line, nothing solved and the user's file kept."""
    out = tmp_path / "s"
    run_sweep(SETTINGS, SPEEDS[1:], out)  # sweep.json and speeds/v_1.400
    folder = speed_folder(out, 1.2)
    make(folder)
    before = {p: p.read_bytes() for p in out.rglob("*") if p.is_file()}
    _no_solve(monkeypatch)
    with pytest.raises(SweepMismatch, match=re.escape(words)) as info:
        run_sweep(SETTINGS, SPEEDS, out)
    assert "\n" not in str(info.value)
    code, err = _cli(capsys, "--speeds", "1.2,1.4", "--out", out)
    assert code == 2 and len(err) == 1 and words in err[0], err
    assert {p: p.read_bytes() for p in out.rglob("*") if p.is_file()} == before


def test_an_empty_speed_folder_is_solved(tmp_path, solves):
    """Negative control: an empty folder (or none) at a speed is written, not refused."""
    out = tmp_path / "s"
    run_sweep(SETTINGS, SPEEDS[1:], out)
    speed_folder(out, 1.2).mkdir()
    solves.clear()
    with pytest.warns(RuntimeWarning, match="solving 1.2 m/s again"):
        assert run_sweep(SETTINGS, SPEEDS, out).ran == 1 and solves[0] == 1.2


@pytest.mark.parametrize("speed", [float("nan"), "1.2", "fast", True, None])
def test_a_stored_speed_that_is_not_a_number_is_solved_again(tmp_path, solves, speed):
    out = tmp_path / "s"
    run_sweep(SETTINGS, SPEEDS, out)
    folder = speed_folder(out, 1.2)
    summary = json.loads((folder / "summary.json").read_text())
    summary["descriptors"]["speed"] = speed
    for p in folder.iterdir():
        p.unlink()
    write_fake(Fake(summary), folder)
    solves.clear()
    with pytest.warns(RuntimeWarning, match=r"v_1.200 cannot be read .*solving 1.2 m/s again"):
        report = run_sweep(SETTINGS, SPEEDS, out)
    assert (report.ran, report.skipped, solves) == (1, 1, [1.2])


def test_a_summary_whose_settings_are_at_another_speed_is_refused(tmp_path, solves):
    out = tmp_path / "s"
    run_sweep(SETTINGS, SPEEDS, out)
    folder = speed_folder(out, 1.2)
    summary = json.loads((folder / "summary.json").read_text())
    summary["settings"]["gait"]["speed"] = 1.4  # the table says 1.2, the problem was 1.4
    for p in folder.iterdir():
        p.unlink()
    write_fake(Fake(summary), folder)
    solves.clear()
    with pytest.raises(SweepMismatch, match="is at 1.4 m/s, not 1.2 m/s"):
        run_sweep(SETTINGS, SPEEDS, out)
    assert solves == []


def test_cli_says_a_damaged_second_pass_record_and_counts_its_tries(tmp_path, solves, capsys):
    """Was silent, and "0 speeds solved, 3 resumed" over two solves."""
    from walk3d.cli import main

    out = tmp_path / "s"
    args = ["sweep", "--nodes", "8", "--criterion", "tor", "--speeds", "1.2,1.3,1.4",
            "--out", str(out)]  # fmt: skip
    with pytest.raises(SystemExit):
        main(args)
    capsys.readouterr()
    (out / "second_pass.json").write_text("{trunc")
    with pytest.raises(SystemExit) as info:
        main(args)
    stdout, err = capsys.readouterr()
    assert info.value.code == 0 and len(err.strip().splitlines()) == 1, err
    assert err.startswith("walk3d: warning:") and "second_pass.json cannot be read" in err
    assert "0 speeds solved, 3 resumed, 2 second-pass tries" in " ".join(stdout.split())
    with pytest.raises(SystemExit) as info:  # control: the record rewritten, nothing tried
        main(args)
    stdout, err = capsys.readouterr()
    assert info.value.code == 0 and err == "" and "second-pass" not in stdout
