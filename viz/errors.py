"""The exception root of the views and figures.

Every user-caused error of :mod:`axisflow.viz` (a log with no axis in it, a figure input that does not
fit) is a :class:`VizError`, itself an :class:`axisflow.model.AxisflowError`: the command line prints
its one line and exits 2. It is not an ``OSError``, so a generic ``except OSError`` never swallows it.
An output (.rrd, .png, a folder) that cannot be written is the one error of every command that writes:
:class:`axisflow.model.files.OutputError`.
"""

from __future__ import annotations

from ..model import AxisflowError


class VizError(AxisflowError):
    """Root of the errors raised by :mod:`axisflow.viz`."""
