"""File readers and writers of walk3d: OpenSim storages and ExternalLoads, TRC, C3D, cycle
tables, calibration files and result tables.

File formats only: a C3D file as a walking trial, gait events and cycle normalisation live in
:mod:`walk3d.trials`; the OpenSim files of a prediction in :mod:`walk3d.results.opensim`.
Every malformed or truncated file raises :class:`~walk3d.io.errors.DataFileError`.
"""

from walk3d.io.c3d import AnalogData, C3dData, ForcePlatform, PointData, read_c3d
from walk3d.io.calibration import read_calibration, write_calibration
from walk3d.io.cycle_table import CycleTable, read_cycle_table
from walk3d.io.errors import DataFileError
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
    "ForcePlatform",
    "PointData",
    "read_c3d",
    "read_calibration",
    "write_calibration",
    "write_csv_table",
    "CycleTable",
    "DataFileError",
    "ExternalForceSpec",
    "FootLoads",
    "PlateColumns",
    "PlateLoad",
    "Storage",
    "TrcData",
    "combine_loads",
    "extract_foot_loads",
    "find_plates",
    "read_cycle_table",
    "read_external_loads_xml",
    "read_storage",
    "read_trc",
    "write_external_loads_xml",
    "write_grf_storage",
    "write_storage",
]
