"""Fault 5: thousands of valid moves from one sender, four senders one after another, behind a move that
runs through them all."""

import pytest
from axisflow.benchmarks.fault_scenarios.move_flood import MAX_FLOOD_RSS_GROWTH_MB, move_flood


@pytest.mark.slow
@pytest.mark.heavy
def test_a_flood_of_valid_moves_fills_the_queue_to_its_bound_and_no_further(tmp_path):
    r = move_flood(tmp_path, moves=2000)
    # the bound holds (the running move counts): the rest are refused, each saying why
    assert r.limit == 1024
    for s in r.per_sender:
        assert s["accepted"] == r.limit - 1
        assert s["rejected"] == s["queue_full"] == s["sent"] - s["accepted"]
        # closing a sender drops its moves that had not started: every one it had queued
        assert s["dropped"] == s["accepted"]
    assert r.max_queued == r.limit
    report = r.end.report
    n = len(r.per_sender)
    assert (report["moves_accepted"], report["moves_rejected"], report["moves_missed"]) == (
        1 + 1023 * n,
        2000 * n - 1023 * n,
        0,
    )
    assert report["moves_completed"] == 0  # the move that runs through the floods ran through them
    # memory flat: after the first, no flood leaves more behind than the one before
    assert len(r.per_sender) == 4
    assert r.rss_growth_mb <= MAX_FLOOD_RSS_GROWTH_MB, r.rss_mb
    # telemetry unaffected: every state and setpoint sample recorded, 1 ms apart, no gap
    assert r.end.telemetry_intact
    for name, stalls in r.stalls.items():  # a coarse net on a shared machine (see test_bad_payloads.py)
        assert stalls.late <= 0.2 * stalls.ticks and stalls.max_ms < 50.0, (name, stalls)
