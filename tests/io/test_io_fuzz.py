"""Fuzzing the readers: damaged storage, GRF, CSV, TRC and C3D files end in a valid parse or in
walk3d's :class:`DataFileError`, never in another exception. Each file starts valid (written by
walk3d or ezc3d) and hypothesis damages it: truncation, deleted, repeated or swapped lines,
replaced tokens (NaN, inf, words, huge numbers), random bytes and flipped C3D bytes."""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np
import pytest
from c3d_support import write_c3d
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from walk3d.io import (
    DataFileError,
    extract_foot_loads,
    read_c3d,
    read_cycle_table,
    read_storage,
    read_trc,
    write_storage,
)

EXAMPLES = 150
"""Examples per format; five formats give 750 damaged files per run (derandomized)."""
FUZZ = settings(max_examples=EXAMPLES, deadline=None, derandomize=True,
                suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
TOKENS = ["nan", "NaN", "inf", "-inf", "1e999", "", " ", "abc", "-", "1,5", "0x10", "1e-320",
          "\t", "endheader", "nRows=3", "nColumns=-1", "version=9", "time", "é",
          "\x00"]  # fmt: skip

_DIR = Path(tempfile.mkdtemp(prefix="walk3d-fuzz-"))


def _valid_storage() -> bytes:
    t = np.linspace(0.0, 0.5, 26)
    cols = ["hip_flexion_r", "knee_angle_r", "ankle_angle_r"]
    data = np.column_stack([20 * np.sin(6 * t), -30 * np.sin(6 * t) ** 2, 5 * np.cos(6 * t)])
    return write_storage(_DIR / "valid.mot", t, cols, data, in_degrees=True).read_bytes()


def _valid_grf() -> bytes:
    t = np.linspace(0.0, 1.0, 51)
    fy = np.clip(np.sin(2 * np.pi * t), 0, None) * 700
    cols, data = [], []
    for k, fz in ((1, fy), (2, fy[::-1])):
        cols += [f"ground_force_{k}_v{a}" for a in "xyz"] + [
            f"ground_force_{k}_p{a}" for a in "xyz"
        ]
        data += [0.1 * fz, fz, 0 * fz, 0.2 + 0 * fz, 0 * fz, 0.1 * k + 0 * fz]
    return write_storage(_DIR / "valid_grf.mot", t, cols, np.column_stack(data)).read_bytes()


def _valid_csv() -> bytes:
    rows = ["percent_cycle,knee_angle_deg_mean,knee_angle_deg_sd,hip_flexion_deg_mean"]
    rows += [f"{p},{-30 + p / 4:.3f},2.0,{20 - p / 3:.3f}" for p in range(101)]
    return ("\n".join(rows) + "\n").encode()


def _valid_trc() -> bytes:
    n, labels = 12, ("HEEL", "TOE")
    head = ["PathFileType\t4\t(X/Y/Z)\tfuzz.trc",
            "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame"
            "\tOrigNumFrames", f"100\t100\t{n}\t2\tmm\t100\t1\t{n}",
            "Frame#\tTime\t" + "\t\t\t".join(labels),
            "\t\tX1\tY1\tZ1\tX2\tY2\tZ2", ""]  # fmt: skip
    body = [f"{i + 1}\t{i / 100:.2f}\t{i}\t50\t100\t{i + 200}\t30\t100" for i in range(n)]
    return ("\n".join(head + body) + "\n").encode()


def _valid_c3d() -> bytes:
    n, rate = 10, 100.0
    points = np.zeros((n, 2, 3))
    points[:, :, 0] = np.arange(n)[:, None] * 10.0
    channels = np.zeros((n * 10, 6))
    channels[:, 2] = -700.0
    corners = np.array([[300, 200, 0], [-300, 200, 0], [-300, -200, 0], [300, -200, 0]], float)
    path = write_c3d(_DIR / "valid.c3d", point_rate=rate, labels=("A", "B"), points=points,
                     analog_rate=10 * rate, plates=[channels], corners=[corners])  # fmt: skip
    return path.read_bytes()


def _read_storage(path: Path) -> None:
    s = read_storage(path)
    for name in s.columns:
        s.column(name)


def _read_grf(path: Path) -> None:
    extract_foot_loads(read_storage(path))


def _read_c3d(path: Path) -> None:
    read_c3d(path)


READERS = {
    "storage": (_valid_storage, _read_storage, ".mot"),
    "grf": (_valid_grf, _read_grf, ".mot"),
    "csv": (_valid_csv, read_cycle_table, ".csv"),
    "trc": (_valid_trc, read_trc, ".trc"),
}


@st.composite
def damaged_text(draw: st.DrawFn, valid: bytes) -> bytes:
    """``valid`` with one to three line or token damages, sometimes then truncated."""
    lines = valid.split(b"\n")
    for _ in range(draw(st.integers(1, 3))):
        kind = draw(st.sampled_from(["delete", "repeat", "swap", "token", "bytes", "cells"]))
        i = draw(st.integers(0, len(lines) - 1))
        if kind == "delete" and len(lines) > 1:
            del lines[i]
        elif kind == "repeat":
            lines.insert(i, lines[i])
        elif kind == "swap":
            j = draw(st.integers(0, len(lines) - 1))
            lines[i], lines[j] = lines[j], lines[i]
        elif kind == "token":
            sep = b"," if b"," in lines[i] else b"\t"
            cells = lines[i].split(sep)
            k = draw(st.integers(0, len(cells) - 1))
            cells[k] = draw(st.sampled_from(TOKENS)).encode()
            lines[i] = sep.join(cells)
        elif kind == "bytes":
            lines[i] = draw(st.binary(max_size=40))
        else:
            sep = b"," if b"," in lines[i] else b"\t"
            cells = lines[i].split(sep)
            lines[i] = sep.join(cells[: draw(st.integers(0, len(cells)))])
    data = b"\n".join(lines)
    if draw(st.booleans()):
        data = data[: draw(st.integers(0, len(data)))]
    return data


def _check(reader, data: bytes, suffix: str) -> None:
    path = _DIR / f"damaged{suffix}"
    path.write_bytes(data)
    try:
        reader(path)
    except DataFileError as exc:
        assert "\n" not in str(exc) and str(exc).startswith(path.name)


@pytest.mark.parametrize("fmt", sorted(READERS))
def test_damaged_text_files_end_in_a_parse_or_data_file_error(fmt: str) -> None:
    make, reader, suffix = READERS[fmt]
    valid = make()
    reader_path = _DIR / f"valid_check{suffix}"
    reader_path.write_bytes(valid)
    reader(reader_path)  # the undamaged file parses

    @FUZZ
    @given(damaged_text(valid))
    def run(data: bytes) -> None:
        _check(reader, data, suffix)

    run()


@st.composite
def damaged_binary(draw: st.DrawFn, valid: bytes) -> bytes:
    """``valid`` with bytes overwritten in the header, parameter or data section, or cut."""
    data = bytearray(valid)
    for _ in range(draw(st.integers(1, 4))):
        start = draw(st.sampled_from([2, 512, 520, 600, 1024, len(data) // 2, len(data) - 64]))
        at = min(len(data) - 1, start + draw(st.integers(0, 63)))
        patch = draw(st.binary(min_size=1, max_size=8))
        data[at : at + len(patch)] = patch
    if draw(st.booleans()):
        del data[draw(st.integers(0, len(data))) :]
    return bytes(data)


def test_damaged_c3d_files_end_in_a_parse_or_data_file_error() -> None:
    valid = _valid_c3d()
    (_DIR / "ok.c3d").write_bytes(valid)
    read_c3d(_DIR / "ok.c3d")

    @FUZZ
    @given(damaged_binary(valid))
    def run(data: bytes) -> None:
        _check(_read_c3d, data, ".c3d")

    run()


def test_the_fuzz_check_can_fail() -> None:
    """Negative control: an exception other than DataFileError is caught by the check."""

    def raw(path: Path) -> None:
        float(path.read_text().split()[0])

    with pytest.raises(ValueError):
        _check(raw, b"abc", ".txt")


@pytest.mark.parametrize("damage", ["dimensions", "backwards", None])
def test_a_damaged_parameter_entry_is_refused_not_looped_on(tmp_path, damage) -> None:
    """ezc3d loops without end on a parameter whose dimensions overrun its entry, so the reader
    walks the entries first (in a subprocess here: a regression fails instead of hanging)."""
    import subprocess
    import sys

    data = bytearray(_valid_c3d())
    at = data.index(b"DESCRIPTIONS") + len(b"DESCRIPTIONS")  # then offset, type, ndim, dims
    if damage == "dimensions":
        data[at + 4 : at + 6] = bytes([0x1F, 0x95])  # 31 x 149 characters, found by the fuzzer
    elif damage == "backwards":
        data[at : at + 2] = (-40).to_bytes(2, "little", signed=True)
    path = tmp_path / "damaged.c3d"
    path.write_bytes(bytes(data))
    code = (f"from walk3d.io import read_c3d, DataFileError\ntry:\n read_c3d({str(path)!r})"
            "; print('ok')\nexcept DataFileError as e: print(e)")  # fmt: skip
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    expect = "ok" if damage is None else "the parameter section is damaged"
    assert r.stdout.startswith(expect) or expect in r.stdout, r.stdout + r.stderr
