"""The periodic extension of a one-cycle record (walk3d.verify.periodic): the neighbouring
cycles' samples continue the cycle smoothly, forward positions moved by one stride."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from walk3d.io.external_loads import read_external_loads_xml
from walk3d.io.storage import Storage, read_storage, write_storage
from walk3d.verify.periodic import extend_cycle, periodic_records

PERIOD, STRIDE = 1.1, 1.43


def _cycle(n=101) -> Storage:
    t = np.linspace(0.0, PERIOD, n)
    w = 2 * np.pi * t / PERIOD
    data = np.column_stack([np.sin(w) + 0.3 * np.cos(2 * w), STRIDE * t / PERIOD + 0.1 * np.sin(w)])
    return Storage("walk3d", t, ("angle", "pelvis_tx"), data, True)


def _smooth(t, y) -> float:
    """Largest second difference on a uniform grid (a jump or a kink shows up here)."""
    assert np.allclose(np.diff(t), t[1] - t[0])
    return float(np.max(np.abs(np.diff(y, 2))))


def test_the_extension_continues_the_cycle_smoothly():
    cyc = _cycle()
    ext = extend_cycle(cyc, ("pelvis_tx",), STRIDE, 10)
    assert ext.time.size == cyc.time.size + 20
    np.testing.assert_array_equal(ext.data[10:-10], cyc.data)
    reference = max(_smooth(cyc.time, cyc.data[:, k]) for k in range(2))
    for k in range(2):
        assert _smooth(ext.time, ext.data[:, k]) <= 1.01 * reference
    # control: without the stride the pelvis jumps back by a stride at each end
    bad = extend_cycle(cyc, (), STRIDE, 10)
    assert _smooth(bad.time, bad.data[:, 1]) > 100 * reference


def test_too_short_a_cycle_is_refused():
    with pytest.raises(ValueError, match="cannot be extended"):
        extend_cycle(_cycle(8), ("pelvis_tx",), STRIDE, 10)


def test_the_records_point_to_their_own_extended_loads(tmp_path):
    cyc = _cycle()
    motion = write_storage(tmp_path / "motion.mot", cyc.time, cyc.columns, cyc.data,
                           in_degrees=True)  # fmt: skip
    px = 0.2 + STRIDE * cyc.time / PERIOD
    write_storage(tmp_path / "grf.mot", cyc.time, ("ground_force_r_vy", "ground_force_r_px"),
                  np.column_stack([np.full_like(px, 700.0), px]), name="walk3d_grf")  # fmt: skip
    (tmp_path / "grf.xml").write_text(
        '<?xml version="1.0" encoding="UTF-8" ?>\n<OpenSimDocument Version="40000">'
        '<ExternalLoads name="externalloads"><objects /><groups />'
        "<datafile>grf.mot</datafile></ExternalLoads></OpenSimDocument>\n"
    )
    out = tmp_path / "ext"
    out.mkdir()
    m, loads = periodic_records(motion, tmp_path / "grf.xml", out, pad=5)
    _, datafile = read_external_loads_xml(loads)
    grf = read_storage(out / "grf.mot")
    assert Path(datafile).resolve() == (out / "grf.mot").resolve()
    assert read_storage(m).in_degrees and read_storage(m).time.size == grf.time.size == 111
    assert _smooth(grf.time, grf.data[:, 1]) < 1e-9  # the centre of pressure moves on
