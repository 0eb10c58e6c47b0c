"""File readers and writers of walk3d: OpenSim storages and ExternalLoads, TRC, C3D (raw, and as
a walking trial in walk3d's ground frame), cycle tables, calibration files and result tables.

Gait-event detection and cycle normalisation for measured data live in :mod:`walk3d.io.events`.
Every malformed or truncated file raises :class:`~walk3d.io.errors.DataFileError`.
"""

from walk3d.io.c3d import AnalogData, C3dData, ForcePlatform, PointData, read_c3d
from walk3d.io.c3d_trial import C3dTrial, read_c3d_trial
from walk3d.io.calibration import read_calibration, write_calibration
from walk3d.io.cycle_table import CycleTable, read_cycle_table
from walk3d.io.errors import DataFileError
from walk3d.io.events import (
    FootEvents,
    detect_contacts,
    detect_foot_events,
    mean_sd,
    normalize_cycles,
    percent_axis,
    stride_periods,
)
from walk3d.io.external_loads import (
    ExternalForceSpec,
    FootLoads,
    PlateColumns,
    PlateLoad,
    combine_loads,
    extract_foot_loads,
    find_plates,
    read_external_loads_xml,
    write_external_loads_xml,
    write_grf_storage,
)
from walk3d.io.storage import Storage, read_storage, write_storage
from walk3d.io.tables import write_csv_table
from walk3d.io.trc import TrcData, read_trc

__all__ = [
    "AnalogData",
    "C3dData",
    "C3dTrial",
    "ForcePlatform",
    "PointData",
    "read_c3d",
    "read_c3d_trial",
    "read_calibration",
    "write_calibration",
    "write_csv_table",
    "CycleTable",
    "DataFileError",
    "ExternalForceSpec",
    "FootEvents",
    "FootLoads",
    "PlateColumns",
    "PlateLoad",
    "Storage",
    "TrcData",
    "combine_loads",
    "detect_contacts",
    "detect_foot_events",
    "extract_foot_loads",
    "find_plates",
    "mean_sd",
    "normalize_cycles",
    "percent_axis",
    "read_cycle_table",
    "read_external_loads_xml",
    "read_storage",
    "read_trc",
    "stride_periods",
    "write_external_loads_xml",
    "write_grf_storage",
    "write_storage",
]
