"""The drive's health, cycle by cycle: which statuswords, emergencies and silences become which events
(the master side alone; the end-to-end cases run against the simulated drive in test_drive_events.py)."""

from axisflow.acquisition.drives.canopen.cia402 import (
    STATE_BITS,
    SW_FOLLOWING_ERROR,
    SW_QUICK_STOP,
    SW_WARNING,
    State,
)
from axisflow.acquisition.drives.canopen.faults import RESET_TIMEOUT_S, Condition, DriveHealth
from axisflow.acquisition.drives.drive import DriveEventKind as K

ENABLED = STATE_BITS[State.OPERATION_ENABLED] | SW_QUICK_STOP
FAULT = STATE_BITS[State.FAULT]


class Clock:
    def __init__(self):
        self.now = 0.0

    def __call__(self):
        return self.now


def _health(code=(0x1234, 0x81)):
    reads = []

    def read():
        reads.append(1)
        return code

    clock = Clock()
    health = DriveHealth("drive node 5", read, clock)
    health.request_reset()  # the start-up's enabling
    assert [e.kind for e in health.update(ENABLED, None)] == [K.ENABLED]
    return health, reads, clock


def test_a_fault_takes_the_code_of_the_emergency_that_came_with_it():
    health, reads, _ = _health()
    health.emergency(0x2310, 0x03)
    (event,) = health.update(FAULT, None)
    assert (event.kind, event.error_code, event.error_register, event.statusword) == (
        K.FAULT,
        0x2310,
        3,
        FAULT,
    )
    assert "0x2310 continuous over-current" in event.text and health.condition is Condition.STOPPED
    assert reads == []  # no SDO read needed


def test_an_emergency_a_cycle_before_the_fault_still_explains_it():
    health, reads, _ = _health()
    health.emergency(0x4310, 0x09)
    assert health.update(ENABLED, None) == []  # held one cycle: a fault may follow
    (event,) = health.update(FAULT, None)
    assert event.error_code == 0x4310 and reads == []


def test_a_fault_without_an_emergency_reads_the_drives_error_code():
    health, reads, _ = _health(code=(0x7305, 0x01))
    (event,) = health.update(FAULT, None)
    assert event.error_code == 0x7305 and reads == [1]


def test_an_emergency_no_fault_follows_is_a_warning_and_the_drive_goes_on():
    health, _, _ = _health()
    health.emergency(0x4210, 0x09)
    assert health.update(ENABLED, None) == []
    (event,) = health.update(ENABLED, None)
    assert (event.kind, event.error_code) == (K.WARNING, 0x4210) and health.condition is Condition.FOLLOWING


def test_rising_warning_and_following_error_bits_warn_once():
    health, _, _ = _health()
    kinds = [e.kind for e in health.update(ENABLED | SW_WARNING | SW_FOLLOWING_ERROR, None)]
    assert kinds == [K.WARNING, K.WARNING]
    assert health.update(ENABLED | SW_WARNING | SW_FOLLOWING_ERROR, None) == []


def test_leaving_operation_enabled_unasked_is_a_drive_stop():
    health, _, _ = _health()
    (event,) = health.update(STATE_BITS[State.QUICK_STOP_ACTIVE], None)
    assert event.kind is K.DRIVE_STOPPED and "quick stop active" in event.text


def test_comm_loss_is_reported_once_and_the_return_is_a_warning():
    health, _, _ = _health()
    (lost,) = health.update(None, "no heartbeat for 400 ms")
    assert lost.kind is K.COMM_LOST and not health.comm_ok and health.condition is Condition.STOPPED
    assert health.update(None, "no heartbeat for 500 ms") == []
    (back,) = health.update(ENABLED, None)
    assert back.kind is K.WARNING and "answers again" in back.text
    assert health.condition is Condition.STOPPED  # still needs a reset


def test_a_reset_succeeds_when_the_drive_is_enabled_again():
    health, _, _ = _health()
    health.update(FAULT, None)
    assert health.request_reset() == [] and health.condition is Condition.RESETTING
    assert health.update(STATE_BITS[State.SWITCH_ON_DISABLED], None) == []
    (event,) = health.update(ENABLED, None)
    assert event.kind is K.ENABLED and health.condition is Condition.FOLLOWING


def test_a_reset_that_does_not_bring_the_drive_back_in_time_fails_as_a_fault():
    health, _, clock = _health()
    health.update(FAULT, None)
    health.request_reset()
    clock.now += RESET_TIMEOUT_S + 0.01
    (event,) = health.update(FAULT, None)
    assert event.kind is K.FAULT and "fault reset failed: still fault" in event.text


def test_a_reset_of_a_silent_drive_fails_at_once():
    health, _, _ = _health()
    health.update(None, "no heartbeat for 400 ms")
    health.request_reset()
    kinds = [e.kind for e in health.update(None, "no heartbeat for 500 ms")]
    assert kinds == [K.FAULT] and health.condition is Condition.STOPPED


def test_a_reset_of_a_following_drive_answers_enabled_at_once():
    health, _, _ = _health()
    assert [e.kind for e in health.request_reset()] == [K.ENABLED]
