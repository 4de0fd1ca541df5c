"""The exception root of the views and figures.

Every user-caused error of :mod:`axisflow.viz` (a log with no axis in it, an output that cannot be
written, a figure input that does not fit) is a :class:`VizError`, itself an
:class:`axisflow.model.AxisflowError`: the command line prints its one line and exits 2. It is not an
``OSError``, so a generic ``except OSError`` never swallows it.
"""

from __future__ import annotations

from ..model import AxisflowError, files


class VizError(AxisflowError):
    """Root of the errors raised by :mod:`axisflow.viz`."""


class OutputError(VizError, files.OutputError):
    """An output file (.rrd, .png) or folder cannot be written (also the base layer's
    :class:`axisflow.model.files.OutputError`, which the folder checks of :mod:`axisflow.model.files`
    raise)."""
