"""The master's start-up against the simulated drive on a virtual bus: what it writes and reads, and
each bad input refused with one message naming the value, within 5 s."""

import time

import canopen
import pytest
from axisflow.acquisition.drives.canopen.config import CanSettings
from axisflow.acquisition.drives.canopen.network import open_bus
from axisflow.acquisition.drives.canopen.objects import TORQUE_OFFSET, drive_dictionary
from axisflow.acquisition.drives.canopen.sim_drive import FaultPlan
from axisflow.acquisition.errors import DriveConfigError, DriveError
from canopen.objectdictionary import UNSIGNED16, UNSIGNED32, ObjectDictionary, ODVariable

BAD_INPUT_S = 5.0


def _u32(node, index, sub=0):
    return int.from_bytes(node.sdo.upload(index, sub), "little", signed=False)


def test_start_up_maps_the_pdos_sets_csp_and_enables(canbus):
    config = canbus.config()
    sim = canbus.sim(config)
    t0 = time.monotonic()
    master = canbus.master(config)
    assert time.monotonic() - t0 < BAD_INPUT_S
    (drive,) = master.drives
    info = drive.info
    assert info.device_type & 0xFFFF == 402 and info.serial == 5
    assert info.device_name == "axisflow simulated CiA 402 drive" and info.absent == ()
    assert info.rated_torque_nm == pytest.approx(sim.rated_torque_mnm / 1000)
    node = drive.node
    # the maps, read back over the bus: RPDO 1 = controlword, target, torque offset; TPDO 1 = statusword,
    # position actual, torque actual; transmission type 1; RPDO/TPDO 3 disabled
    assert [_u32(node, 0x1600, s) for s in (1, 2, 3)] == [0x60400010, 0x607A0020, 0x60B20010]
    assert [_u32(node, 0x1A00, s) for s in (1, 2, 3)] == [0x60410010, 0x60640020, 0x60770010]
    assert _u32(node, 0x1A01, 1) == 0x606C0020 and _u32(node, 0x1601, 1) == 0x60B10020
    assert node.sdo.upload(0x1800, 2) == b"\x01" and _u32(node, 0x1800, 1) == 0x40000185
    assert _u32(node, 0x1802, 1) & 0x8000_0000
    assert node.sdo.upload(0x6061, 0) == b"\x08"  # CSP
    assert int.from_bytes(node.sdo.upload(0x605A, 0), "little", signed=True) == 6  # ramp, then hold
    low, high = (int.from_bytes(node.sdo.upload(0x607D, s), "little", signed=True) for s in (1, 2))
    assert (low, high) == (drive.units.counts(0.0), drive.units.counts(canbus.params.L))
    assert sim.operational and drive.status().following
    assert node.nmt.state == "OPERATIONAL"


def _timed_refusal(error, match, call):
    t0 = time.monotonic()
    with pytest.raises(error, match=match):
        call()
    assert time.monotonic() - t0 < BAD_INPUT_S


def test_no_drive_at_the_node_id_is_named(canbus):
    config = canbus.config({"node_id": 9, "axis": "a0"})
    says = r"no answer from drive node 9 \(axis a0\) on CAN interface 'virtual'.*node id 9"
    _timed_refusal(DriveError, says, lambda: canbus.master(config))


def test_an_unknown_interface_is_named():
    _timed_refusal(DriveError, r"CAN interface 'nope' channel 'x': 'nope' is not a python-can interface",
                   lambda: open_bus(CanSettings("nope", "x")))  # fmt: skip


def test_an_interface_that_cannot_open_is_named():
    _timed_refusal(DriveError, r"CAN interface 'socketcan' channel 'nocan7' cannot be opened: .+",
                   lambda: open_bus(CanSettings("socketcan", "nocan7")))  # fmt: skip


def test_a_device_that_is_not_a_drive_is_refused(canbus):
    config = canbus.config()
    dictionary = ObjectDictionary()  # a CiA 401 I/O module: a real canopen SDO server, not a drive
    for index, dtype, value in ((0x1000, UNSIGNED32, 0x000F0191), (0x1017, UNSIGNED16, 0)):
        var = ODVariable("object", index)
        var.data_type, var.access_type, var.default = dtype, "rw", value
        dictionary.add_object(var)
    network = canopen.Network(open_bus(config.can))
    network.connect()
    canbus.stack.callback(network.disconnect)
    network.create_node(5, dictionary)
    _timed_refusal(DriveError, r"node 5 is not a CiA 402 drive: its device type 0x000F0191 names profile 401",
                   lambda: canbus.master(config))  # fmt: skip


@pytest.mark.slow
def test_a_drive_in_fault_is_refused_with_its_code_and_how_to_reset_it(canbus):
    config = canbus.config()
    canbus.sim(config, faults=FaultPlan(fault_at_s=0.0, fault_code=0x4310))
    _timed_refusal(
        DriveError,
        r"drive node 5 \(axis a0\) is in fault: 0x4310 drive temperature too high \(error register 0x09, "
        r"fault 0x0228\); remove the cause, then start the bridge with --reset-fault",
        lambda: canbus.master(config),
    )


def test_a_drive_in_fault_is_reset_when_asked(canbus):
    config = canbus.config()
    sim = canbus.sim(config, faults=FaultPlan(fault_at_s=0.0))
    master = canbus.master(config, reset_fault=True)
    assert master.drives[0].status().following and sim.node.sdo[0x603F].raw == 0


def test_an_eds_lacking_an_object_is_refused_before_the_bus_is_asked(canbus, tmp_path):
    eds = tmp_path / "drive.eds"
    canopen.export_od(drive_dictionary(5, {}, leave_out=(TORQUE_OFFSET,)), str(eds))
    config = canbus.config({"node_id": 5, "axis": "a0", "eds": str(eds)})
    says = r"drive\.eds of drive node 5 \(axis a0\) lacks what axisflow needs: 0x60B2"
    _timed_refusal(DriveConfigError, says, lambda: canbus.master(config))


def test_a_drive_with_its_eds_starts(canbus, tmp_path):
    eds = tmp_path / "drive.eds"
    canopen.export_od(drive_dictionary(5, {}), str(eds))
    config = canbus.config({"node_id": 5, "axis": "a0", "eds": str(eds)})
    canbus.sim(config)
    assert canbus.master(config).drives[0].status().following
