"""Proofs of a case-2 optimum from convexity: the tangent bound and the certificate of a bracket.

J(T) is convex in T (:mod:`.energy`), so J lies above each of its tangents. Given durations a ≤ b
with slopes g_a = dJ/dT(a) ≤ 0 ≤ g_b = dJ/dT(b), the minimiser lies in [a, b] and

    min J ≥ max over T ∈ [a, b] of min(tangent at a, tangent at b) = the value where they cross,

a lower bound from two exact evaluations. ``gap_j`` = J(returned) − that bound.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from ..certificates import TimeEnergyCertificate


def tangent_lower_bound(a: float, b: float, ja: float, jb: float, ga: float, gb: float) -> float:
    """A lower bound on min J over [a, b] for a convex J with slopes ga ≤ 0 ≤ gb at the ends: the
    crossing of the tangents at a and b."""
    if a == b:
        return ja
    if gb > ga:
        t_x = (jb - ja + ga * a - gb * b) / (ga - gb)
        return ja + ga * (t_x - a)
    return min(ja, jb)


def bracket_certificate(
    value_and_slope: Callable[[float], tuple[float, float]], t: float, j: float, slope: float
) -> TimeEnergyCertificate:
    """Certificate of an interior optimum t of a convex J (``value_and_slope(x)`` = (J, dJ/dT) at x,
    ``j`` = J(t), ``slope`` = dJ/dT(t)): durations a < t < b with dJ/dT(a) ≤ 0 ≤ dJ/dT(b), widened
    from 3e-11·t until they bracket, and the gap of J(t) to the tangent bound."""
    for rel in (3e-11, 1e-9, 1e-7, 1e-5, 1e-4):
        a, b = t * (1.0 - rel), t * (1.0 + rel)
        (ja, ga), (jb, gb) = value_and_slope(a), value_and_slope(b)
        if ga <= 0.0 <= gb:
            lb = tangent_lower_bound(a, b, ja, jb, ga, gb)
            return TimeEnergyCertificate(gap_j=max(j - lb, 0.0), dJ_dT=slope, t_lower_s=a, t_upper_s=b)
    return TimeEnergyCertificate(gap_j=math.nan, dJ_dT=slope)  # pragma: no cover - J flat to 1e-4·T
