"""Fault 5: thousands of valid moves from one sender, four senders one after another."""

import pytest
from axisflow.benchmarks.fault_scenarios.move_flood import MAX_FLOOD_RSS_GROWTH_MB, move_flood


@pytest.mark.slow
@pytest.mark.heavy
def test_a_flood_of_valid_moves_fills_the_queue_to_its_bound_and_no_further(tmp_path):
    r = move_flood(tmp_path, moves=2000)
    first, *later = r.per_sender
    # the bound holds (the running move counts): the rest are refused, each saying why
    assert first["accepted"] == r.limit == 1024
    for s in later:
        assert s["accepted"] == r.limit - 1  # the first sender's running move is still there
    for s in r.per_sender:
        assert s["rejected"] == s["queue_full"] == s["sent"] - s["accepted"]
        # closing a sender drops its moves that had not started: all but the running one
        assert s["dropped"] == r.limit - 1
    assert r.max_queued == r.limit
    report = r.end.report
    n = len(r.per_sender)
    assert (report["moves_accepted"], report["moves_rejected"], report["moves_missed"]) == (
        1024 + 1023 * (n - 1),
        2000 * n - 1024 - 1023 * (n - 1),
        0,
    )
    # memory flat: after the first, no flood leaves more behind than the one before
    assert len(r.per_sender) == 4
    assert r.rss_growth_mb <= MAX_FLOOD_RSS_GROWTH_MB, r.rss_mb
    # telemetry unaffected: every state and setpoint sample recorded, 1 ms apart, no gap
    assert r.end.telemetry_intact
    for name, stalls in r.stalls.items():  # a coarse net on a shared machine (see test_bad_payloads.py)
        assert stalls.late <= 0.2 * stalls.ticks and stalls.max_ms < 50.0, (name, stalls)
