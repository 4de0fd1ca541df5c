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


def test_the_last_number_a_publisher_said_counts_the_tail_no_gap_shows():
    t = SequenceTracker()
    for s in (1, 2, 4, 5):
        t.add(A, s)
    for s in (1, 2, 3):
        t.add(B, s)
    assert (t.missed, t.untold) == (1, 2)
    t.said(A, 9)  # 6..9 never arrived: no message after them shows the gap
    t.said(B, 3)  # everything arrived
    t.said(A, 7)  # an older word changes nothing
    a, b = t.publishers[A], t.publishers[B]
    assert (a.gaps, a.tail, a.missed, b.tail, b.missed) == (1, 4, 5, 0, 0)
    assert (t.gaps, t.missed, t.untold) == (1, 5, 0)


def test_a_publisher_expected_at_the_join_that_got_nothing_through_owes_all_it_said_after_it():
    t = SequenceTracker()
    t.said(A, 40)  # neither received nor expected: where its due began is not known
    t.expect(B, 101)  # it had sent 100 when the receiver joined
    t.said(B, 130)
    assert A not in t.publishers
    assert (t.publishers[B].missed, t.messages, t.missed, t.untold) == (30, 0, 30, 0)


def test_the_number_a_publisher_had_at_the_join_counts_the_head_no_gap_shows():
    t = SequenceTracker()
    for s in (13, 14, 15):
        t.add(A, s)
    for s in (8, 9, 10):  # arrived from before the join (a route that was not owed yet): nothing lost
        t.add(B, s)
    t.expect(A, 11)
    t.expect(B, 10)
    assert (t.publishers[A].head, t.publishers[B].head, t.missed) == (2, 0, 2)


def test_a_lossy_stream_whose_first_and_last_were_lost_too_is_counted_whole():
    rng = np.random.default_rng(4)
    sent = np.arange(1, 20_001)
    lost = rng.random(sent.size) < 0.02
    lost[:3] = lost[-50:] = True
    t = SequenceTracker()
    for s in sent[~lost].tolist():
        t.add(A, s)
    t.expect(A, 1)
    t.said(A, int(sent[-1]))
    assert t.missed == int(lost.sum())
    assert t.messages + t.missed == sent.size
