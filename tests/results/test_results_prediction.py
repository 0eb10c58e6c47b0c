"""Result folders: PredictedCycle save/load round trip, OpenSim files and the summary figure."""

import json
import re
import shutil
import xml.etree.ElementTree as ET
from dataclasses import replace

import numpy as np
import pytest

from walk3d.body.model import JOINT_NAMES, SEGMENT_NAMES, build_body
from walk3d.io.checks import file_digest
from walk3d.io.errors import DataFileError
from walk3d.io.external_loads import extract_foot_loads, grf_column_names
from walk3d.io.storage import read_storage
from walk3d.plots import summary_figure
from walk3d.plots.summary import _title
from walk3d.results import PredictedCycle, load_result, pelvis_angles, save_prediction
from walk3d.results.opensim import OPENSIM_COORDINATES, write_motion

N = 21
RAJAGOPAL = {
    "hip_flexion_r", "hip_adduction_r", "hip_rotation_r", "knee_angle_r", "ankle_angle_r",
    "subtalar_angle_r", "hip_flexion_l", "hip_adduction_l", "hip_rotation_l", "knee_angle_l",
    "ankle_angle_l", "subtalar_angle_l", "lumbar_extension", "lumbar_bending", "lumbar_rotation",
    "arm_flex_r", "arm_add_r", "arm_rot_r", "elbow_flex_r", "arm_flex_l", "arm_add_l",
    "arm_rot_l", "elbow_flex_l",
}  # fmt: skip


def _unit_quaternions(rng: np.random.Generator, shape: tuple[int, ...]) -> np.ndarray:
    q = rng.normal(size=shape + (4,))
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def make_prediction(seed: int = 0, summary: dict | None = None) -> PredictedCycle:
    rng = np.random.default_rng(seed)
    body = build_body()
    time = np.linspace(0.0, 1.1, N)
    phase = 2 * np.pi * time / 1.1
    n_dof = len(body.dof_names)
    amp = rng.uniform(0.05, 0.6, n_dof)
    shift = rng.uniform(0, 2 * np.pi, n_dof)
    angle = amp * np.sin(phase[:, None] + shift)
    active = np.zeros((12, 3), bool)
    for j, joint in enumerate(body.joints):
        active[j, list(joint.dof_slots)] = True
    # right foot in stance for the first 60 %, left from 50 % on (wrapping): NaN COP in swing
    stance = np.stack([phase < 0.6 * 2 * np.pi, phase >= 0.5 * 2 * np.pi], axis=1)
    force = rng.normal(size=(N, 2, 3)) * [50.0, 300.0, 20.0]
    force[..., 1] = np.abs(force[..., 1]) + 100.0
    force[~stance] = 0.0
    cop = rng.normal(size=(N, 2, 3)) * 0.1
    cop[~stance] = np.nan
    free = np.where(stance, rng.normal(size=(N, 2)), 0.0)
    default_summary = {
        "inputs": {"speed_m_s": 1.2, "period_s": 1.1, "double_support_s": 0.12},
        "converged": True,
        "status": "Solve_Succeeded",
        "iterations": 57,
        "wall_time_s": 12.5,
        "objective": {
            "C_tor": {"total": 0.0123, "x": 0.002, "y": 0.001, "z": 0.0093},
            "C_en": {"total": 1.5, "x": 0.2, "y": 0.1, "z": 1.2},
        },
        "max_constraint_violation": 3.2e-9,
        "double_support_contact_residual_m": None,
        "stride_length_m": 1.32,
        "seed": 4,
    }
    return PredictedCycle(
        time=time,
        segment_names=SEGMENT_NAMES,
        segment_mass=[s.mass for s in body.segments],
        segment_inertia=[np.diag(s.inertia) for s in body.segments],
        segment_com_position=rng.normal(size=(N, 13, 3)),
        segment_orientation=_unit_quaternions(rng, (N, 13)),
        dof_names=body.dof_names,
        joint_angle=angle,
        joint_names=JOINT_NAMES,
        joint_moment=rng.normal(size=(N, 12, 3)) * 20 * active,
        joint_axis_active=active,
        grf_force=force,
        grf_cop=cop,
        grf_free_moment=free,
        pelvis_position=np.column_stack([1.2 * time, 0.95 + 0.02 * np.sin(2 * phase), 0 * time]),
        summary=default_summary if summary is None else summary,
    )


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    pred = make_prediction()
    out = save_prediction(pred, tmp_path_factory.mktemp("run") / "nested" / "result")
    return pred, out


def test_prediction_is_read_only_and_checked():
    pred = make_prediction()
    with pytest.raises(ValueError):
        pred.joint_angle[0, 0] = 1.0
    with pytest.raises(AttributeError):
        pred.time = np.zeros(N)  # type: ignore[misc]
    assert pred.joint_axis_active.dtype == bool
    assert pred.body_mass == pytest.approx(68.8, rel=1e-6)
    with pytest.raises(ValueError, match="grf_cop"):
        PredictedCycle(**{**_fields(pred), "grf_cop": np.zeros((N, 2, 2))})


def _fields(pred: PredictedCycle) -> dict:
    return {k: getattr(pred, k) for k in pred.__dataclass_fields__}


def test_save_writes_all_files_without_temporaries(saved):
    _, out = saved
    names = sorted(p.name for p in out.iterdir())
    files = ["result.npz", "summary.json", "motion.mot", "grf.mot", "grf.xml", "manifest.json",
             "model.osim", "inverse_dynamics.sto", "markers.c3d"]  # fmt: skip
    assert names == sorted(files)
    assert not [p for p in out.parent.iterdir() if p.name.startswith(".tmp_")]


def test_a_failed_save_leaves_nothing_and_keeps_the_earlier_result(saved, tmp_path):
    pred, out = saved
    before = {p.name: p.read_bytes() for p in out.iterdir()}

    def broken(folder):
        (folder / "summary.png").write_bytes(b"half")
        raise OSError(28, "No space left on device")

    with pytest.raises(OSError, match="No space"):
        save_prediction(pred, out, extra=broken)
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    with pytest.raises(OSError):
        save_prediction(pred, tmp_path / "fresh", extra=broken)
    assert sorted(p.name for p in tmp_path.iterdir()) == []
    save_prediction(pred, tmp_path / "fresh", extra=lambda f: (f / "x.png").write_bytes(b"png"))
    assert (tmp_path / "fresh" / "x.png").read_bytes() == b"png"  # control: extra files land
    assert "x.png" in json.loads((tmp_path / "fresh" / "manifest.json").read_text())["files"]


@pytest.mark.parametrize("damage", ["delete", "truncate", "no manifest"])
def test_an_incomplete_result_folder_is_refused(saved, tmp_path, damage):
    import shutil

    _, out = saved
    bad = tmp_path / "bad"
    shutil.copytree(out, bad)
    load_result(bad)  # negative control: the intact copy loads
    if damage == "delete":
        (bad / "motion.mot").unlink()
    elif damage == "truncate":
        text = (bad / "grf.mot").read_text()
        (bad / "grf.mot").write_text(text[: len(text) // 2])
    else:
        (bad / "manifest.json").unlink()
    with pytest.raises(DataFileError, match="incomplete"):
        load_result(bad)


def test_a_view_rewritten_before_its_manifest_entry_is_still_complete(saved, tmp_path):
    """A view (report.html, ...) is replaced atomically and then its size recorded: a crash
    between the two leaves a stale size, which must not make the result unreadable."""
    import shutil

    from walk3d.results.prediction import VIEW_FILES, record_file

    _, out = saved
    folder = tmp_path / "views"
    shutil.copytree(out, folder)
    (folder / "report.html").write_text("<p>first</p>")
    record_file(folder, "report.html")
    (folder / "report.html").write_text("<p>the page made again, longer</p>")  # no record
    assert "report.html" in VIEW_FILES
    load_result(folder)  # still complete
    (folder / "report.html").unlink()
    with pytest.raises(DataFileError, match="report.html is missing"):  # but it must be there
        load_result(folder)
    text = (folder / "grf.mot").read_text()  # control: a result file's size still counts
    (folder / "grf.mot").write_text(text + "\n")
    with pytest.raises(DataFileError, match="incomplete"):
        load_result(folder)


def test_load_round_trip(saved):
    pred, out = saved
    back = load_result(out)
    for name, value in _fields(pred).items():
        got = getattr(back, name)
        if name == "joint_angle":
            np.testing.assert_allclose(got, value, rtol=0, atol=1e-12)
        elif isinstance(value, np.ndarray):
            assert got.dtype == value.dtype, name
            np.testing.assert_array_equal(got, value, err_msg=name)
            assert not got.flags.writeable
        else:
            assert got == value, name
    assert back.summary == pred.summary
    assert np.isnan(back.grf_cop).any()


def test_npz_keys_and_degrees(saved):
    pred, out = saved
    with np.load(out / "result.npz", allow_pickle=False) as data:
        assert set(data.files) == set(_fields(pred)) - {"summary"}
        np.testing.assert_allclose(data["joint_angle"], np.degrees(pred.joint_angle), rtol=1e-15)
        assert tuple(data["dof_names"]) == pred.dof_names


def test_summary_json_is_sorted_and_pretty(saved):
    pred, out = saved
    text = (out / "summary.json").read_text()
    assert text.startswith("{\n  ")
    assert json.loads(text) == pred.summary
    top = [line.split('"')[1] for line in text.splitlines() if line.startswith('  "')]
    assert top == sorted(pred.summary)


def test_motion_file(saved):
    pred, out = saved
    st = read_storage(out / "motion.mot")
    assert st.in_degrees is True
    np.testing.assert_array_equal(st.time, pred.time)
    assert st.columns[:6] == (
        "pelvis_tilt", "pelvis_list", "pelvis_rotation", "pelvis_tx", "pelvis_ty", "pelvis_tz",
    )  # fmt: skip
    assert RAJAGOPAL <= set(st.columns)
    assert "neck_flexion" in st.columns
    assert "knee_flexion_r" not in st.columns
    for k, dof in enumerate(pred.dof_names):
        col = st.column(OPENSIM_COORDINATES[dof])
        np.testing.assert_array_equal(col, np.degrees(pred.joint_angle[:, k]))
    np.testing.assert_allclose(st.column("knee_angle_l"), np.degrees(pred.dof("knee_flexion_l")))
    pelvis = np.degrees(pelvis_angles(pred.segment_orientation[:, 0]))
    np.testing.assert_allclose(st.data[:, :3], pelvis)
    np.testing.assert_array_equal(st.data[:, 3:6], pred.pelvis_position)


def test_grf_files(saved):
    pred, out = saved
    st = read_storage(out / "grf.mot")
    assert st.columns == grf_column_names("r") + grf_column_names("l")
    np.testing.assert_array_equal(st.time, pred.time)
    assert not np.isnan(st.data).any()
    loads = extract_foot_loads(out / "grf.mot", out / "grf.xml")
    np.testing.assert_array_equal(loads.right.force, pred.grf_force[:, 0])
    np.testing.assert_array_equal(loads.left.force, pred.grf_force[:, 1])
    stance = ~np.isnan(pred.grf_cop[:, 0, 0])
    np.testing.assert_array_equal(loads.right.cop[stance], pred.grf_cop[stance, 0])
    np.testing.assert_array_equal(loads.left.torque[:, 1], pred.grf_free_moment[:, 1])
    root = ET.parse(out / "grf.xml").getroot()
    assert root.find(".//datafile").text == "grf.mot"
    bodies = sorted(e.text for e in root.iter("applied_to_body"))
    assert bodies == ["calcn_l", "calcn_r"]


def test_write_motion_standalone(tmp_path):
    pred = make_prediction(seed=3)
    path = write_motion(tmp_path / "m.mot", pred)
    st = read_storage(path)
    assert len(st.columns) == 6 + 24
    np.testing.assert_array_equal(st.column("hip_flexion_r"), np.degrees(pred.dof("hip_flexion_r")))


def test_load_errors(tmp_path, saved):
    import shutil

    with pytest.raises(DataFileError, match="incomplete"):
        load_result(tmp_path)
    _, out = saved
    bad = tmp_path / "bad"
    shutil.copytree(out, bad)

    def rewrite(name, write):
        write(bad / name)
        manifest = json.loads((bad / "manifest.json").read_text())
        manifest["files"][name] = (bad / name).stat().st_size
        if name in manifest["sha256"]:  # only the content is wrong, not the folder
            manifest["sha256"][name] = file_digest(bad / name)
        (bad / "manifest.json").write_text(json.dumps(manifest))

    rewrite("summary.json", lambda p: p.write_text("{not json"))
    with pytest.raises(DataFileError, match="JSON"):
        load_result(bad)
    rewrite("summary.json", lambda p: p.write_text("{}"))
    with np.load(out / "result.npz") as data:
        arrays = {k: data[k] for k in data.files if k != "grf_cop"}
    rewrite("result.npz", lambda p: np.savez(p, **arrays))
    with pytest.raises(DataFileError, match="grf_cop"):
        load_result(bad)


def test_summary_figure_png(tmp_path):
    summary = {"converged": False, "objective": {"C_tor": "n/a", "C_en": {"x": 1.0}}}
    pred = make_prediction(seed=1, summary=summary)
    path = summary_figure(pred, tmp_path / "figs" / "summary.png")
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert len(data) > 10_000
    assert [p.name for p in path.parent.iterdir()] == ["summary.png"]


def test_summary_title():
    pred = make_prediction()
    title = _title(pred.summary)
    assert title.startswith("walk3d prediction: converged (Solve_Succeeded)")
    assert "C_tor = 0.0123" in title and "C_en = 1.5" in title
    assert "max violation 3.20e-09" in title
    assert _title({"converged": False}) == "walk3d prediction: NOT CONVERGED"
    assert "unknown" in _title({})
    assert _title({"converged": False, "objective": {"C_tor": None}, "iterations": "x"}) == (
        "walk3d prediction: NOT CONVERGED"
    )


def test_warm_up_leaves_the_summary_figure_unchanged(tmp_path):
    """walk3d.plots.warm_up (run in a thread while IPOPT iterates) writes nothing and changes
    no Matplotlib state that the figure reads: the same PNG, byte for byte, before and after.
    Negative control: another prediction gives another PNG."""
    from walk3d.plots import warm_up

    pred = make_prediction(seed=1)
    before = summary_figure(pred, tmp_path / "a.png").read_bytes()
    warm_up()
    after = summary_figure(pred, tmp_path / "b.png").read_bytes()
    other = summary_figure(make_prediction(seed=2), tmp_path / "c.png").read_bytes()
    assert before == after and other != before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.png", "b.png", "c.png"]


def test_a_result_npz_swapped_between_folders_is_refused(saved, tmp_path):
    """Two results of the same shape have result.npz files of the same size: only the
    manifest's SHA-256 tells them apart. The untouched folder is the negative control."""
    from walk3d.results.prediction import check_complete

    a, b = tmp_path / "a", tmp_path / "b"
    save_prediction(make_prediction(1), a)
    save_prediction(make_prediction(2), b)
    assert (a / "result.npz").stat().st_size == (b / "result.npz").stat().st_size
    check_complete(a)
    shutil.copyfile(b / "result.npz", a / "result.npz")
    with pytest.raises(DataFileError, match="SHA-256"):
        check_complete(a)
    with pytest.raises(DataFileError, match="SHA-256"):
        load_result(a)


@pytest.mark.parametrize(
    ("name", "index", "value", "words"),
    [("joint_angle", (5, 3), np.nan, "joint_angle holds non-finite values (1, the first nan"),
     ("grf_cop", (0, 0, 0), np.inf, "grf_cop holds non-finite values (1, the first inf"),
     ("pelvis_position", (3, 1), -np.inf, "pelvis_position holds non-finite"),
     ("time", (4,), 0.0, "time is not increasing")],
)  # fmt: skip
def test_save_refuses_what_load_would_refuse(saved, tmp_path, name, index, value, words):
    """``replace(p, joint_angle=<a NaN>).save()`` succeeded and load_result then refused it."""
    pred = saved[0]
    arr = getattr(pred, name).copy()
    arr[index] = value
    with pytest.raises(ValueError, match=re.escape(words)) as info:
        save_prediction(replace(pred, **{name: arr}), tmp_path / "r")
    assert "\n" not in str(info.value) and "could not read it back" in str(info.value)
    assert not list(tmp_path.iterdir())  # nothing written


def test_what_save_accepts_loads_back(saved, tmp_path):
    """Negative control: NaN centres of pressure in swing are saved and read back."""
    pred = saved[0]
    assert np.isnan(pred.grf_cop).any()
    back = load_result(save_prediction(pred, tmp_path / "r"))
    np.testing.assert_array_equal(np.isnan(back.grf_cop), np.isnan(pred.grf_cop))
