"""What the faults changed in the bridge, step by step (in-process bridge, real Zenoh sessions on
loopback): a burst of moves is taken a few per tick, a dropped queue's statuses go out a few per tick,
and a payload larger than any move is refused from its length."""

from axisflow.acquisition import (
    AxisKeys,
    BridgeConfig,
    MoveSender,
    MoveState,
    SimulatedAxis,
    ZenohOptions,
    load_plant,
    open_session,
)
from axisflow.acquisition.bridge.admission import MOVES_PER_TICK
from axisflow.acquisition.bridge.bridge import STATUSES_PER_TICK, Bridge
from axisflow.acquisition.bridge.move_intake import MAX_PAYLOAD_BYTES
from axisflow.benchmarks.fault_scenarios.payloads import RawSender
from axisflow.benchmarks.fault_scenarios.rig import StatusWatch
from axisflow.model import default_params

from axisflow.deploy.processes import wait_until

P = default_params()
KEYS = AxisKeys("a0")
T0 = 1_700_000_000_000_000_000


def _bridge(session) -> Bridge:
    drive = SimulatedAxis(load_plant(None, P), P, T0, axis="a0")
    return Bridge(session, drive, P, BridgeConfig(keys=KEYS, speed=0.0))


def test_a_burst_of_bad_moves_is_taken_a_few_per_tick(port):
    with (
        open_session(ZenohOptions.loopback(listen_port=port)) as session,
        _bridge(session) as bridge,
        open_session(ZenohOptions.loopback(connect_port=port)) as other,
    ):
        sender = RawSender(other, live=True)
        for _ in range(40):
            sender.put(b"\x00\x01\x00\x00 not a move")
        assert wait_until(lambda: bridge.moves_waiting == 40, 20.0)  # decoded (and refused) off the loop
        per_tick = []
        while bridge.report.moves_rejected < 40 and len(per_tick) < 100:
            before = bridge.report.moves_rejected
            bridge.step()
            per_tick.append(bridge.report.moves_rejected - before)
        sender.close()
    assert per_tick[:10] == [MOVES_PER_TICK] * 10  # before: all 40 in the first tick
    assert sum(per_tick) == 40


def test_a_dropped_queue_is_announced_a_few_statuses_per_tick(port):
    with (
        open_session(ZenohOptions.loopback(listen_port=port)) as session,
        _bridge(session) as bridge,
        open_session(ZenohOptions.loopback(connect_port=port)) as other,
    ):
        watch = StatusWatch(other, KEYS)
        with MoveSender(other, KEYS) as sender:
            assert sender.wait_for_bridge(10.0)
            x = 0.0
            for k in range(20):
                x1 = 0.3 if k % 2 == 0 else 0.31
                sender.send(x, x1, 5.0)
                x = x1
            assert wait_until(lambda: (bridge.step(), bridge.report.moves_accepted)[1] == 20, 10.0, 0.001)
            assert wait_until(lambda: watch.count(MoveState.ACCEPTED) == 20, 5.0)
        # the tick that sees the sender's token gone drops its queue (and sends the first statuses)
        assert wait_until(lambda: (bridge.step(), bridge.report.moves_dropped)[1] > 0, 10.0, 0.001)

        def dropped_so_far() -> int:  # every status the bridge sent by now (a hello round trip)
            return sum(s.state is MoveState.DROPPED for s in watch.settled())

        dropped = [dropped_so_far()]
        for _ in range(3):
            bridge.step()
            dropped.append(dropped_so_far())
        watch.close()
    assert bridge.report.moves_dropped == 19  # in one tick: all but the running move
    assert dropped == [STATUSES_PER_TICK, 2 * STATUSES_PER_TICK, 19, 19]  # before: [19, 19, 19, 19]


def test_a_payload_larger_than_any_move_is_refused_from_its_length(port):
    with (
        open_session(ZenohOptions.loopback(listen_port=port)) as session,
        _bridge(session) as bridge,
        open_session(ZenohOptions.loopback(connect_port=port)) as other,
    ):
        watch = StatusWatch(other, KEYS)
        sender = RawSender(other, live=True)
        sender.put(bytes(MAX_PAYLOAD_BYTES + 1))
        assert wait_until(lambda: (bridge.step(), watch.count(MoveState.REJECTED))[1] == 1, 20.0, 0.001)
        (status,) = watch.statuses
        sender.close()
        watch.close()
    assert f"payload of {MAX_PAYLOAD_BYTES + 1} bytes exceeds the largest move" in status.text
