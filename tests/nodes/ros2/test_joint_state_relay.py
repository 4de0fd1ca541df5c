"""Decimation of the samples by drive time (the relay itself runs against real ROS 2 nodes in
test_node.py)."""

from __future__ import annotations

import itertools

import pytest

pytest.importorskip("rclpy", reason='ROS 2 is not installed (pip install "axisflow[ros2]")')

from axisflow.nodes.ros2.joint_state_relay import Decimator

T0_NS = 1_700_000_000_000_000_000
TICK_NS = 1_000_000


def kept(rate_hz, ticks: int, t0_ns: int = T0_NS) -> list[int]:
    decimator = Decimator(rate_hz)
    return [k for k in range(ticks) if decimator.keep(t0_ns + k * TICK_NS)]


def test_every_sample_without_a_rate_and_at_the_drives_rate():
    assert kept(None, 50) == list(range(50))
    assert kept(1000.0, 50) == list(range(50))


@pytest.mark.parametrize(("rate", "every"), [(100.0, 10), (250.0, 4), (1.0, 1000)])
def test_a_rate_that_divides_the_drives_keeps_one_sample_per_period_on_the_grid(rate, every):
    t0_ns = T0_NS + 3 * TICK_NS  # the first sample falls inside a period: kept, then the grid
    stamps = kept(rate, 5000, t0_ns)
    assert stamps[0] == 0
    assert [b - a for a, b in itertools.pairwise(stamps[1:])] == [every] * (len(stamps) - 2)
    assert all((t0_ns + k * TICK_NS) % round(1e9 / rate) == 0 for k in stamps[1:])


def test_a_rate_that_does_not_divide_keeps_the_rate_on_average():
    stamps = kept(300.0, 10_000)
    assert len(stamps) in (2999, 3000, 3001)
    assert {b - a for a, b in itertools.pairwise(stamps)} == {3, 4}
