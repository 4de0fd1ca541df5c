"""Fault 6, beside one bridge and its recorder: a full disk, a second recorder on the same file, 30
Zenoh peers coming and going; the first recording stays complete."""

import pytest
from axisflow.benchmarks.fault_scenarios.session_faults import JOIN_LOSS_ALLOWANCE, session_faults

# a module fixture of several seconds: the whole module is in the slow tier, and bounds the bridge's stalls
pytestmark = [pytest.mark.slow, pytest.mark.heavy]


@pytest.fixture(scope="module")
def faults(tmp_path_factory):
    return session_faults(tmp_path_factory.mktemp("session-faults"), peers=30)


@pytest.mark.slow
def test_the_first_recording_is_complete_after_all_of_them(faults):
    end = faults.end
    assert end.bridge.returncode == 0 and end.recorder.returncode == 0, end.recorder.stderr
    assert end.complete and end.telemetry_intact
    assert end.summary["missed"] == 0


@pytest.mark.slow
def test_a_second_recorder_on_the_same_file_is_refused_before_it_touches_it(faults):
    ow = faults.twice["--overwrite"]
    assert ow.returncode == 2 and ow.stdout == ""
    assert ow.stderr.strip().splitlines() == [
        f"axisflow record: error: {faults.end.summary['files'][0]} is being recorded by another process: "
        "choose another name"
    ]
    assert "already exists" in faults.twice["plain"].stderr and faults.twice["plain"].returncode == 2
    before, after = faults.size_before_after
    assert after >= before  # not truncated: the first recorder kept writing
    assert faults.twice_s < 15.0


@pytest.mark.slow
def test_a_full_disk_ends_the_recording_with_one_line_and_what_was_flushed_recovers(faults):
    full = faults.full
    assert full.returncode == 2, full.stderr
    (line,) = full.stderr.strip().splitlines()
    assert f"writing {faults.full_path} failed: File too large" in line
    assert f"`axisflow recover {faults.full_path}`" in line
    assert faults.full_size <= faults.fsize_limit
    assert faults.full_recovered.returncode == 0, faults.full_recovered.stderr
    state = faults.full_state
    # the flushed chunks, every sample where its sequence number puts it; this recorder joined the
    # running bridge and may have lost a sample live (once in a CI run: 1 of 1002)
    assert state is not None and state.messages >= 500 and state.consistent
    assert state.sequence_gaps <= JOIN_LOSS_ALLOWANCE


@pytest.mark.slow
def test_peers_coming_and_going_leave_the_bridge_unmoved(faults):
    assert faults.peers_heard == faults.peers == 30  # each one really joined: it heard the bridge
    report = faults.end.report
    # thirty sender tokens came and went: nothing was queued, nothing dropped or rejected
    assert report["moves_dropped"] == report["moves_rejected"] == report["moves_accepted"] == 0
    churn = faults.stalls["churn"]
    assert churn.late <= 0.2 * churn.ticks and churn.max_ms < 50.0, churn  # a coarse net (shared machine)
