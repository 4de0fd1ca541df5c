"""Foreign logs: other tools' files (a drive scope's CSV, Parquet, MATLAB .mat v5 and v7.3) read as
one JointState joint and written as the recorder writes its logs.

=====================  ============================================================================
module                 what
=====================  ============================================================================
:mod:`.table`          a file as named numeric columns (and scalars); :func:`read_table` by suffix
:mod:`.csv_table`      CSV as scopes export it: delimiter, decimal comma, header and units rows
:mod:`.parquet_table`  Parquet (pyarrow, loaded when used)
:mod:`.mat_table`      MATLAB v5 (scipy) and v7.3 (h5py, loaded when used)
:mod:`.column_map`     which columns are time, position, velocity, effort, and their units
:mod:`.samples`        a mapped joint in SI units with integer-ns stamps, checked
:mod:`.recording`      joints written as a JointState MCAP by the recorder's writer
:mod:`.importer`       :func:`import_logs` (``axisflow import``) and :func:`import_for_reading`
=====================  ============================================================================

Units come from :mod:`axisflow.model.units`, the one table of units. docs/identification.md
("Foreign logs") has worked examples.
"""

from .column_map import ColumnMap, Signal, parse_counts_per, parse_scale
from .errors import ForeignLogError
from .importer import (
    ImportedFile,
    ImportedLog,
    ImportResult,
    import_for_reading,
    import_logs,
    read_joint_samples,
)
from .recording import DEFAULT_TOPIC, write_joint_states
from .samples import JointSamples, joint_samples
from .table import FORMATS, SUFFIXES, CsvOptions, ForeignTable, format_of, read_table

__all__ = [
    "DEFAULT_TOPIC",
    "FORMATS",
    "SUFFIXES",
    "ColumnMap",
    "CsvOptions",
    "ForeignLogError",
    "ForeignTable",
    "ImportResult",
    "ImportedFile",
    "ImportedLog",
    "JointSamples",
    "Signal",
    "format_of",
    "import_for_reading",
    "import_logs",
    "joint_samples",
    "parse_counts_per",
    "parse_scale",
    "read_joint_samples",
    "read_table",
    "write_joint_states",
]
