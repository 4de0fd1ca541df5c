"""Planner errors (all are :class:`axisflow.model.AxisflowError`)."""

from __future__ import annotations

from ..model import MoveError


class InfeasibleMoveError(MoveError):
    """No duration within the bounds keeps the move within the axis limits."""
