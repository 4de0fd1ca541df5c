"""Fault 4: malformed, truncated, oversized and random payloads on the trajectory key.

The catalogue is checked here against the bridge's own decoder and validation (fast); the slow test
sends it, and a thousand generated payloads per sender, to a bridge process at 1× real time."""

import pytest
from axisflow.acquisition.bridge.move_queue import validate_move
from axisflow.acquisition.errors import AcquisitionError
from axisflow.acquisition.wire.messages import MoveCommand
from axisflow.benchmarks.fault_scenarios.bad_payloads import bad_payloads
from axisflow.benchmarks.fault_scenarios.payloads import PayloadCatalog
from axisflow.model import default_params

P = default_params()


def _verdict(data: bytes) -> str:
    try:
        validate_move(MoveCommand.decode(data), P, "a0")
    except AcquisitionError as exc:
        return str(exc)
    return "runs"


def test_every_catalogued_payload_breaks_the_rule_it_names():
    catalog = PayloadCatalog(P, hold_m=0.0, seed=1)
    named = catalog.named(oversized=False)
    assert len(named) >= 30 and len({p.name for p in named}) == len(named)
    queue_level = {"timed start in 1970", "start 0.4 m from the axis"}  # valid moves the queue refuses
    for p in named:
        verdict = _verdict(p.data)
        if p.name in queue_level:
            assert verdict == "runs" and MoveCommand.decode(p.data).move_id == p.move_id
        else:
            assert p.reason in verdict, (p.name, verdict)


def test_generated_payloads_are_seeded_and_none_could_run():
    a = PayloadCatalog(P, hold_m=0.0, seed=7).generated(300)
    b = PayloadCatalog(P, hold_m=0.0, seed=7).generated(300)
    assert [p.data for p in a] == [p.data for p in b]
    assert {p.kind for p in a} == {"random", "truncated", "flipped"}
    catalog = PayloadCatalog(P, hold_m=0.0)
    assert not any(catalog.could_run(p.data) for p in a)
    assert catalog.could_run(catalog.move().encode())  # the check itself sees a good move


@pytest.mark.slow
@pytest.mark.heavy
def test_a_bridge_rejects_every_bad_payload_with_a_reason_and_records_every_tick(tmp_path):
    r = bad_payloads(tmp_path, per_sender=1000, oversized=True)
    report = r.end.report
    assert r.sent["live sender"] >= 1000 and r.sent["no sender token"] >= 1000
    assert r.largest_payload_mb > 100
    # every payload answered by one REJECTED status with a reason, from every kind of sender
    assert r.rejected == r.sent
    assert r.other_statuses == 0 and r.without_reason == 0
    assert r.wrong_reason == []  # each catalogued move rejected for what it breaks
    assert report["moves_rejected"] == r.total and report["moves_accepted"] == 0
    # no crash, and no tick missing: every tick the bridge ran is in the file, 1 ms apart, no gap
    assert r.end.bridge.returncode == 0, r.end.bridge.stderr[-2000:]
    assert r.end.telemetry_intact
    assert abs(report["wall_time_s"] - report["ticks"] / 1000) < 0.25  # it kept 1 kHz: the schedule held
    # timing, on a shared machine, as a coarse net (test_tick_bounds.py beside this one checks the
    # per-tick bounds exactly): a quiet run shows a few late ticks and ~5 ms stalls; without the
    # bounds, 1000 rejections in one tick stalled the loop 35–650 ms
    fuzz = r.stalls["fuzz"]
    assert fuzz.late <= 0.2 * fuzz.ticks and fuzz.max_ms < 50.0, fuzz
    # a legal-size 64 MB move is copied out of Zenoh holding the interpreter lock (~35 ms) and
    # validated for ~1 s beside the loop; the 128 MB one is refused before the copy. Measured: 55–92 ms
    # on a quiet machine, 449 ms once in a CI run (docs/trust.md): the net is that the loop never hangs
    assert r.stalls["oversized"].max_ms < 1000.0, r.stalls["oversized"]
