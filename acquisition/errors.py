"""The exception root of acquisition.

Every user-caused acquisition error is an :class:`AcquisitionError` (itself an
:class:`axisflow.model.AxisflowError`), so the command line prints it without a traceback. A subclass
derives from a builtin only where it truly is one (a bad value: ``ValueError``); a recording error is
not an ``OSError``, so a generic ``except OSError`` never swallows it.
"""

from __future__ import annotations

import re

from ..model import AxisflowError, AxisflowWarning


class AcquisitionError(AxisflowError):
    """Root of the errors raised by :mod:`axisflow.acquisition`."""


class WireError(AcquisitionError, ValueError):
    """Bytes on the wire or on disk do not decode to the expected record (truncated, wrong type)."""


class PlantError(AcquisitionError, ValueError):
    """A plant file or simulated-axis setting is invalid (unknown key, bad value, wrong range)."""


class MoveRejectedError(AcquisitionError, ValueError):
    """A move sent to the drive was refused (outside [0, L], above the limits, discontinuous)."""


class BridgeLostError(AcquisitionError):
    """The bridge of an axis disappeared while a program waited on its moves."""


class AxisTakenError(AcquisitionError):
    """A bridge was started on an axis that another bridge already runs."""


class ZenohConfigError(AcquisitionError, ValueError):
    """The Zenoh options or configuration file are invalid."""


class ZenohConnectError(AcquisitionError):
    """A session whose configuration must connect reached no router or peer in the time allowed."""


class RecordingError(AcquisitionError):
    """An MCAP recording cannot be written, read or recovered."""


class AxisNotRecordedError(AcquisitionError, ValueError):
    """An axis asked for is not in a recording (the message lists the axes the recording holds)."""


class DamagedLogWarning(AxisflowWarning):
    """A part of a recording (a chunk) could not be read and was skipped; the message names the file,
    the chunk, its byte offset, the reason and what was lost."""


def zenoh_reason(exc: BaseException) -> str:
    """A Zenoh error as one line, without the Rust source locations it carries."""
    text = re.sub(r"\s+at /\S+\.rs:\d+\.?", "", str(exc).strip())
    return " ".join(part.strip(" |") for part in text.splitlines() if part.strip(" |"))


class DriveError(AcquisitionError):
    """A drive cannot be reached, configured, enabled or kept running (no answer at its node id, not a
    CiA 402 drive, in fault, its bus cannot be opened)."""


class DriveConfigError(DriveError, ValueError):
    """A drive configuration file is invalid (unknown key, bad value, wrong range)."""
