"""The bounds of iterative work: a deadline that passes raises a typed error naming where."""

import math

import pytest
from axisflow.model import AxisflowError
from axisflow.model.deadline import Deadline, DeadlineError, IterationCapError, SolveLimitError, iteration_cap


def test_a_passed_deadline_raises_naming_the_work_and_the_place():
    deadline = Deadline(1e-9, "the test solve")
    while not deadline.expired:  # a fact, not a sleep: the monotonic clock moves on
        pass
    with pytest.raises(
        DeadlineError, match=r"the test solve ran past its deadline of 1e-09 s \(in the loop\)"
    ):
        deadline.check("the loop")


def test_no_deadline_never_expires_and_a_bad_one_is_refused():
    forever = Deadline(math.inf)
    forever.check("anywhere")
    assert not forever.expired
    with pytest.raises(ValueError, match=r"deadline = 0\.0 s must be > 0 s"):
        Deadline(0.0)


def test_both_limits_are_axisflow_errors_under_one_root():
    cap = iteration_cap("the search", 64)
    assert isinstance(cap, IterationCapError) and isinstance(cap, SolveLimitError)
    assert issubclass(DeadlineError, SolveLimitError) and issubclass(SolveLimitError, AxisflowError)
    assert str(cap) == "the search did not converge within its cap of 64 steps"
