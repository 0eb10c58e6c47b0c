"""A one-cycle record extended by samples of the neighbouring cycles, for OpenSim's check.

OpenSim's inverse dynamics differentiates splines through the sampled coordinates. At a
record's two ends the splines are free and their second derivatives are wrong, which shows as
a residual force of about 3 % body weight at the first and last samples. A predicted cycle is
periodic up to the stride (the pelvis and the centres of pressure move forward by ``V T``), so
the check runs on the cycle with ``pad`` samples of the cycle before and after it, and compares
only the cycle's own samples.
"""

from __future__ import annotations

from os import PathLike
from pathlib import Path

import numpy as np

from walk3d.io.checks import read_xml
from walk3d.io.errors import DataFileError
from walk3d.io.external_loads import read_external_loads_xml
from walk3d.io.storage import Storage, read_storage, write_storage

__all__ = ["PAD_SAMPLES", "periodic_records", "extend_cycle"]

PAD_SAMPLES = 10
"""Samples of each neighbouring cycle (10 % of a 101-sample cycle): far more than a spline's
reach, so the cycle's own samples see no free end."""


def extend_cycle(storage: Storage, forward: tuple[str, ...], stride: float, pad: int) -> Storage:
    """``storage`` (one cycle, its last sample repeating the first a period later) with ``pad``
    samples of the cycles before and after it; the ``forward`` columns move by ``∓ stride``."""
    t, data = storage.time, storage.data
    if t.size < pad + 2:
        raise ValueError(f"a cycle of {t.size} samples cannot be extended by {pad}")
    period = float(t[-1] - t[0])
    shift = np.array([stride if c in forward else 0.0 for c in storage.columns])
    before, after = data[-1 - pad : -1] - shift, data[1 : pad + 1] + shift
    return Storage(
        storage.name,
        np.concatenate([t[-1 - pad : -1] - period, t, t[1 : pad + 1] + period]),
        storage.columns,
        np.vstack([before, data, after]),
        storage.in_degrees,
    )


def periodic_records(
    motion: str | PathLike[str],
    external_loads: str | PathLike[str],
    folder: str | PathLike[str],
    pad: int = PAD_SAMPLES,
) -> tuple[Path, Path]:
    """``(motion, external loads)`` in ``folder``: copies of a prediction's ``motion.mot`` and
    ``grf.xml`` (with its data file) extended periodically (module doc)."""
    folder = Path(folder)
    mot = read_storage(motion, finite=True)
    pelvis_x = mot.column("pelvis_tx")
    stride = float(pelvis_x[-1] - pelvis_x[0])
    ext = extend_cycle(mot, ("pelvis_tx",), stride, pad)
    motion_out = write_storage(folder / "motion.mot", ext.time, ext.columns, ext.data,
                               in_degrees=bool(mot.in_degrees))  # fmt: skip
    read_external_loads_xml(external_loads)  # an ExternalLoads file, or one line
    tree = read_xml(external_loads)
    datafile = tree.getroot().find(".//datafile")
    if datafile is None or not (datafile.text or "").strip():
        raise DataFileError(external_loads, "no <datafile>")
    source = Path(datafile.text.strip())
    if not source.is_absolute():
        source = Path(external_loads).resolve().parent / source
    grf = read_storage(source, finite=True)
    x_points = tuple(c for c in grf.columns if c.endswith("_px"))
    ext = extend_cycle(grf, x_points, stride, pad)
    grf_out = write_storage(folder / "grf.mot", ext.time, ext.columns, ext.data, name=grf.name)
    datafile.text = str(grf_out.resolve())
    loads_out = folder / "grf.xml"
    tree.write(loads_out, encoding="UTF-8", xml_declaration=True)
    return motion_out, loads_out
