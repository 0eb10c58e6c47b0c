"""load_result's refusals: a result.npz of random bytes or with NaN or infinite arrays, and a
manifest that lists a path; each one DataFileError line (exit code 2 on the command line)."""

from __future__ import annotations

import io
import json
import shutil

import numpy as np
import pytest
from helpers import replace_result_file
from test_results_prediction import make_prediction

from walk3d.io.errors import DataFileError
from walk3d.results import load_result, save_prediction


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    return save_prediction(make_prediction(seed=4), tmp_path_factory.mktemp("load") / "r")


@pytest.fixture()
def copy(saved, tmp_path):
    return shutil.copytree(saved, tmp_path / "r")


def _npz(folder, **changes) -> bytes:
    with np.load(folder / "result.npz") as data:
        arrays = {k: data[k] for k in data.files} | changes
    buffer = io.BytesIO()
    np.savez(buffer, **arrays)
    return buffer.getvalue()


def _refused(folder, *words) -> str:
    with pytest.raises(DataFileError) as info:
        load_result(folder)
    message = str(info.value)
    assert "\n" not in message and all(w in message for w in words), message
    return message


def test_the_good_folder_loads(saved):
    """Negative control of the refusals below: the folder they damage is accepted."""
    assert load_result(saved).n_nodes > 0


def test_random_bytes_are_not_a_walk3d_result_and_say_nothing_of_pickles(copy):
    replace_result_file(copy, "result.npz", np.random.default_rng(0).bytes(5000))
    message = _refused(copy, "result.npz", "not a walk3d result", "damaged")
    assert "pickle" not in message


@pytest.mark.parametrize("data", [b"PK\x03\x04" + bytes(300), b"", b"\x93NUMPY" + bytes(100)],
                         ids=["zip-of-zeros", "empty", "npy"])  # fmt: skip
def test_a_damaged_or_other_numpy_file_is_refused(copy, data):
    replace_result_file(copy, "result.npz", data)
    _refused(copy, "result.npz")


@pytest.mark.parametrize("value", [np.nan, np.inf])
def test_a_non_finite_joint_angle_is_refused_naming_the_array(copy, value):
    with np.load(copy / "result.npz") as data:
        angle = data["joint_angle"].copy()
    angle[3, 2] = value
    replace_result_file(copy, "result.npz", _npz(copy, joint_angle=angle))
    _refused(copy, "result.npz", "joint_angle", "non-finite", "[3, 2]")


def test_nan_centres_of_pressure_are_kept_but_infinite_ones_refused(copy):
    """NaN is what a foot in the air has (the control); infinity is damage."""
    with np.load(copy / "result.npz") as data:
        cop = data["grf_cop"].copy()
    cop[0, 0, :] = np.nan
    replace_result_file(copy, "result.npz", _npz(copy, grf_cop=cop))
    assert np.isnan(load_result(copy).grf_cop[0, 0]).all()
    cop[1, 1, 0] = np.inf
    replace_result_file(copy, "result.npz", _npz(copy, grf_cop=cop))
    _refused(copy, "grf_cop")


def test_names_that_are_numbers_are_refused(copy):
    replace_result_file(copy, "result.npz", _npz(copy, dof_names=np.arange(3.0)))
    _refused(copy, "dof_names", "names")


@pytest.mark.parametrize(
    "manifest",
    ['{"files": {"../r/result.npz": 1}}', '{"files": {"result.npz": "big"}}', '{"files": []}',
     "[1, 2]", '{"files": {"a\\u0000b": 1}}', "[" * 100000],
    ids=["path", "size", "list", "array", "nul", "deep"],
)  # fmt: skip
def test_a_malformed_manifest_is_refused(copy, manifest):
    (copy / "manifest.json").write_text(manifest, encoding="utf-8")
    _refused(copy, "manifest.json")


def test_a_summary_of_invalid_utf8_is_refused(copy):
    replace_result_file(copy, "summary.json", b'{"a": "\xff"}')
    _refused(copy, "summary.json", "UTF-8")
    replace_result_file(copy, "summary.json", b"[]")
    _refused(copy, "summary.json", "not an object")


def _time_first(folder, keep) -> dict[str, np.ndarray]:
    """Every array whose first axis is time, cut to the samples ``keep``."""
    with np.load(folder / "result.npz") as data:
        n = data["time"].size
        return {k: data[k][keep] for k in data.files if data[k].ndim and data[k].shape[0] == n}


@pytest.mark.parametrize(
    ("change", "words"),
    [(lambda t: {"time": t[::-1].copy()}, "time is not increasing"),
     (lambda t: {"time": np.zeros_like(t)}, "time is not increasing"),
     ("one", "time holds 1 samples"), ("two", "time holds 2 samples"),
     ("ten", "time holds 10 samples")],
    ids=["reversed", "zeros", "one", "two", "ten"],
)  # fmt: skip
def test_a_time_axis_that_is_not_a_cycle_is_refused(copy, change, words):
    """They were read, reported, animated and validated (r = NaN marked 'ok'), exit 0."""
    with np.load(copy / "result.npz") as data:
        time = data["time"]
    if callable(change):
        arrays = change(time)
    else:
        arrays = _time_first(copy, slice(0, {"one": 1, "two": 2, "ten": 10}[change]))
    replace_result_file(copy, "result.npz", _npz(copy, **arrays))
    _refused(copy, "result.npz", words)


def test_eleven_increasing_samples_are_a_cycle(copy):
    """Negative control: the fewest samples accepted (walk3d writes 101)."""
    replace_result_file(copy, "result.npz", _npz(copy, **_time_first(copy, slice(0, 11))))
    assert load_result(copy).n_nodes == 11


@pytest.mark.parametrize(("marker", "words"), [
    ("sweep.json", "is a sweep folder, not a prediction: give one of its speed folders"),
    ("campaign.json", "is a campaign folder, not a prediction: give its best/"),
])  # fmt: skip
def test_a_sweep_or_campaign_folder_is_named_as_such(tmp_path, capsys, saved, marker, words):
    """Was "incomplete result folder: no manifest.json" (compare, validate, report...)."""
    from helpers import cli, one_line_error

    folder = tmp_path / "f"
    folder.mkdir()
    (folder / marker).write_text("{}\n")
    _refused(folder, words)
    one_line_error(cli(capsys, "compare", saved, folder, "--out", tmp_path / "c"), words)
    (folder / marker).unlink()  # control: a folder of nothing is an incomplete result
    _refused(folder, "incomplete result folder: no manifest.json")


@pytest.mark.parametrize(("marker", "inner", "words"), [
    ("campaign.json", "starts", "is a campaign's starts folder, not a prediction: give one of its "
     "seed_* folders"),
    ("sweep.json", "speeds", "is a sweep's speeds folder, not a prediction: give one of its v_* "
     "folders"),
])  # fmt: skip
def test_a_campaigns_starts_or_a_sweeps_speeds_folder_is_named_as_such(
    tmp_path, capsys, saved, marker, inner, words
):
    """compare p1 c1/starts and audit p1 s1/speeds said "incomplete result folder"."""
    from helpers import cli, one_line_error

    (tmp_path / marker).write_text("{}\n")
    folder = tmp_path / inner
    shutil.copytree(saved, folder / ("seed_000000" if inner == "starts" else "v_1.300"))
    message = _refused(folder, words)
    assert str(folder / ("seed_000000" if inner == "starts" else "v_1.300")) in message
    one_line_error(cli(capsys, "compare", saved, folder, "--out", tmp_path / "c"), words)
    one_line_error(cli(capsys, "audit", saved, folder), words)
    (tmp_path / marker).unlink()  # control: without its parent's marker, an incomplete result
    _refused(folder, "incomplete result folder: no manifest.json")


@pytest.mark.parametrize(("name", "factor", "words"), [
    ("joint_moment", 1e300, "beyond ±1e+06 N m"),
    ("grf_force", 1e5, "beyond ±1e+07 N"),
    ("joint_angle", 1e4, "beyond ±100000 °"),
])  # fmt: skip
def test_an_implausible_magnitude_is_refused_under_a_forged_manifest(
    copy, tmp_path, capsys, name, factor, words
):
    """joint_moment x1e300 with the manifest rewritten passed, and validate printed numpy's
    overflow warnings with file paths and rows labelled "constant reference"."""
    from helpers import cli, one_line_error

    with np.load(copy / "result.npz") as data:
        scaled = data[name] * factor
    replace_result_file(copy, "result.npz", _npz(copy, **{name: scaled}))
    _refused(copy, "result.npz", name, words, "not a walking result")
    one_line_error(cli(capsys, "compare", copy, copy, "--out", tmp_path / "c"), name, words)


@pytest.mark.parametrize(("change", "words"), [
    (lambda m: m * np.where(np.arange(m.size) == 1, -1.0, 1.0), "segment_mass holds -"),
    (lambda m: m * np.where(np.arange(m.size) == 0, 0.0, 1.0), "segment_mass holds 0 kg"),
    (lambda m: m * 0.9, "segment_mass sums to"),
])  # fmt: skip
def test_a_segment_mass_that_is_not_positive_or_not_the_body_mass_is_refused(
    copy, tmp_path, capsys, change, words
):
    """A negative segment mass under a forged manifest passed: compare showed 61.94 kg of body
    for a summary of 68.8 kg."""
    from helpers import cli, one_line_error

    summary = json.loads((copy / "summary.json").read_text())
    with np.load(copy / "result.npz") as data:
        mass = data["segment_mass"]
    summary["body_mass_kg"] = float(mass.sum())
    replace_result_file(copy, "summary.json", json.dumps(summary).encode())
    assert load_result(copy).body_mass == pytest.approx(summary["body_mass_kg"])  # control
    replace_result_file(copy, "result.npz", _npz(copy, segment_mass=change(mass)))
    _refused(copy, "result.npz", words)
    one_line_error(cli(capsys, "compare", copy, copy, "--out", tmp_path / "c"), words)


def test_the_body_mass_check_allows_added_mass_and_de_levas_rounding(tmp_path):
    """A what-if added mass is in both the segments and body_mass_kg; a female body's segments
    sum to 0.9999 of its mass: both accepted. save_prediction refuses a body mass 10 % off."""
    from dataclasses import replace

    from walk3d.body.changes import apply_changes
    from walk3d.body.model import build_body
    from walk3d.results.readback import check_masses

    for sex, added in (("female", ()), ("male", (("torso", 10.0), ("foot", 2.0)))):
        body = apply_changes(build_body(68.8, 1.77, sex), (), added, ())
        check_masses("result.npz", np.array([s.mass for s in body.segments]),
                     {"body_mass_kg": body.mass})  # fmt: skip
    pred = make_prediction(seed=4)
    bad = replace(pred, summary=pred.summary | {"body_mass_kg": pred.body_mass * 1.1})
    with pytest.raises(ValueError, match="segment_mass sums to .* body_mass_kg"):
        save_prediction(bad, tmp_path / "bad")
    assert not (tmp_path / "bad").exists()
    good = replace(pred, summary=pred.summary | {"body_mass_kg": pred.body_mass})  # control
    assert load_result(save_prediction(good, tmp_path / "ok")).n_nodes > 0


def test_save_refuses_what_load_would_refuse(tmp_path):
    from dataclasses import replace

    pred = make_prediction(seed=4)
    with pytest.raises(ValueError, match="joint_moment holds .* beyond ±1e\\+06 N m"):
        save_prediction(replace(pred, joint_moment=pred.joint_moment * 1e9), tmp_path / "r")
    assert not (tmp_path / "r").exists()
    save_prediction(pred, tmp_path / "ok")  # control: the same prediction as it is
    assert load_result(tmp_path / "ok").n_nodes > 0
