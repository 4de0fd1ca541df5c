"""``axisflow drive-sim`` and ``axisflow bridge --drive-config`` as two processes on a udp_multicast CAN
bus, as users run them, with this test's Zenoh peer sending moves: a move, an injected fault, its reset,
a clean stop of both.

udp_multicast sends its packets out of the default network interface: the whole run (both processes
and the Zenoh peers) happens inside a private network namespace that has only loopback (``unshare -n``,
multicast routed to ``lo``). The outer test re-runs this file's inner test there; where no namespace can
be made (not root, no unshare) it is skipped with the reason.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from axisflow.deploy import private_network

CONFIG = """[can]
interface = "udp_multicast"
channel = "239.74.163.2"

[drive]
node_id = 5
cycle_hz = 1000
encoder_counts_per_rev = 131072
pacing = "lockstep"
# two Python processes on a machine others load too: a lock-step wait may last; only a dead drive counts
pdo_timeout_ms = 2000
heartbeat_timeout_ms = 2000
"""


@pytest.mark.slow
def test_drive_sim_and_bridge_as_processes_in_a_private_network_namespace(tmp_path):
    if private_network.inside():
        pytest.skip("this is the namespace's own run")
    why_not = private_network.unavailable()
    if why_not is not None:
        pytest.skip(f"no private network namespace here ({why_not})")
    inner = f"{Path(__file__)}::test_inside_the_namespace"
    command = private_network.command(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-x", inner]
    )
    env = {**os.environ, private_network.INSIDE_ENV: "1", "CI": "1", "RUST_LOG": "error"}
    run = subprocess.run(command, capture_output=True, text=True, env=env, timeout=300, cwd=tmp_path)
    assert run.returncode == 0 and "1 passed" in run.stdout, run.stdout[-4000:] + run.stderr[-2000:]


@pytest.mark.skipif(not private_network.inside(), reason="runs inside the namespace the test above makes")
def test_inside_the_namespace(tmp_path, cli, port):
    import zenoh
    from axisflow.acquisition import AxisKeys, MoveSender, MoveState, MoveStatus
    from axisflow.acquisition.bus.axis_state import AxisState
    from axisflow.acquisition.bus.session import ZenohOptions, open_session

    assert private_network.interfaces() == ["lo"]  # nowhere else to go
    config = tmp_path / "drive.toml"
    config.write_text(CONFIG)
    drive = cli.start("drive-sim", "--drive-config", str(config), "--fault-at", "4:4310")
    bridge = cli.start("bridge", "--drive-config", str(config), "--listen", f"tcp/127.0.0.1:{port}", "--json")
    keys = AxisKeys("a0")
    # the bridge's start-up (imports, the drive's SDO start-up) may take a while on a loaded machine
    options = ZenohOptions(mode="peer", connect=(f"tcp/127.0.0.1:{port}",), connect_wait_s=60.0)
    with open_session(options) as session, MoveSender(session, keys) as sender:
        events = session.declare_subscriber(keys.event, zenoh.handlers.FifoChannel(10_000))
        assert sender.wait_for_bridge(30.0), "no bridge"
        move = sender.send(0.0, 0.3, 0.8)
        done = sender.wait_status(move.move_id, {MoveState.COMPLETED}, 30.0)
        assert done is not None and done.state is MoveState.COMPLETED, sender.statuses
        fault = None  # the drive faults at 4 s of its time: the bridge says so on the event key ...
        for sample in events:
            status = MoveStatus.decode(sample.payload.to_bytes())
            if status.state is MoveState.FAULT:
                fault = status
                break
        assert fault is not None and fault.error_code == 0x4310 and "drive temperature too high" in fault.text
        with AxisState(session, keys) as state:
            here = state.wait(10.0).position_m
        refused = sender.send(here, 0.1, 0.8)  # ... refuses moves ...
        answer = sender.wait_status(refused.move_id, {MoveState.REJECTED}, 10.0)
        assert answer is not None and answer.state is MoveState.REJECTED and "--reset-fault" in answer.text
        # ... until the fault is reset through the bridge, by another process
        reset = cli.run("stop", "--axis", "a0", "--reset-fault", "--connect", f"tcp/127.0.0.1:{port}")
        assert reset.returncode == 0 and "fault reset; operation enabled" in reset.stdout, reset.stderr
        with AxisState(session, keys, "setpoint") as held:
            here = held.wait(10.0).position_m
        after = sender.send(here, 0.1, 0.8)
        again = sender.wait_status(after.move_id, {MoveState.COMPLETED}, 30.0)
        assert again is not None and again.state is MoveState.COMPLETED, again
        events.undeclare()
    bridge.send_signal(signal.SIGINT)
    out, err = cli.finish(bridge, 60)
    assert bridge.returncode == 0, err
    assert '"drive_faults": 1' in out and '"moves_completed": 2' in out, out
    drive.send_signal(signal.SIGINT)
    drive_out, _ = cli.finish(drive, 30)
    assert drive.returncode == 0 and "state switch on disabled" in drive_out  # the bridge switched it off
