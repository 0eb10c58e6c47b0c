"""Fuzzing walk3d's own files: damaged result.npz, summary.json, manifest.json, motion storages,
grf.xml, cycle tables and atlas files end in a valid read or in one DataFileError line, never in
another exception; a few go through the command line (exit code 0 or 2, no traceback).

Each file starts valid (written by walk3d) and hypothesis damages its structure (values replaced
by NaN, infinities, strings, wrong shapes or types, keys deleted) or its bytes (overwritten,
cut). :data:`CASES` adds up the generated cases (derandomized, so CI sees the same ones).
"""

from __future__ import annotations

import copy
import io
import json
import shutil
import tempfile
from pathlib import Path

import numpy as np
import pytest
from helpers import random_decision, replace_result_file
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import walk3d.verify.run as run_module
from walk3d.cli import main
from walk3d.io import DataFileError, read_cycle_table, read_external_loads_xml, read_storage
from walk3d.results.prediction import check_complete, load_result, save_prediction
from walk3d.solve.atlas import ATLAS_DIR, read_atlas
from walk3d.validation.reference import reference_from_table
from walk3d.verify.periodic import periodic_records

EXAMPLES = {"npz_arrays": 120, "npz_bytes": 50, "summary": 60, "manifest": 60, "motion": 60,
            "grf_xml": 70, "cycle_table": 70, "atlas": 90, "sweep": 60, "cli_verify": 15,
            "cli_atlas": 15}  # fmt: skip
"""Examples per reader."""
CASES = sum(EXAMPLES.values())


def fuzz(name: str):
    return settings(max_examples=EXAMPLES[name], deadline=None, derandomize=True,
                    suppress_health_check=list(HealthCheck))  # fmt: skip


_DIR = Path(tempfile.mkdtemp(prefix="walk3d-fuzz-readers-"))
ODD = [float("nan"), float("inf"), -float("inf"), 1e308, -1, 0, True, None, "", "x", "nan", [],
       {}, [1, 2], {"a": 1}, 10**400]  # fmt: skip
odd_values = st.sampled_from(ODD) | st.floats() | st.integers() | st.text(max_size=8)


@pytest.fixture(scope="module")
def good_folder():
    """A result folder of a smooth random motion (no solve)."""
    from walk3d.body.model import build_body
    from walk3d.problem.settings import PredictionSettings
    from walk3d.results.evaluate import evaluate_cycle, make_prediction

    s = PredictionSettings()
    ev = evaluate_cycle(build_body(), s, random_decision(5))
    pred = make_prediction(ev.prediction_arrays, {"settings": s.model_dump()})
    return save_prediction(pred, _DIR / "good")


def _only_data_file_errors(read, *args) -> None:
    try:
        read(*args)
    except DataFileError as exc:
        assert "\n" not in str(exc), str(exc)


def _fresh(good: Path, name: str = "work") -> Path:
    work = _DIR / name
    if work.exists():
        shutil.rmtree(work)
    return Path(shutil.copytree(good, work))


# -- structural damage of JSON documents -------------------------------------------------------


@st.composite
def damaged_json(draw: st.DrawFn, valid: object) -> bytes:
    """``valid`` with one to three values replaced or keys deleted, sometimes cut or with
    bytes overwritten."""
    doc = copy.deepcopy(valid)
    for _ in range(draw(st.integers(1, 3))):
        parent, key = None, None
        node = doc
        for _depth in range(draw(st.integers(0, 4))):
            keys = list(node) if isinstance(node, dict) else list(range(len(node))) \
                if isinstance(node, list) else []  # fmt: skip
            if not keys:
                break
            parent, key = node, draw(st.sampled_from(keys))
            node = node[key]
        if parent is None:
            doc = copy.deepcopy(draw(odd_values)) if draw(st.integers(0, 9)) == 0 else doc
        elif isinstance(parent, dict) and draw(st.booleans()):
            del parent[key]
        else:
            parent[key] = copy.deepcopy(draw(odd_values))  # ODD's lists stay empty
    data = json.dumps(doc).encode()
    if draw(st.integers(0, 4)) == 0:
        data = data[: draw(st.integers(0, len(data)))]
    if draw(st.integers(0, 4)) == 0 and data:
        at = draw(st.integers(0, len(data) - 1))
        data = data[:at] + draw(st.binary(min_size=1, max_size=6)) + data[at + 6 :]
    return data


# -- result.npz ------------------------------------------------------------------------------


def _arrays(folder: Path) -> dict[str, np.ndarray]:
    with np.load(folder / "result.npz") as data:
        return {k: data[k] for k in data.files}


REPLACEMENTS = {
    "nan": lambda a: np.full(a.shape, np.nan),
    "inf": lambda a: np.full(a.shape, np.inf),
    "one-nan": lambda a: (
        np.where(np.arange(a.size).reshape(a.shape) == a.size // 2, np.nan, a)
        if a.dtype.kind == "f" and a.size
        else a
    ),  # fmt: skip
    "shape": lambda a: a.reshape(-1)[: max(a.size - 1, 0)],
    "scalar": lambda a: np.array(1.5),
    "text": lambda a: np.array(["a"] * max(a.size, 1)),
    "bool": lambda a: np.ones(a.shape, bool),
    "int": lambda a: np.ones(a.shape, np.int64),
    "complex": lambda a: np.ones(a.shape, complex),
    "empty": lambda a: np.zeros((0,)),
    "transpose": lambda a: a.T,
}


@st.composite
def damaged_arrays(draw: st.DrawFn, valid: dict[str, np.ndarray]) -> bytes:
    arrays = dict(valid)
    for _ in range(draw(st.integers(1, 2))):
        key = draw(st.sampled_from(sorted(valid)))
        kind = draw(st.sampled_from(["delete", *REPLACEMENTS]))
        if kind == "delete":
            arrays.pop(key, None)
        else:
            arrays[key] = REPLACEMENTS[kind](valid[key])
    buffer = io.BytesIO()
    np.savez(buffer, **arrays)
    return buffer.getvalue()


def test_damaged_result_arrays_end_in_a_read_or_one_line(good_folder):
    load_result(good_folder)  # the undamaged folder loads
    work = _fresh(good_folder)

    @fuzz("npz_arrays")
    @given(damaged_arrays(_arrays(good_folder)))
    def run(data: bytes) -> None:
        replace_result_file(work, "result.npz", data)
        _only_data_file_errors(load_result, work)

    run()


def test_damaged_result_bytes_end_in_one_line(good_folder):
    valid = (good_folder / "result.npz").read_bytes()
    work = _fresh(good_folder)

    @fuzz("npz_bytes")
    @given(st.lists(st.tuples(st.integers(0, len(valid) - 1), st.binary(min_size=1, max_size=8)),
                    min_size=0, max_size=4), st.integers(0, len(valid)))  # fmt: skip
    def run(patches, cut) -> None:
        data = bytearray(valid[:cut] if cut < len(valid) // 2 else valid)
        for at, patch in patches:
            data[at : at + len(patch)] = patch
        replace_result_file(work, "result.npz", bytes(data))
        _only_data_file_errors(load_result, work)

    run()


def test_damaged_summary_and_manifest_end_in_a_read_or_one_line(good_folder):
    work = _fresh(good_folder)
    summary = json.loads((good_folder / "summary.json").read_text())
    manifest = json.loads((good_folder / "manifest.json").read_text())

    @fuzz("summary")
    @given(damaged_json(summary))
    def run_summary(data: bytes) -> None:
        replace_result_file(work, "summary.json", data)
        _only_data_file_errors(load_result, work)

    @fuzz("manifest")
    @given(damaged_json(manifest))
    def run_manifest(data: bytes) -> None:
        (work / "manifest.json").write_bytes(data)
        _only_data_file_errors(check_complete, work)
        _only_data_file_errors(load_result, work)

    run_summary()
    shutil.copy(good_folder / "summary.json", work / "summary.json")
    shutil.copy(good_folder / "manifest.json", work / "manifest.json")
    run_manifest()


# -- motion.mot and grf.xml, as walk3d verify reads them ----------------------------------------

TOKENS = ["nan", "inf", "-inf", "1e999", "", "abc", "endheader", "nRows=3", "\x00"]


@st.composite
def damaged_lines(draw: st.DrawFn, valid: bytes) -> bytes:
    lines = valid.split(b"\n")
    for _ in range(draw(st.integers(1, 3))):
        i = draw(st.integers(0, len(lines) - 1))
        kind = draw(st.sampled_from(["delete", "repeat", "token", "bytes"]))
        if kind == "delete" and len(lines) > 1:
            del lines[i]
        elif kind == "repeat":
            lines.insert(i, lines[i])
        elif kind == "token":
            cells = lines[i].split(b"\t")
            cells[draw(st.integers(0, len(cells) - 1))] = draw(st.sampled_from(TOKENS)).encode()
            lines[i] = b"\t".join(cells)
        else:
            lines[i] = draw(st.binary(max_size=30))
    data = b"\n".join(lines)
    return data[: draw(st.integers(0, len(data)))] if draw(st.integers(0, 3)) == 0 else data


def test_damaged_motion_ends_in_a_read_or_one_line(good_folder):
    valid = (good_folder / "motion.mot").read_bytes()
    path = _DIR / "motion.mot"

    @fuzz("motion")
    @given(damaged_lines(valid))
    def run(data: bytes) -> None:
        path.write_bytes(data)
        _only_data_file_errors(lambda p: read_storage(p, finite=True), path)

    run()


@st.composite
def damaged_xml(draw: st.DrawFn, valid: str) -> bytes:
    text = valid
    for _ in range(draw(st.integers(1, 3))):
        kind = draw(st.sampled_from(["cut", "tag", "text", "bytes"]))
        at = draw(st.integers(0, len(text)))
        if kind == "cut":
            text = text[:at]
        elif kind == "tag":
            text = text[:at] + draw(st.sampled_from(["<", ">", "</a>", "<a>", "&", "<!--"])) + \
                text[at:]  # fmt: skip
        elif kind == "text":
            text = text.replace(draw(st.sampled_from(["grf.mot", "ExternalLoads", "datafile",
                                                      "ExternalForce", "ground"])),
                                draw(st.sampled_from(["", "nope.mot", "x", " "])), 1)  # fmt: skip
        else:
            text = text[:at] + draw(st.binary(max_size=8)).decode("latin-1") + text[at:]
    return text.encode("utf-8", "surrogateescape")


def test_damaged_grf_xml_ends_in_a_read_or_one_line(good_folder):
    valid = (good_folder / "grf.xml").read_text()
    work = _fresh(good_folder, "xml")
    out = _DIR / "periodic"
    out.mkdir(exist_ok=True)
    periodic_records(work / "motion.mot", work / "grf.xml", out)  # the control

    @fuzz("grf_xml")
    @given(damaged_xml(valid))
    def run(data: bytes) -> None:
        (work / "grf.xml").write_bytes(data)
        _only_data_file_errors(read_external_loads_xml, work / "grf.xml")
        try:
            periodic_records(work / "motion.mot", work / "grf.xml", out)
        except FileNotFoundError:  # a <datafile> naming a file that is not there
            pass
        except DataFileError as exc:
            assert "\n" not in str(exc)

    run()


# -- cycle tables, as validate and report read them --------------------------------------------


def _valid_table() -> bytes:
    rows = ["percent_cycle,knee_angle_deg_mean,knee_angle_deg_sd,hip_flexion_deg_mean,"
            "hip_flexion_deg_sd"]  # fmt: skip
    rows += [f"{p},{-30 + p / 4:.3f},2.0,{20 - p / 3:.3f},3.0" for p in range(0, 101, 2)]
    return ("\n".join(rows) + "\n").encode()


def test_damaged_cycle_tables_end_in_a_reference_or_one_line():
    path = _DIR / "table.csv"
    path.write_bytes(_valid_table())
    reference_from_table(read_cycle_table(path))  # the control

    def read(p: Path) -> None:
        ref = reference_from_table(read_cycle_table(p))
        assert all(np.isfinite(m).all() for m in ref.mean.values())

    @fuzz("cycle_table")
    @given(damaged_lines(_valid_table().replace(b",", b"\t")))
    def run(data: bytes) -> None:
        path.write_bytes(data.replace(b"\t", b","))
        _only_data_file_errors(read, path)

    run()


# -- atlas files ---------------------------------------------------------------------------------


def _small_atlas() -> dict:
    data = json.loads((ATLAS_DIR / "male-natural.json").read_text())
    return data | {"entries": data["entries"][:3]}


def test_damaged_atlas_files_end_in_an_atlas_or_one_line():
    path = _DIR / "male-natural.json"
    path.write_text(json.dumps(_small_atlas()))
    read_atlas(path)  # the control

    @fuzz("atlas")
    @given(damaged_json(_small_atlas()))
    def run(data: bytes) -> None:
        path.write_bytes(data)
        _only_data_file_errors(read_atlas, path)

    run()


# -- sweep.json, through walk3d.campaign.sweep_folder.check_folder ------------------------------


def test_damaged_sweep_files_end_in_a_resume_or_one_line():
    from walk3d.campaign.sweep_folder import SweepMismatch, check_folder
    from walk3d.problem.settings import PredictionSettings

    folder = _DIR / "sweep"
    folder.mkdir(exist_ok=True)
    ours = PredictionSettings()
    check_folder(folder, ours)  # writes sweep.json; the control: it resumes
    check_folder(folder, ours)
    valid = json.loads((folder / "sweep.json").read_text())

    @fuzz("sweep")
    @given(damaged_json(valid))
    def run(data: bytes) -> None:
        (folder / "sweep.json").write_bytes(data)
        try:
            check_folder(folder, ours)
        except SweepMismatch as exc:
            assert "\n" not in str(exc)

    run()


# -- through the command line ---------------------------------------------------------------------


def _cli(*args) -> tuple[int, str]:
    import contextlib

    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        try:
            main([str(a) for a in args])
        except SystemExit as exc:
            return exc.code, err.getvalue()
    raise AssertionError("main() returned without SystemExit")


def test_walk3d_verify_on_damaged_results_exits_2_in_one_line(good_folder, monkeypatch):
    """OpenSim taken as absent: a folder that reads gets the install hint, one that does not
    its reader's line; both exit code 2."""
    monkeypatch.setattr(run_module, "opensim_available", lambda: False)
    work = _fresh(good_folder, "cli")

    @fuzz("cli_verify")
    @given(damaged_arrays(_arrays(good_folder)))
    def run(data: bytes) -> None:
        replace_result_file(work, "result.npz", data)
        code, err = _cli("verify", work)
        assert code == 2 and len(err.strip().splitlines()) == 1, err

    run()


def test_walk3d_atlas_show_on_damaged_files_exits_0(monkeypatch):
    folder = _DIR / "atlas_cli"
    folder.mkdir(exist_ok=True)
    monkeypatch.setattr("walk3d.solve.atlas.ATLAS_DIR", folder)

    @fuzz("cli_atlas")
    @given(damaged_json(_small_atlas()))
    def run(data: bytes) -> None:
        (folder / "male-natural.json").write_bytes(data)
        code, err = _cli("atlas", "show")
        assert code == 0 and err == "", err

    run()


def test_the_fuzz_checks_can_fail():
    """Negative controls: an exception other than DataFileError escapes the check, and so does
    a wrong exit code."""
    with pytest.raises(KeyError):
        _only_data_file_errors(lambda: {}["x"])
    assert CASES >= 500
