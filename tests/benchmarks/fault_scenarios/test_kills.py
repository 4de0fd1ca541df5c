"""Faults 1 and 2: the recorder and the bridge SIGKILLed mid-session (real processes and files)."""

import pytest
from axisflow.benchmarks.fault_scenarios.bridge_kill import bridge_kill
from axisflow.benchmarks.fault_scenarios.recorder_kill import MAX_CRASH_LOSS_S, recorder_kill


@pytest.mark.slow
def test_a_killed_recorder_loses_at_most_a_second_and_recover_makes_a_file_every_tool_opens(tmp_path):
    r = recorder_kill(tmp_path, kill_after_s=3.0)
    assert r.bridge.returncode == 0, r.bridge.stderr
    assert r.on_disk.messages > 1000  # two seconds and more were flushed before the kill
    # counted against what the bridge published (1 sample per ms of drive time): the tail since the
    # last flush is all that is missing, and what is there has no gap
    assert 0 <= r.lost_s <= MAX_CRASH_LOSS_S, r.lost
    assert r.on_disk.every_tick
    assert r.recover.returncode == 0 and "truncated" in r.recover.stdout, r.recover.stderr
    assert r.recovered_complete
    assert r.recovered_messages == r.on_disk.messages
    assert r.rosbags_messages == r.on_disk.messages  # rosbags' AnyReader decodes every one
    assert r.rerun_rows == r.on_disk.messages  # rerun's importer: one row per sample
    assert r.passed


@pytest.mark.slow
def test_a_killed_bridge_leaves_a_complete_recording_and_its_restart_starts_where_the_axis_coasted(tmp_path):
    r = bridge_kill(tmp_path, at_fraction=0.45)
    x_kill, v_kill = r.killed_at
    assert v_kill > 1.0  # killed at speed, mid-move
    # the recorder went on and stopped cleanly: a complete file, every tick of both bridges
    assert r.recorder.returncode == 0, r.recorder.stderr
    assert r.complete and r.state.every_tick
    # nothing missing before the kill: the last sample is one tick of travel (1.5 mm) short of where
    # the plant was (the sample is read before its tick moves the plant), two if one was in flight,
    # none if the kill fell between publishing a sample and moving the plant
    assert 0.0 <= r.ticks_after_last_sample <= 2.5, r.ticks_after_last_sample
    # its summary names the restarted bridge as a second publisher, each numbered from 1
    (n1, first1, last1, _), (n2, first2, last2, _) = r.state.runs
    assert (first1, last1, first2, last2) == (1, n1, 1, n2)
    assert [(p["first_sequence"], p["last_sequence"], p["messages"]) for p in r.publishers] == [
        (1, n1, n1),
        (1, n2, n2),
    ]
    assert len({p["id"] for p in r.publishers}) == 2
    assert n2 == r.restart_ticks
    # the restart is at rest where the plant coasted to on friction from its state at the kill
    assert r.coasts_to_m > x_kill + 0.05
    assert r.restart_first[1] == 0.0
    assert abs(r.restart_offset_m) <= r.count_m  # one encoder count (1.9 µm)
    assert r.restart_span_m <= 2 * r.count_m  # and it holds there
    assert r.passed
