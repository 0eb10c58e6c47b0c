"""Campaign bookkeeping without solving: ranking order, folder layout, refusing a resume."""

import json
import re
import subprocess
import sys
import time

import pytest

from walk3d.campaign import rank, store
from walk3d.campaign.ranking import COLUMNS, order_records, update_best, write_ranking
from walk3d.campaign.task import error_record
from walk3d.problem.settings import PredictionSettings
from walk3d.solve import SOLVE_REVISION
from walk3d.solve.starts import ATLAS_NOISE_FRACTION

TINY = PredictionSettings(nodes=6, max_iter=3)


def record(seed, converged, value, status="Solve_Succeeded"):
    split = None if value is None else {"total": value, "x": value / 2, "y": 0.0, "z": value / 2}
    return {
        "seed": seed, "status": status, "converged": converged, "criterion": "tor",
        "criterion_value": value, "C_tor": split or {}, "C_en": {}, "iterations": 10,
        "wall_time_s": 1.0,
    }  # fmt: skip


def test_order_converged_first_by_value_then_the_rest():
    records = [
        record(0, False, 5.0, "Maximum_Iterations_Exceeded"),
        record(1, True, 30.0),
        record(2, False, None, "error: RuntimeError: boom"),
        record(3, True, 10.0),
        record(4, False, 1.0, "Infeasible_Problem_Detected"),
        record(5, True, float("nan")),
        record(6, True, 10.0),
    ]
    rows = order_records(records)
    assert [r["seed"] for r in rows] == [3, 6, 1, 5, 4, 0, 2]
    assert [r["rank"] for r in rows] == list(range(1, 8))
    assert rows[3]["criterion_value"] is None  # NaN value ranks last among the converged


def _make_start(out, seed, converged, value):
    tmp = store.new_temporary(store.starts_dir(out), store.start_name(seed))
    (tmp / "summary.json").write_text("{}\n")
    return store.commit_start(tmp, seed, record(seed, converged, value))


def test_rank_csv_and_best_folder(tmp_path):
    out = tmp_path / "c"
    store.open_campaign(out, TINY, 0, 4, "ipopt")
    for seed, conv, value in [(0, False, 1.0), (1, True, 9.0), (2, True, 4.0)]:
        _make_start(out, seed, conv, value)
    store.new_temporary(store.starts_dir(out), "seed_000003")  # an interrupted start
    owner = store.starts_dir(out) / ".tmp_.tmp_seed_000004_0123456789ab_0123456789ab.owner"
    owner.write_text("host 1\n")  # a killed worker's owner file, its folder already gone
    rows = rank(out)
    assert [r["seed"] for r in rows] == [2, 1, 0]
    lines = write_ranking(out, rows).read_text().splitlines()
    assert lines[0].split(",") == list(COLUMNS)
    assert [line.split(",")[1] for line in lines[1:]] == ["2", "1", "0"]
    assert update_best(out, rows) == 2
    assert json.loads((out / "best" / "record.json").read_text())["seed"] == 2
    assert (out / "best" / "summary.json").is_file()
    assert len(store.clean_temporaries(out)) == 2
    assert not [p for p in store.starts_dir(out).iterdir() if p.name.startswith(".tmp")]
    assert [r["seed"] for r in rank(out)] == [2, 1, 0]  # the starts themselves stay


def test_no_converged_start_means_no_best(tmp_path):
    out = tmp_path / "c"
    store.open_campaign(out, TINY, 0, 1, "ipopt")
    _make_start(out, 0, False, 1.0)
    assert update_best(out, rank(out)) is None
    assert not (out / "best").exists()


def test_commit_keeps_the_first_finished_copy(tmp_path):
    root = tmp_path / "starts"
    first = store.commit_start(store.new_temporary(root, "seed_000007"), 7, record(7, True, 1.0))
    again = store.commit_start(store.new_temporary(root, "seed_000007"), 7, record(7, True, 2.0))
    assert again == first
    assert [p.name for p in root.iterdir()] == ["seed_000007"]


def test_error_record_is_not_converged():
    r = error_record(3, "en", "RuntimeError: boom", 0.5)
    assert r["status"] == "error: RuntimeError: boom" and r["converged"] is False
    assert order_records([r, record(4, False, 7.0)])[1]["seed"] == 3


def test_resume_may_add_starts_but_not_change_settings(tmp_path):
    out = tmp_path / "c"
    store.open_campaign(out, TINY, 5, 4, "ipopt")
    assert store.open_campaign(out, TINY, 5, 8, "ipopt")["starts"] == 8
    assert store.read_campaign(out)["starts"] == 8
    with pytest.raises(store.CampaignMismatch, match="speed"):
        store.open_campaign(out, TINY.replace(**{"speed": 1.2}), 5, 8, "ipopt")
    with pytest.raises(store.CampaignMismatch, match="base_seed"):
        store.open_campaign(out, TINY, 0, 8, "ipopt")
    # a campaign solved by another solver revision is refused: its starts ran otherwise
    stored = store.read_campaign(out)
    assert stored["solve_revision"] == SOLVE_REVISION
    # atlas starts drawn with other noise (a fifth of --perturbation before it was recorded)
    assert stored["atlas_noise_fraction"] == ATLAS_NOISE_FRACTION
    store.write_json(out / store.CAMPAIGN_FILE, stored | {"atlas_noise_fraction": 0.2})
    with pytest.raises(store.CampaignMismatch, match="other noise \\(0.2 of --perturbation"):
        store.open_campaign(out, TINY, 5, 8, "ipopt")
    standing = {**stored, "atlas_noise_fraction": 0.2}  # control: standing starts have none
    standing["settings"]["solver"]["start"] = "standing"
    store.write_json(out / store.CAMPAIGN_FILE, standing)
    assert store.open_campaign(out, TINY.replace(start="standing"), 5, 8, "ipopt")["starts"] == 8
    stored["settings"]["solver"]["start"] = TINY.solver.start
    store.write_json(out / store.CAMPAIGN_FILE, stored | {"solve_revision": 10})
    with pytest.raises(store.CampaignMismatch, match=f"revision 10, now {SOLVE_REVISION}\\)"):
        store.open_campaign(out, TINY, 5, 8, "ipopt")
    del stored["solve_revision"]  # made before revisions were recorded
    store.write_json(out / store.CAMPAIGN_FILE, stored)
    with pytest.raises(store.CampaignMismatch, match="revision before 11"):
        store.open_campaign(out, TINY, 5, 8, "ipopt")
    stored["solve_revision"] = SOLVE_REVISION
    # a campaign whose settings were stored flat (before the groups) resumes as it is
    grouped = stored["settings"]
    stored["settings"] = {k: v for group in grouped.values() for k, v in group.items()}
    store.write_json(out / store.CAMPAIGN_FILE, stored)
    assert store.open_campaign(out, TINY, 5, 8, "ipopt")["starts"] == 8
    with pytest.raises(store.CampaignMismatch, match="nodes: stored 6, requested 7"):
        store.open_campaign(out, TINY.replace(nodes=7), 5, 8, "ipopt")
    # a campaign made before a setting existed is refused, naming that setting
    del stored["settings"]["restarts"]
    store.write_json(out / store.CAMPAIGN_FILE, stored)
    with pytest.raises(store.CampaignMismatch, match="earlier walk3d.* restarts; use a new --out$"):
        store.open_campaign(out, TINY, 5, 8, "ipopt")
    (tmp_path / "other").mkdir()
    (tmp_path / "other" / "file.txt").write_text("x")
    with pytest.raises(store.CampaignMismatch, match="not a campaign"):
        store.open_campaign(tmp_path / "other", TINY, 0, 1, "ipopt")


@pytest.mark.parametrize(
    "args,word",
    [
        (["--speed", "1.2"], "speed"),
        (["--criterion", "en"], "criterion"),
        (["--solver", "sqp"], "solver"),
        (["--max-iter", "4"], "max_iter"),
        (["--perturbation", "0.1"], "perturbation"),
        (["--restarts", "0"], "restarts"),
    ],
)
def test_cli_refuses_changed_settings_on_resume(tmp_path, args, word):
    out = tmp_path / "c"
    store.open_campaign(out, TINY, 0, 2, "ipopt")
    before = (out / "campaign.json").read_bytes()
    cmd = [sys.executable, "-m", "walk3d.cli", "campaign", "--starts", "2", "--out", str(out),
           "--nodes", "6", "--max-iter", "3", "--criterion", "tor", "--period", "1.08",
           "--double-support", "0.16", *args]  # fmt: skip
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and word in lines[0] and lines[0].startswith("walk3d: error:"), r.stderr
    assert (out / "campaign.json").read_bytes() == before
    assert not list(store.starts_dir(out).iterdir())


@pytest.mark.parametrize(
    ("text", "words"),
    [("[" * 100000, "campaign.json is unreadable (invalid JSON (RecursionError))"),
     ("[1, 2]", "campaign.json is unreadable (not a walk3d campaign file"),
     ('{"settings": 3, "starts": 2}', "campaign.json is not a walk3d campaign file"),
     ('{"settings": {}, "starts": "2"}', "campaign.json is not a walk3d campaign file")],
    ids=["nested", "list", "settings", "starts"],
)  # fmt: skip
def test_a_damaged_campaign_json_is_one_line_and_exit_2_on_resume(tmp_path, text, words):
    """Nested too deep it raised RecursionError (a traceback), a JSON list or a wrong type
    AttributeError or TypeError. Control: the same resume of an intact campaign.json gets
    past it to the changed --speed."""
    out = tmp_path / "c"
    store.open_campaign(out, TINY, 0, 2, "ipopt")
    intact = (out / "campaign.json").read_text()
    (out / "campaign.json").write_text(text)
    with pytest.raises(store.CampaignMismatch, match=re.escape(words)):
        store.open_campaign(out, TINY, 0, 2, "ipopt")
    cmd = [sys.executable, "-m", "walk3d.cli", "campaign", "--starts", "2", "--out", str(out),
           "--nodes", "6", "--max-iter", "3", "--criterion", "tor", "--period", "1.08",
           "--double-support", "0.16", "--speed", "1.2"]  # fmt: skip
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2 and len(lines) == 1 and words in lines[0], r.stderr
    (out / "campaign.json").write_text(intact)
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and "speed: stored" in r.stderr, r.stderr


def test_a_start_record_nested_too_deep_is_no_record(tmp_path):
    folder = tmp_path / "seed_000001"
    folder.mkdir()
    (folder / store.RECORD_FILE).write_text("[" * 100000)
    assert store.read_record(folder) is None
    (folder / store.RECORD_FILE).write_text('{"seed": 1}')  # control
    assert store.read_record(folder) == {"seed": 1}


@pytest.mark.parametrize(
    "args,word",
    [(["--starts", "0"], "--starts"), (["--starts", "99999999999999999999"], "--starts"),
     (["--workers", "0"], "--workers"), (["--workers", "99999999999"], "--workers"),
     (["--max-iter", "0"], "max_iter"), (["--restarts", "-1"], "restarts")],
)  # fmt: skip
def test_cli_refuses_bad_campaign_options_before_creating_the_folder(tmp_path, args, word):
    out = tmp_path / "c"
    base = ["--starts", "2"] if args[0] != "--starts" else []
    cmd = [sys.executable, "-m", "walk3d.cli", "campaign", *base, "--out", str(out), *args]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and word in lines[0] and "Traceback" not in r.stderr, r.stderr
    assert not out.exists()


def test_cli_campaign_takes_a_calibration_like_predict(tmp_path):
    """--calibration reaches the campaign's settings: a missing file is refused before the
    folder exists, and a calibration differs from a stored campaign without one."""
    from helpers import sample_calibration

    from walk3d.io import write_calibration

    path = write_calibration(tmp_path / "cal.json", sample_calibration().to_dict())
    base = [sys.executable, "-m", "walk3d.cli", "campaign", "--starts", "2", "--nodes", "6",
            "--max-iter", "3", "--criterion", "tor", "--period", "1.08",
            "--double-support", "0.16"]  # fmt: skip
    missing = tmp_path / "missing"
    r = subprocess.run([*base, "--out", str(missing), "--calibration", str(tmp_path / "no.json")],
                       capture_output=True, text=True, timeout=60)  # fmt: skip
    assert r.returncode == 2 and "no.json" in r.stderr and "Traceback" not in r.stderr
    assert not missing.exists()
    out = tmp_path / "c"
    store.open_campaign(out, TINY, 0, 2, "ipopt")
    r = subprocess.run([*base, "--out", str(out), "--calibration", str(path)],
                       capture_output=True, text=True, timeout=60)  # fmt: skip
    assert r.returncode == 2, r.stderr
    assert "rollover" in r.stderr and len(r.stderr.strip().splitlines()) == 1, r.stderr


def test_walking_verdict_flows_from_summary_to_ranking_and_table():
    from rich.console import Console

    from walk3d.campaign.ranking import top_table
    from walk3d.campaign.task import record_from_summary

    summary = {"seed": 3, "status": "Solve_Succeeded", "converged": True,
               "objective": {"C_tor": {"total": 6.3, "x": 1.0, "y": 2.0, "z": 3.3}},
               "gait_checks": {"looks_like_walking": False}}  # fmt: skip
    rec = record_from_summary(summary, "tor", 1.0)
    assert rec["looks_like_walking"] is False
    rows = order_records([rec, record(4, True, 1.9) | {"looks_like_walking": True}])
    assert [(r["seed"], r["looks_like_walking"]) for r in rows] == [(4, True), (3, False)]
    console = Console(width=200, record=True)
    console.print(top_table(rows, "tor"))
    lines = [line for line in console.export_text().splitlines() if "Solve_Succeeded" in line]
    assert "yes" in lines[0].split("1.9")[1] and " no " in lines[1]
    assert "looks_like_walking" in COLUMNS


@pytest.mark.parametrize(
    ("address", "word"),
    [("foo", "not a scheduler address"), ("tcp://127.0.0.1:1", "no Dask scheduler answers")],
)
def test_a_bad_scheduler_is_refused_quickly_without_a_folder(tmp_path, address, word):
    import time

    out = tmp_path / "c"
    cmd = [sys.executable, "-m", "walk3d.cli", "campaign", "--starts", "2", "--out", str(out),
           "--scheduler", address]  # fmt: skip
    t0 = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    assert time.perf_counter() - t0 < 10
    assert r.returncode == 2 and "Traceback" not in r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and word in lines[0], r.stderr
    assert not out.exists()


def test_a_listener_passes_the_check_only_if_it_greets_as_a_scheduler_does():
    """A listener that accepts and never answers (a dashboard's port) left the campaign's
    Client waiting without end: it is refused. The control: a listener that sends its
    greeting first, as a Dask scheduler sends its handshake, passes."""
    import socket
    import threading

    from walk3d.campaign.runner import check_scheduler

    for greets in (False, True):
        with socket.create_server(("127.0.0.1", 0)) as server:

            def serve(server=server, greets=greets):
                conn, _ = server.accept()
                if greets:
                    conn.sendall(b"dask")
                time.sleep(1.5)
                conn.close()

            threading.Thread(target=serve, daemon=True).start()
            address = f"tcp://127.0.0.1:{server.getsockname()[1]}"
            if greets:
                check_scheduler(address, timeout_s=1.0)
            else:
                with pytest.raises(ValueError, match="not a Dask scheduler"):
                    check_scheduler(address, timeout_s=1.0)
    with pytest.raises(ValueError, match="no Dask scheduler answers"):
        check_scheduler("tcp://127.0.0.1:1", timeout_s=2.0)


def test_starts_are_ranked_by_the_minimized_value_with_its_what_if_parts():
    """A one-sided change's full cycle minimizes ``C_weighted`` (its weights times the step
    asymmetry's factor, plus any overload) even under a plain criterion: the ranking reads that.
    Control: without ``C_weighted`` (an older summary) the criterion's own value."""
    from walk3d.model import terms

    weighted = {"total": 3.3, "weights": {"tor": 1.0}, "parts": {"tor": 3.2, "overload": 0.1}}
    objective = {"C_tor": {"total": 3.2}, "C_weighted": weighted}
    assert terms.minimized(objective, "tor") == 3.3
    assert terms.minimized({"C_tor": {"total": 3.2}}, "tor") == 3.2
    assert terms.minimized({}, "tor") is None


def test_the_table_says_when_its_values_are_per_metre():
    """Printed 6.166 under "C_weighted" where predict prints 9.231 per cycle for the same
    solution: the ranking's value is per metre walked when T or Td is predicted."""
    from rich.console import Console

    from walk3d.campaign.ranking import top_table

    rows = order_records([record(1, True, 6.166)])
    for per_metre, label in ((True, "C_tor per m"), (False, "C_tor")):
        console = Console(width=200, record=True)
        console.print(top_table(rows, "tor", per_metre=per_metre))
        title, _, header = console.export_text().splitlines()[:3]
        assert title.strip().endswith(f"by {label}"), title
        assert (" per m " in header) is per_metre, header  # control: per cycle, no unit added
