"""Helpers shared by the tests: finite differences (physics tests), a random decision vector, a
sample calibration and the location of the shared measured data."""

import os
from pathlib import Path

import numpy as np

FD_STEP = 1e-3


def random_decision(seed: int) -> np.ndarray:
    """A smooth random decision vector (no optimization): coefficients uniform in ±0.04 with the
    midline symmetry's zeros, half step width 0.08 m."""
    from walk3d.problem import layout

    rng = np.random.default_rng(seed)
    x = rng.uniform(-0.04, 0.04, layout.N_X)
    x[layout.fixed_zero_mask()] = 0.0
    x[layout.I_HALF_STEP] = 0.08
    return x


def fd1(f, t, h=FD_STEP):
    """Fourth-order central first derivative of f (array-valued, time first)."""
    return (-f(t + 2 * h) + 8 * f(t + h) - 8 * f(t - h) + f(t - 2 * h)) / (12 * h)


def fd2(f, t, h=FD_STEP):
    """Fourth-order central second derivative."""
    return (-f(t + 2 * h) + 16 * f(t + h) - 30 * f(t) + 16 * f(t - h) - f(t - 2 * h)) / (12 * h**2)


def assert_rel(actual, expected, rel=1e-6):
    """|actual - expected| <= rel * max|expected| (relative to the signal's scale)."""
    actual, expected = np.asarray(actual), np.asarray(expected)
    scale = max(np.max(np.abs(expected)), 1e-12)
    err = np.max(np.abs(actual - expected))
    assert err <= rel * scale, f"max error {err:.3e} > {rel:.0e} x scale {scale:.3e}"


def sample_calibration():
    """A plausible roll-over calibration (7 knots) with transfer ratios, subject and quality."""
    from walk3d.calibration.fit import Calibration
    from walk3d.contact.transition import TransitionRatios

    s = np.sin(np.radians(np.linspace(-60, 30, 7)) / 2)
    ankle = tuple((float(-0.3 * v), float(0.07 + 0.2 * v * v), float(0.01 * v)) for v in s)
    return Calibration(tuple(float(v) for v in s), ankle, (float(s[1]), float(s[-2])),
                       TransitionRatios(0.25, -0.02, 0.14, -0.01),
                       subject={"mass_kg": 62.0}, quality={"rms_m": 0.007})  # fmt: skip


def shared_data_dir() -> Path:
    """``$WALK3D_SHARED_DATA`` if set, else ``../shared/data`` beside the repository."""
    env = os.environ.get("WALK3D_SHARED_DATA")
    return Path(env) if env else Path(__file__).resolve().parents[1].parent / "shared" / "data"


def storage_with_nan(src: Path, dst: Path, column: str, rows: range) -> Path:
    """A copy of the storage ``src`` with NaN in ``column`` at the given data rows."""
    lines = src.read_text().splitlines()
    head = next(i for i, line in enumerate(lines) if line.strip().lower() == "endheader") + 1
    k = lines[head].split().index(column)
    for r in rows:
        tokens = lines[head + 1 + r].split()
        tokens[k] = "nan"
        lines[head + 1 + r] = "\t".join(tokens)
    dst.write_text("\n".join(lines) + "\n")
    return dst


def replace_result_file(folder: Path, name: str, data: bytes) -> Path:
    """Write ``data`` as ``folder/name`` and list its new size in the result folder's manifest,
    so that only the file's content, not the folder's completeness, is wrong."""
    import json

    (folder / name).write_bytes(data)
    manifest = json.loads((folder / "manifest.json").read_text(encoding="utf-8"))
    manifest["files"][name] = len(data)
    if name in manifest.get("sha256", {}):
        import hashlib

        manifest["sha256"][name] = hashlib.sha256(data).hexdigest()
    (folder / "manifest.json").write_text(json.dumps(manifest), encoding="utf-8")
    return folder / name


def cli(capsys, *args) -> tuple[int, str, str]:
    """``walk3d ARGS`` run in this process: (exit code, stdout, stderr)."""
    import pytest

    from walk3d.cli import main

    with pytest.raises(SystemExit) as info:
        main([str(a) for a in args])
    out, err = capsys.readouterr()
    return info.value.code, out, err


def one_line_error(result: tuple[int, str, str], *words: str) -> None:
    """Assert that ``result`` (from :func:`cli`) is exit 2 with one ``walk3d: error:`` line that
    names every one of ``words``, and no traceback."""
    code, _, err = result
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and lines[0].startswith("walk3d: error:"), err
    assert "Traceback" not in err and all(w in lines[0] for w in words), err
