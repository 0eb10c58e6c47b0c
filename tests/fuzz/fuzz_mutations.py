"""Deterministic mutations of walk3d's input files, for the fuzz set (``-m fuzz``).

:func:`mutate` damages a valid file's bytes in one named way (:data:`KINDS` per format), drawn
from a NumPy generator seeded by the case's name, so that a failing case comes back the same.
Text tables (.mot, .sto, .csv, .trc), JSON, TOML, XML, NumPy archives and C3D files each have
their own mutations: truncated, bytes flipped, NaN/inf/1e308 numbers, a column scaled or the
time in another unit, columns or labels swapped, empty, header only, repeated or reversed rows,
non-UTF-8 bytes and a very long line.
"""

from __future__ import annotations

import contextlib
import json
import re
import zlib
from collections.abc import Callable

import numpy as np

ODD_NUMBERS = ("nan", "NaN", "inf", "-inf", "Infinity", "1e999", "1e308", "-1e308", "1e30",
               "-1e30", "0", "1e-320")  # fmt: skip
"""What a number is replaced by: not finite (1e999 overflows when read) or finite extremes."""
SCALES = (1e3, 1e-3, -1.0, 0.0, 1e6, 1e-9)
"""Factors of a scaled column: units mixed up (mm for m, ms for s), a sign, a dead channel."""
TIME_SCALES = (1e3, 1e-3, 1e6, 1e-6, 1e-9, 60.0)
"""Factors of a scaled time column: ms, ks, µs or minutes for seconds, and worse."""
NUMBER = re.compile(rb"(?<![\w.])-?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?(?![\w.])")
LONG = 3_000_000
"""Bytes of the very long line."""

COMMON = ("truncate", "flip", "empty", "non_utf8", "long_line")
KINDS: dict[str, tuple[str, ...]] = {
    "table": (*COMMON, "nonfinite", "swap_columns", "swap_labels", "header_only",
              "duplicate_rows", "reverse_rows", "time_constant", "ragged", "scale_column",
              "time_scale"),
    "json": (*COMMON, "nonfinite", "retype", "delete_key", "swap_values", "header_only",
             "deep"),
    "toml": (*COMMON, "nonfinite", "retype", "swap_values", "swap_labels", "header_only",
             "duplicate_rows"),
    "xml": (*COMMON, "nonfinite", "swap_labels", "header_only", "duplicate_rows", "ragged"),
    "npz": ("truncate", "flip", "empty", "nonfinite", "swap_columns", "swap_labels",
            "header_only", "duplicate_rows", "reverse_rows", "time_constant", "retype",
            "reshape", "non_utf8"),
    "c3d": ("truncate", "flip", "empty", "long_line", "nonfinite", "swap_columns",
            "swap_labels", "header_only", "duplicate_rows", "non_utf8", "zero_rate"),
}  # fmt: skip
"""The mutations of each format, in the order the cases cycle through them."""


def case_rng(name: str) -> np.random.Generator:
    """The generator of the case ``name``: the same draws on every run and machine."""
    return np.random.default_rng(zlib.crc32(name.encode()))


def mutate(data: bytes, fmt: str, kind: str, rng: np.random.Generator) -> bytes:
    """``data`` (a valid file of format ``fmt``) damaged by the mutation ``kind``."""
    if kind not in KINDS[fmt]:
        raise ValueError(f"no mutation {kind!r} for {fmt}")
    if kind == "empty":
        return b""
    if kind == "truncate":
        return data[: int(rng.integers(0, max(len(data), 1)))]
    if kind == "flip":
        return flip(data, rng, 3072 if fmt == "c3d" and rng.integers(0, 2) else None)
    if fmt in ("npz", "c3d"):
        from fuzz_binary import c3d_mutation, npz_mutation

        return (npz_mutation if fmt == "npz" else c3d_mutation)(data, kind, rng)
    return _MUTATORS[fmt](data, kind, rng)


def flip(data: bytes, rng: np.random.Generator, region: int | None = None) -> bytes:
    """``data`` with one bit flipped in each of 1-8 bytes (in the first ``region`` bytes)."""
    out = bytearray(data)
    if not out:
        return b"\x00"
    end = min(region or len(out), len(out))
    for _ in range(int(rng.integers(1, 9))):
        out[int(rng.integers(0, end))] ^= 1 << int(rng.integers(0, 8))
    return bytes(out)


def junk(rng: np.random.Generator, n: int) -> bytes:
    """``n`` bytes of 0x80-0xFF: never valid UTF-8 alone."""
    return bytes(rng.integers(0x80, 0x100, n, dtype=np.uint8))


def _insert(data: bytes, at: int, piece: bytes) -> bytes:
    return data[:at] + piece + data[at:]


def _non_utf8(data: bytes, rng: np.random.Generator) -> bytes:
    for _ in range(int(rng.integers(1, 4))):
        data = _insert(data, int(rng.integers(0, len(data) + 1)), junk(rng, 3))
    return data


def _long_line(data: bytes, rng: np.random.Generator) -> bytes:
    lines = data.split(b"\n")
    piece = (b"1.5\t" * (LONG // 4)) if rng.integers(0, 2) else b"x" * LONG
    lines.insert(int(rng.integers(0, len(lines) + 1)), piece)
    return b"\n".join(lines)


def _numbers(data: bytes, rng: np.random.Generator, start: int = 0) -> bytes:
    """Up to five numbers after byte ``start`` replaced by :data:`ODD_NUMBERS`."""
    spans = [m.span() for m in NUMBER.finditer(data, start)]
    if not spans:
        return data + b"\nnan"
    picks = sorted(rng.choice(len(spans), min(len(spans), int(rng.integers(1, 6))), False))
    out = bytearray(data)
    for i in reversed(picks):
        a, b = spans[i]
        out[a:b] = ODD_NUMBERS[int(rng.integers(0, len(ODD_NUMBERS)))].encode()
    return bytes(out)


# -- text tables: .mot, .sto, .csv, .trc ----------------------------------------------------------


def _cells(line: bytes) -> tuple[list[bytes], bytes]:
    sep = b"," if b"," in line else b"\t"
    return line.split(sep), sep


def _is_row(line: bytes) -> bool:
    cells, _ = _cells(line.strip())
    if len(cells) < 2:
        return False
    try:
        [float(c) for c in cells if c.strip()]
    except ValueError:
        return False
    return True


def _layout(lines: list[bytes]) -> tuple[int, int]:
    """(label line, first data line) of a table: data are numeric rows and labels precede
    them; in a table of words and numbers (``tracking.csv``), labels come first."""
    first = next((i for i, ln in enumerate(lines) if _is_row(ln)), None)
    if first is None:
        return 0, 1
    label = next((i for i in range(first - 1, -1, -1) if lines[i].strip()), 0)
    return label, first


def _swap_cells(line: bytes, i: int, j: int) -> bytes:
    cells, sep = _cells(line)
    if max(i, j) < len(cells):
        cells[i], cells[j] = cells[j], cells[i]
    return sep.join(cells)


def _table(data: bytes, kind: str, rng: np.random.Generator) -> bytes:
    if kind == "non_utf8":
        return _non_utf8(data, rng)
    if kind == "long_line":
        return _long_line(data, rng)
    lines = data.split(b"\n")
    label, first = _layout(lines)
    rows = [i for i in range(first, len(lines)) if lines[i].strip()]
    width = len(_cells(lines[label])[0])
    if kind == "header_only" or not rows:
        return b"\n".join(lines[: label + 1]) + b"\n"
    if kind == "nonfinite":
        if rng.integers(0, 2):  # a dead channel: one whole column
            col, odd = int(rng.integers(0, width)), rng.choice(ODD_NUMBERS).encode()
            for r in rows:
                cells, sep = _cells(lines[r])
                if col < len(cells):
                    cells[col] = odd
                lines[r] = sep.join(cells)
            return b"\n".join(lines)
        return _numbers(data, rng, sum(len(ln) + 1 for ln in lines[:first]))
    if kind in ("swap_columns", "swap_labels"):
        i, j = (int(v) for v in rng.choice(max(width, 2), 2, replace=False))
        for r in rows if kind == "swap_columns" else [label]:
            lines[r] = _swap_cells(lines[r], i, j)
        return b"\n".join(lines)
    a = int(rng.integers(0, len(rows)))
    b = min(len(rows), a + int(rng.integers(2, 40)))
    block = [lines[r] for r in rows[a:b]]
    if kind == "duplicate_rows":  # the row count in the header follows, if there is one
        at = rows[b - 1] + 1
        lines[at:at] = block
        lines = [re.sub(rb"^nRows=\d+", b"nRows=%d" % (len(rows) + len(block)), ln)
                 for ln in lines]  # fmt: skip
    elif kind == "reverse_rows":
        for r, line in zip(rows[a:b], reversed(block), strict=True):
            lines[r] = line
    elif kind in ("scale_column", "time_scale"):  # column 0 is the time
        col = 0 if kind == "time_scale" else int(rng.integers(1, max(width, 2)))
        factor = float(rng.choice(TIME_SCALES if kind == "time_scale" else SCALES))
        for r in rows:
            cells, sep = _cells(lines[r])
            with contextlib.suppress(ValueError, IndexError):
                cells[col] = repr(float(cells[col]) * factor).encode()
            lines[r] = sep.join(cells)
    elif kind == "time_constant":
        value = b"0" if rng.integers(0, 2) else _cells(lines[rows[0]])[0][0]
        for r in rows:
            cells, sep = _cells(lines[r])
            lines[r] = sep.join([value, *cells[1:]])
    else:  # ragged: rows that lose their last cells
        for r in rows[a:b]:
            cells, sep = _cells(lines[r])
            lines[r] = sep.join(cells[: int(rng.integers(0, len(cells)))])
    return b"\n".join(lines)


# -- JSON ----------------------------------------------------------------------------------------

ODD_VALUES = (float("nan"), float("inf"), -float("inf"), 1e308, -1.0, 0, True, None, "", "x",
              [], {}, [1, 2], {"a": 1}, 10**400, "nan")  # fmt: skip


def _paths(node, prefix=()) -> list[tuple]:
    """Every path (tuple of keys and indices) to a value inside ``node``."""
    out = []
    items = node.items() if isinstance(node, dict) else enumerate(node) \
        if isinstance(node, list) else ()  # fmt: skip
    for key, value in items:
        out.append((*prefix, key))
        out.extend(_paths(value, (*prefix, key)))
    return out


def _at(doc, path: tuple):
    for key in path:
        doc = doc[key]
    return doc


def _json(data: bytes, kind: str, rng: np.random.Generator) -> bytes:
    if kind == "non_utf8":
        return _non_utf8(data, rng)
    if kind == "header_only":
        return b"{}"
    if kind == "deep":
        n = int(rng.integers(2_000, 200_000))
        return b'{"a": ' + b"[" * n + b"]" * n + b"}"
    if kind == "long_line":
        doc = json.loads(data)
        doc["z" * 40] = "x" * LONG
        return json.dumps(doc).encode()
    doc = json.loads(data)
    paths = _paths(doc)
    if not paths:
        return data
    if kind == "nonfinite":
        numeric = [p for p in paths if isinstance(_at(doc, p), int | float)] or paths
        for i in rng.choice(len(numeric), min(len(numeric), int(rng.integers(1, 4))), False):
            path = numeric[int(i)]
            _at(doc, path[:-1])[path[-1]] = float(rng.choice([np.nan, np.inf, -np.inf, 1e308]))
    elif kind == "retype":
        for _ in range(int(rng.integers(1, 4))):
            path = paths[int(rng.integers(0, len(paths)))]
            parent = _at(doc, path[:-1])
            if isinstance(parent, dict) or path[-1] < len(parent):
                parent[path[-1]] = ODD_VALUES[int(rng.integers(0, len(ODD_VALUES)))]
            paths = _paths(doc) or [()]
            if paths == [()]:
                break
    elif kind == "delete_key":
        keyed = [p for p in paths if isinstance(_at(doc, p[:-1]), dict)]
        for i in rng.choice(len(keyed), min(len(keyed), int(rng.integers(1, 3))), False):
            parent = _at(doc, keyed[int(i)][:-1]) if _exists(doc, keyed[int(i)]) else None
            if parent is not None:
                del parent[keyed[int(i)][-1]]
    else:  # swap_values: two values anywhere in the document trade places
        i, j = (int(v) for v in rng.choice(len(paths), 2, replace=len(paths) < 2))
        a, b = paths[i], paths[j]
        if a[: len(b)] != b and b[: len(a)] != a:
            va, vb = _at(doc, a), _at(doc, b)
            _at(doc, a[:-1])[a[-1]], _at(doc, b[:-1])[b[-1]] = vb, va
    return json.dumps(doc).encode()


def _exists(doc, path: tuple) -> bool:
    try:
        _at(doc, path)
    except (KeyError, IndexError, TypeError):
        return False
    return True


# -- TOML and XML (text) ---------------------------------------------------------------------


def _toml(data: bytes, kind: str, rng: np.random.Generator) -> bytes:
    if kind == "non_utf8":
        return _non_utf8(data, rng)
    if kind == "long_line":
        return data + b'\nzzz = "' + b"x" * LONG + b'"\n'
    lines = data.split(b"\n")
    pairs = [i for i, ln in enumerate(lines) if b"=" in ln and not ln.lstrip().startswith(b"#")]
    if kind == "nonfinite":
        return _numbers(data, rng)
    if kind == "header_only":
        return b"\n".join(ln for ln in lines if ln.strip().startswith(b"[")) + b"\n"
    if not pairs:
        return data
    i, j = (int(v) for v in rng.choice(pairs, 2, replace=len(pairs) < 2))
    (ka, va), (kb, vb) = lines[i].split(b"=", 1), lines[j].split(b"=", 1)
    if kind == "swap_values":
        lines[i], lines[j] = ka + b"=" + vb, kb + b"=" + va
    elif kind == "swap_labels":
        lines[i], lines[j] = kb + b"=" + va, ka + b"=" + vb
    elif kind == "retype":
        odd = (b'"x"', b"[]", b"true", b"{}", b"1979-05-27", b"[[1], 2]", b"-0", b'""')
        lines[i] = ka + b"= " + odd[int(rng.integers(0, len(odd)))]
    else:  # duplicate_rows: a key given twice
        lines.insert(i + 1, lines[i])
    return b"\n".join(lines)


def _xml(data: bytes, kind: str, rng: np.random.Generator) -> bytes:
    if kind == "non_utf8":
        return _non_utf8(data, rng)
    if kind == "long_line":
        return _long_line(data, rng)
    if kind == "nonfinite":
        return _numbers(data, rng)
    lines = data.split(b"\n")
    if kind == "header_only":
        return lines[0] + b"\n"
    i = int(rng.integers(0, len(lines)))
    if kind == "duplicate_rows":
        lines[i:i] = lines[i : i + int(rng.integers(1, 6))]
    elif kind == "ragged":  # lines lost
        del lines[i : i + int(rng.integers(1, 4))]
    else:  # swap_labels: two elements' texts trade places
        texts = [m for m in re.finditer(rb">([^<>\n]+)</", data)]
        if len(texts) < 2:
            return data
        a, b = sorted(int(v) for v in rng.choice(len(texts), 2, replace=False))
        ta, tb = texts[a], texts[b]
        return (data[: ta.start(1)] + tb.group(1) + data[ta.end(1) : tb.start(1)] + ta.group(1)
                + data[tb.end(1) :])  # fmt: skip
    return b"\n".join(lines)


_MUTATORS: dict[str, Callable[[bytes, str, np.random.Generator], bytes]] = {
    "table": _table,
    "json": _json,
    "toml": _toml,
    "xml": _xml,
}
