"""The errors of :mod:`axisflow.deploy.security`: one root, and the bad-argument kind (a ``ValueError``)."""

from __future__ import annotations

from ...model import AxisflowError


class SecurityError(AxisflowError):
    """Root of the errors of :mod:`axisflow.deploy.security`."""


class SecurityArgumentError(SecurityError, ValueError):
    """A role name, validity, host or port given to ``security init`` or ``security add`` is invalid."""
