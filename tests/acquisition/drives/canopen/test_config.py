"""drive.toml: the issue's eight lines load; every bad value is refused naming the key, the limit and
the unit; unknown keys by name; several drives share one SYNC."""

import pytest
from axisflow.acquisition.drives.canopen.config import Pacing, config_from_mapping, load_drive_config
from axisflow.acquisition.errors import DriveConfigError

CAN = {"interface": "socketcan", "channel": "can0", "bitrate": 1_000_000}
DRIVE = {"node_id": 5, "cycle_hz": 1000, "encoder_counts_per_rev": 131072}


def test_the_issues_eight_lines(tmp_path):
    path = tmp_path / "drive.toml"
    path.write_text(
        '[can]\ninterface = "socketcan"\nchannel = "can0"\nbitrate = 1000000\n'
        "[drive]\nnode_id = 5\ncycle_hz = 1000\nencoder_counts_per_rev = 131072\n"
    )
    config = load_drive_config(path)
    assert (config.can.interface, config.can.channel, config.can.bitrate) == ("socketcan", "can0", 1_000_000)
    (drive,) = config.drives
    assert (drive.node_id, drive.encoder_counts_per_rev, drive.axis) == (5, 131072, None)
    assert config.cycle_hz == 1000 and config.pacing is Pacing.WALL and config.ticks_per_cycle == 1
    assert config.with_axis("x1").drives[0].axis == "x1"
    assert config.bus_load() == pytest.approx(
        0.515
    )  # one axis at 1 kHz: SYNC + 4 frames, 515 bits worst case


def test_the_packaged_simulation_config_loads():
    config = load_drive_config(None)
    assert config.can.interface == "virtual" and config.pacing is Pacing.LOCKSTEP


def test_an_eds_path_is_relative_to_the_file(tmp_path):
    config = config_from_mapping({"can": CAN, "drive": {**DRIVE, "eds": "x.eds"}}, "d.toml", tmp_path)
    assert config.drives[0].eds == tmp_path / "x.eds"


def _one(**drive):
    return {"can": CAN, "drive": {**DRIVE, **drive}}


def _bus(**can):
    return {"can": {**CAN, **can}, "drive": DRIVE}


def _two(second):
    return {"can": CAN, "drive": [{**DRIVE, "axis": "a0"}, {**DRIVE, **second}]}


@pytest.mark.parametrize(
    ("data", "says"),
    [
        (_one(node_id=0), r"\[drive\] node_id = 0 must be in 1…127"),
        (_one(node_id=128), r"node_id = 128 must be in 1…127"),
        (_one(node_id=5.0), r"node_id = 5.0 must be an integer"),
        (_one(cycle_hz=300), r"cycle_hz = 300 Hz is not one of 100, 125, 200, 250, 500, 1000 Hz"),
        (_one(pacing="fast"), r"pacing = 'fast' is not one of wall, lockstep"),
        (_one(encoder_counts_per_rev=0), r"encoder_counts_per_rev = 0 counts must be in 1…"),
        (_one(direction=2), r"direction = 2 is not one of 1, -1"),
        (_one(following_error_window_m=-1.0), r"following_error_window_m = -1.0 m must be in 1e-06…1 m"),
        (_one(quick_stop_option=9), r"quick_stop_option = 9 is not one of 0, 1"),
        (
            _one(heartbeat_timeout_ms=50),
            r"heartbeat_timeout_ms = 50 ms must be longer than heartbeat_ms = 100",
        ),
        (_one(spin=1), r"unknown key\(s\) spin in \[drive\]; allowed: node_id"),
        (_bus(baud=5), r"unknown key\(s\) baud in \[can\]"),
        (_bus(bitrate=2_000_000), r"bitrate = 2000000 bit/s must be in 10000…1e\+06 bit/s"),
        ({"can": {"channel": "can0"}, "drive": DRIVE}, r"\[can\] lacks interface"),
        ({"can": CAN, "drive": {"node_id": 5}}, r"\[drive\] lacks encoder_counts_per_rev"),
        ({"can": CAN}, r"no \[drive\] section"),
        ({"can": CAN, "drive": DRIVE, "motor": {}}, r"unknown section\(s\) motor"),
        (
            _two({"node_id": 6, "axis": "a1", "cycle_hz": 500}),
            r"2 cycle_hz = 500 differs from 1000 of \[drive\] 1",
        ),
        (_two({"axis": "a1"}), r"\[drive\] 2 node_id = 5 is also \[drive\] 1's"),
        (_two({"node_id": 6}), r"\[drive\] 2 lacks axis"),
        (
            {"can": CAN, "drive": [{**DRIVE, "node_id": n, "axis": f"a{n}"} for n in (1, 2, 3)]},
            r"3 drive\(s\) at cycle_hz = 1000 Hz need 1.44 Mbit/s in the worst case, more than the "
            r"bitrate of 1 Mbit/s: lower cycle_hz to 500 Hz",
        ),
    ],
)
def test_bad_configurations_are_refused_naming_the_value(data, says):
    with pytest.raises(DriveConfigError, match=says):
        config_from_mapping(data, "drive.toml")


def test_several_drives_share_the_bus_settings():
    config = config_from_mapping(
        {
            "can": CAN,
            "drive": [
                {**DRIVE, "axis": "a0", "cycle_hz": 250},
                {"node_id": 6, "axis": "a1", "encoder_counts_per_rev": 4096},  # takes the bus's 250 Hz
            ],
        }
    )
    assert [d.axis for d in config.drives] == ["a0", "a1"] and config.cycle_hz == 250
    assert config.ticks_per_cycle == 4
    assert config.with_axis("zz") is config  # several drives keep their own names
