"""The sequence tracker: gaps, duplicates and restarts per publisher id, checked against a count made
by hand and against a stream built with known losses."""

import numpy as np
from axisflow.acquisition.wire.sequence import SequenceTracker

A, B = b"A" * 16, b"B" * 16


def test_an_unbroken_stream_counts_nothing_lost():
    t = SequenceTracker()
    assert [t.add(A, s) for s in range(1, 101)] == [0] * 100
    p = t.publishers[A]
    assert (p.first, p.last, p.messages, p.missed, p.duplicates, p.restarts) == (1, 100, 100, 0, 0, 0)
    assert (t.missed, t.duplicates, t.restarts, t.messages, len(t)) == (0, 0, 0, 100, 1)


def test_a_gap_counts_the_numbers_skipped_and_returns_them_where_it_is():
    t = SequenceTracker()
    returned = [t.add(A, s) for s in (1, 2, 3, 7, 8, 20)]
    assert returned == [0, 0, 0, 3, 0, 11]
    assert t.missed == 14 and t.publishers[A].missed == 14
    assert (t.publishers[A].first, t.publishers[A].last, t.publishers[A].messages) == (1, 20, 6)


def test_a_repeated_or_late_number_is_a_duplicate_not_a_gap():
    t = SequenceTracker()
    for s in (1, 2, 3, 3, 2, 4):
        t.add(A, s)
    assert (t.missed, t.duplicates, t.restarts) == (0, 2, 0)
    assert t.publishers[A].last == 4


def test_numbering_that_starts_again_at_one_is_a_restart_of_the_same_id():
    t = SequenceTracker()
    for s in (1, 2, 3, 4, 1, 2, 3):
        t.add(A, s)
    p = t.publishers[A]
    assert (t.restarts, t.missed, t.duplicates) == (1, 0, 0)
    assert (p.first, p.last, p.messages) == (1, 3, 7)


def test_publishers_are_tracked_apart_in_the_order_they_appeared():
    t = SequenceTracker()
    for a, b in zip(range(1, 11), range(5, 15), strict=True):  # B joined late: its first is 5, no gap
        t.add(B, b)
        t.add(A, a if a != 6 else 99)
    assert list(t.publishers) == [B, A]
    assert t.publishers[B].first == 5 and t.publishers[B].missed == 0
    # A jumped from 5 to 99 (93 skipped) and then fell back to 7..10: four duplicates
    assert (t.publishers[A].missed, t.publishers[A].duplicates) == (93, 4)


def test_a_lossy_stream_with_a_known_count_of_losses():
    rng = np.random.default_rng(3)
    sent = np.arange(1, 50_001)
    lost = rng.random(sent.size) < 0.01
    lost[0] = lost[-1] = False  # the tracker cannot see a loss before the first or after the last
    t = SequenceTracker()
    for s in sent[~lost].tolist():
        t.add(A, s)
    assert t.missed == int(lost.sum())
    assert t.publishers[A].messages == int((~lost).sum())
