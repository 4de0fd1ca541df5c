"""The scene's friction curve: the law of model/friction.py, both directions and f0 at rest, checked
against F_c evaluated point by point (an independent closed form of the law's terms)."""

import math

import numpy as np
import pytest
from axisflow.acquisition.wire.params_estimate import Decision, ParamsEstimate
from axisflow.viz.scene import FRICTION_POINTS, friction_curve

V_MAX = 1.5


def _record(a1=72.0, a2=215.0, a3=180.0, a4=12.8, f0=25.0, da1=6.0, da2=-12.0) -> ParamsEstimate:
    values = (109.25, a1, a2, a3, a4, f0, da1, da2)
    return ParamsEstimate(1_700_000_000_000_000_000, "a0", 0, 0, Decision.INITIAL, "start", values=values)


def _closed_form(v: float, a1, a2, a3, a4, f0, da1, da2) -> float:
    """F_c(ẋ) of docs/parameters.md written out: each direction's Coulomb and viscous friction."""
    if v > 0:
        return f0 + (a1 + da1) + (a2 + da2) * v + a3 * math.atan(a4 * v)
    if v < 0:
        return f0 - (a1 - da1) + (a2 - da2) * v + a3 * math.atan(a4 * v)
    return f0


def test_the_curve_draws_both_directions_and_the_force_at_rest():
    terms = {"a1": 72.0, "a2": 215.0, "a3": 180.0, "a4": 12.8, "f0": 25.0, "da1": 6.0, "da2": -12.0}
    curve = friction_curve(_record(**terms), V_MAX)
    assert curve.shape == (2 * FRICTION_POINTS + 1, 2)
    speeds, force = curve[:, 0], curve[:, 1]
    assert speeds[0] == -V_MAX and speeds[-1] == V_MAX and np.all(np.diff(speeds) >= 0.0)
    middle = FRICTION_POINTS
    assert speeds[middle - 1 : middle + 2].tolist() == [0.0, 0.0, 0.0]  # the step through rest
    assert force[middle] == 25.0  # f0: the force at rest
    assert force[middle - 1] == pytest.approx(25.0 - (72.0 - 6.0))  # the limit moving towards −x
    assert force[middle + 1] == pytest.approx(25.0 + (72.0 + 6.0))  # the limit moving towards +x
    moving = np.flatnonzero(speeds != 0.0)
    expected = [_closed_form(speeds[i], **terms) for i in moving]
    assert force[moving] == pytest.approx(expected, rel=1e-12, abs=1e-9)


def test_a_record_of_the_papers_shape_draws_a_symmetric_curve_through_zero():
    curve = friction_curve(_record(f0=0.0, da1=0.0, da2=0.0), V_MAX)
    assert curve[FRICTION_POINTS, 1] == 0.0
    assert curve[::-1, 1] == pytest.approx(-curve[:, 1], abs=1e-9)  # odd: F_c(−ẋ) = −F_c(ẋ)
