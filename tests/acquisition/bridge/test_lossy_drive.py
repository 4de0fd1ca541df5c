"""A bridge in front of the realistic plant (real Zenoh sessions on loopback): the samples its drive
loses are counted and not published, setpoints keep the drive's 1 ms grid, and the bridge says what
drives the axis (DriveInfo once a second, and in its report)."""

import threading

import numpy as np
import pytest
import zenoh
from axisflow.acquisition import AxisKeys, AxisSample, BridgeConfig, SimulatedAxis, ZenohOptions, open_session
from axisflow.acquisition import run_bridge as run
from axisflow.acquisition.drives.plant import load_profile
from axisflow.acquisition.wire.drive_info import SIMULATED, DriveInfo
from axisflow.model import default_params

PARAMS = default_params()
T0 = 1_700_000_000_000_000_000
KEYS = AxisKeys("a0")


def _drain(sub) -> list:
    out = []
    while (s := sub.try_recv()) is not None:
        out.append(s)
    return out


@pytest.mark.slow
@pytest.mark.heavy  # every sample must cross Zenoh: on two workers, a busy machine lost some in transport
def test_lost_samples_are_counted_and_the_bridge_names_its_drive(port):
    plant = load_profile("realistic", PARAMS)
    drive = SimulatedAxis(plant, PARAMS, T0, axis="a0")
    info = DriveInfo(0, "a0", SIMULATED, plant.profile, plant.source)
    # speed 0: as fast as the observer takes the samples, on blocking congestion control; at a real-time
    # speed telemetry is dropped on congestion by design (a drive never waits), and on a loaded machine
    # (20× and 5× lost a third and a twentieth of the setpoints) what the observer misses would no
    # longer be only what the drive lost
    config = BridgeConfig(keys=KEYS, speed=0.0, duration_s=5.0, wait_subscribers_s=10.0, drive=info)
    with (
        open_session(ZenohOptions.loopback(listen_port=port)) as bridge_session,
        open_session(ZenohOptions.loopback(connect_port=port)) as observer,
    ):
        states = observer.declare_subscriber(KEYS.state, zenoh.handlers.FifoChannel(20_000))
        setpoints = observer.declare_subscriber(KEYS.setpoint, zenoh.handlers.FifoChannel(20_000))
        drives = observer.declare_subscriber(KEYS.drive, zenoh.handlers.FifoChannel(100))
        result = {}
        thread = threading.Thread(
            target=lambda: result.update(report=run(bridge_session, drive, PARAMS, config))
        )
        thread.start()
        thread.join(timeout=120)
        assert not thread.is_alive()
        report = result["report"]
        received = [AxisSample.decode(s.payload.to_bytes()) for s in _drain(states)]
        commanded = [AxisSample.decode(s.payload.to_bytes()) for s in _drain(setpoints)]
        infos = [DriveInfo.decode(s.payload.to_bytes()) for s in _drain(drives)]
    assert report.ticks == 5000 and len(commanded) == 5000
    assert report.stale_ticks == 5000 - len(received) > 0  # 0.1 % of 5000: a handful
    assert np.all(np.diff([s.stamp_ns for s in commanded]) == 1_000_000)
    jitter = np.array([s.stamp_ns for s in received]) - commanded[0].stamp_ns
    assert np.max(np.abs(jitter - np.round(jitter / 1e6) * 1e6)) <= 100_000  # two stamps of ±50 µs
    assert [i.stamp_ns for i in infos] == [commanded[k].stamp_ns for k in range(0, 5000, 1000)]
    assert {(i.profile, i.source, i.axis) for i in infos} == {
        ("realistic", "packaged plant_realistic.toml", "a0")
    }
    assert report.drive == "simulated axis, plant realistic (packaged plant_realistic.toml)"
    assert report.to_dict()["stale_ticks"] == report.stale_ticks
    assert "without a new sample" in report.summary()
