"""Mutations of the binary files (:mod:`fuzz_mutations`): a result's ``result.npz``, damaged
array by array, and C3D files, damaged through ezc3d (values, labels, frames, rates) or byte
by byte."""

from __future__ import annotations

import io
import struct
import tempfile
from pathlib import Path

import numpy as np
from fuzz_mutations import LONG, junk

ODD = (np.nan, np.inf, -np.inf, 1e308)


def npz_arrays(data: bytes) -> dict[str, np.ndarray]:
    """The arrays of an .npz archive's bytes."""
    with np.load(io.BytesIO(data), allow_pickle=False) as archive:
        return {k: archive[k] for k in archive.files}


def npz_bytes(arrays: dict[str, np.ndarray]) -> bytes:
    """``arrays`` as the bytes of an .npz archive (object arrays pickled)."""
    buffer = io.BytesIO()
    np.savez(buffer, **arrays)
    return buffer.getvalue()


def _pick(rng: np.random.Generator, names: list[str]) -> str:
    return names[int(rng.integers(0, len(names)))]


def npz_mutation(data: bytes, kind: str, rng: np.random.Generator) -> bytes:
    """A walk3d ``result.npz`` (time-first arrays, names as unicode) damaged by ``kind``."""
    a = npz_arrays(data)
    n = a["time"].shape[0]
    floats = [k for k, v in a.items() if v.dtype.kind == "f" and v.size]
    timed = [k for k, v in a.items() if v.ndim and v.shape[0] == n]
    names = [k for k, v in a.items() if v.dtype.kind == "U"]
    if kind == "nonfinite":
        for _ in range(int(rng.integers(1, 4))):
            key = _pick(rng, floats)
            flat = a[key].reshape(-1).copy()
            flat[rng.integers(0, flat.size, int(rng.integers(1, 6)))] = rng.choice(ODD)
            a[key] = flat.reshape(a[key].shape)
    elif kind == "swap_columns":
        key = _pick(rng, [k for k in floats if a[k].ndim >= 2 and a[k].shape[1] >= 2])
        i, j = (int(v) for v in rng.choice(a[key].shape[1], 2, replace=False))
        a[key] = a[key].copy()
        a[key][:, [i, j]] = a[key][:, [j, i]]
    elif kind == "swap_labels":
        key = _pick(rng, names)
        i, j = (int(v) for v in rng.choice(a[key].size, 2, replace=False))
        a[key] = a[key].copy()
        a[key][[i, j]] = a[key][[j, i]]
    elif kind == "header_only":
        a = {k: a[k] for k in names}
    elif kind in ("duplicate_rows", "reverse_rows"):
        lo = int(rng.integers(0, n - 2))
        hi = min(n, lo + int(rng.integers(2, 20)))
        for key in timed:
            v = a[key]
            a[key] = np.concatenate([v[:hi], v[lo:hi], v[hi:]]) if kind == "duplicate_rows" \
                else np.concatenate([v[:lo], v[lo:hi][::-1], v[hi:]])  # fmt: skip
    elif kind == "time_constant":
        a["time"] = np.full(n, 0.0 if rng.integers(0, 2) else a["time"][0])
    elif kind == "retype":
        key = _pick(rng, sorted(a))
        choices = (lambda v: v.astype(str), lambda v: np.ones(v.shape, np.int64),
                   lambda v: np.ones(v.shape, bool), lambda v: np.ones(v.shape, complex),
                   lambda v: np.array(v.tolist(), dtype=object))  # fmt: skip
        a[key] = choices[int(rng.integers(0, len(choices)))](a[key])
    elif kind == "reshape":
        key = _pick(rng, sorted(a))
        v = a[key]
        choices = (v.reshape(-1), v.T, v.reshape(-1)[: max(v.size - 1, 0)], np.zeros((0,)),
                   np.array(1.5), v[: max(n // 4, 1)])  # fmt: skip
        a[key] = choices[int(rng.integers(0, len(choices)))]
    else:  # non_utf8: names that are bytes, or hold control or odd code points
        key = _pick(rng, names)
        odd = ("\udcff", "\x00", "\u202e", "é" * 3, "\ufffd", "")
        v = a[key].astype(object)
        v[int(rng.integers(0, v.size))] = odd[int(rng.integers(0, len(odd)))]
        a[key] = np.array(v.tolist(), dtype=f"U{max(len(str(x)) for x in v) or 1}") \
            if rng.integers(0, 2) else np.array([str(x).encode("utf-8", "surrogateescape")
                                                  for x in v])  # fmt: skip
    return npz_bytes(a)


# -- C3D ------------------------------------------------------------------------------------------


def _through_ezc3d(data: bytes, change) -> bytes:  # noqa: ANN001 - change(c3d) edits in place
    import ezc3d

    with tempfile.TemporaryDirectory(prefix="walk3d-fuzz-c3d-") as tmp:
        src, dst = Path(tmp) / "in.c3d", Path(tmp) / "out.c3d"
        src.write_bytes(data)
        c3d = ezc3d.c3d(str(src))
        change(c3d)
        c3d.write(str(dst))
        return dst.read_bytes()


def _labels(c3d, group: str) -> list[str]:  # noqa: ANN001
    return list(c3d["parameters"][group]["LABELS"]["value"])


def _patch_rates(data: bytes, rate: float, where: int) -> bytes:
    """The frame rate in the header (``where`` 0 or 2) and the RATE parameters (1 or 2) set to
    ``rate``, in place: the byte layout of the C3D format (little-endian floats)."""
    out = bytearray(data)
    value = struct.pack("<f", rate)
    if where in (0, 2):
        out[20:24] = value  # header words 11-12: the point frame rate
    if where in (1, 2):
        at = out.find(b"RATE", 512)
        while at > 0:
            ndim = out[at + 4 + 3]  # after the name: offset (2 bytes), type, number of dims
            start = at + 4 + 4 + ndim
            if out[at - 2] in (4, 0xFC) and out[at + 4 + 2] == 4:  # "RATE" (locked: -4), floats
                out[start : start + 4] = value
            at = out.find(b"RATE", at + 4)
    return bytes(out)


def c3d_mutation(data: bytes, kind: str, rng: np.random.Generator) -> bytes:
    """A C3D file with points and force-plate analogs, damaged by ``kind``."""
    if kind == "long_line":
        return data + junk(rng, LONG)
    if kind == "header_only":  # the header and parameters, without the data blocks
        start = struct.unpack_from("<H", data, 16)[0]
        return data[: max(start - 1, 1) * 512]
    if kind == "non_utf8":
        out = bytearray(data)
        at = out.find(b"LASI") if b"LASI" in out else int(rng.integers(512, len(out)))
        out[at : at + 2] = junk(rng, 2)
        return bytes(out)
    if kind == "zero_rate":
        rate = (0.0, -100.0, 1e-30, 1e30, np.nan, np.inf)[int(rng.integers(0, 6))]
        return _patch_rates(data, float(rate), int(rng.integers(0, 3)))
    group = "POINT" if rng.integers(0, 2) else "ANALOG"

    def change(c3d) -> None:  # noqa: ANN001
        key = "points" if group == "POINT" else "analogs"
        values = np.array(c3d["data"][key], dtype=float)
        if kind == "nonfinite":
            flat = values.reshape(-1)
            flat[rng.integers(0, flat.size, int(rng.integers(1, 50)))] = rng.choice(ODD)
            c3d["data"][key] = values
        elif kind == "swap_columns":
            i, j = (int(v) for v in rng.choice(values.shape[1], 2, replace=False))
            values[:, [i, j]] = values[:, [j, i]]
            c3d["data"][key] = values
        elif kind == "swap_labels":
            labels = _labels(c3d, group)
            i, j = (int(v) for v in rng.choice(len(labels), 2, replace=False))
            labels[i], labels[j] = labels[j], labels[i]
            c3d["parameters"][group]["LABELS"]["value"] = tuple(labels)
        elif kind == "duplicate_rows":
            c3d["data"][key] = np.concatenate([values, values], axis=-1)
            other = "analogs" if key == "points" else "points"
            o = np.array(c3d["data"][other], dtype=float)
            c3d["data"][other] = np.concatenate([o, o], axis=-1)
            del c3d["data"]["meta_points"]  # ezc3d makes it again for the new frame count

    try:
        return _through_ezc3d(data, change)
    except (RuntimeError, ValueError, IndexError) as exc:  # ezc3d refuses: damage the bytes
        return data[: len(data) // 2] + str(exc).encode()[:64]
