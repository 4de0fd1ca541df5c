"""The ring of samples: in place, wrap-around, restarts and repeated stamps counted."""

import numpy as np
import pytest
from axisflow.identification.online import SampleRing


def _batch(first: int, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    k = np.arange(first, first + n)
    return k * 1_000_000, k * 0.5, -k * 0.25


def test_it_keeps_the_newest_samples_in_order_across_the_wrap():
    ring = SampleRing(10)
    for first in range(0, 27, 3):  # nine batches of three: 27 samples through a ring of 10
        ring.extend(*_batch(first, 3))
    assert len(ring) == 10 and ring.received == 27
    stamps, position, effort = ring.since(0)
    assert stamps.tolist() == [k * 1_000_000 for k in range(17, 27)]
    assert position.tolist() == [k * 0.5 for k in range(17, 27)] and effort[0] == -17 * 0.25
    assert (ring.oldest_ns, ring.newest_ns) == (17_000_000, 26_000_000)
    stamps, _p, _e = ring.since(23_500_000)
    assert stamps.tolist() == [24_000_000, 25_000_000, 26_000_000]


def test_a_batch_larger_than_the_ring_keeps_its_newest():
    ring = SampleRing(4)
    ring.extend(*_batch(0, 9))
    assert ring.since(0)[0].tolist() == [5_000_000, 6_000_000, 7_000_000, 8_000_000]


def test_a_source_that_starts_again_empties_the_ring_and_repeats_are_dropped():
    ring = SampleRing(8)
    ring.extend(*_batch(10, 5))
    ring.extend(*_batch(0, 3))  # a bridge restarted: its stamps begin again
    assert ring.restarts == 1 and ring.since(0)[0].tolist() == [0, 1_000_000, 2_000_000]
    stamps, position, effort = _batch(3, 4)
    stamps[2] = stamps[1]  # a repeated stamp inside a batch
    ring.extend(stamps, position, effort)
    assert ring.dropped == 1 and ring.since(0)[0].tolist() == [k * 1_000_000 for k in (0, 1, 2, 3, 4, 6)]


def test_refusals():
    with pytest.raises(ValueError, match="ring capacity = 1 samples must be at least 2"):
        SampleRing(1)
    with pytest.raises(ValueError, match="three 1-D columns of one length"):
        SampleRing(4).extend(np.arange(3), np.zeros(2), np.zeros(3))
    empty = SampleRing(4)
    assert empty.newest_ns is None and empty.since(0)[0].size == 0
