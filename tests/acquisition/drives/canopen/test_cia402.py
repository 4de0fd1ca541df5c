"""The CiA 402 state machine: every state's statusword decodes back to it, and the master's
controlwords walk the drive's transitions to operation enabled from every state."""

import pytest
from axisflow.acquisition.drives.canopen.cia402 import (
    CW_DISABLE_VOLTAGE,
    CW_ENABLE_OPERATION,
    CW_FAULT_RESET,
    CW_QUICK_STOP,
    CW_SHUTDOWN,
    CW_SWITCH_ON,
    STATE_BITS,
    SW_REMOTE,
    SW_WARNING,
    State,
    drive_transition,
    master_controlword,
    state_of,
)


@pytest.mark.parametrize("state", list(State))
def test_each_state_reads_back_from_its_statusword_whatever_the_other_bits(state):
    word = STATE_BITS[state]
    assert state_of(word) is state
    assert state_of(word | SW_WARNING | SW_REMOTE | (1 << 12)) is state


def test_the_standard_examples_decode():
    assert state_of(0x0250) is State.SWITCH_ON_DISABLED  # remote, quick stop bit, switch on disabled
    assert state_of(0x0637) is State.OPERATION_ENABLED
    assert state_of(0x0617) is State.QUICK_STOP_ACTIVE
    assert state_of(0x0218) is State.FAULT
    assert state_of(0x0001) is None  # ready to switch on without bit 5 is no state


@pytest.mark.parametrize(
    ("state", "controlword", "after"),
    [
        (State.SWITCH_ON_DISABLED, CW_SHUTDOWN, State.READY_TO_SWITCH_ON),  # 2
        (State.READY_TO_SWITCH_ON, CW_SWITCH_ON, State.SWITCHED_ON),  # 3
        (State.SWITCHED_ON, CW_ENABLE_OPERATION, State.OPERATION_ENABLED),  # 4
        (State.OPERATION_ENABLED, CW_SWITCH_ON, State.SWITCHED_ON),  # 5
        (State.SWITCHED_ON, CW_SHUTDOWN, State.READY_TO_SWITCH_ON),  # 6
        (State.READY_TO_SWITCH_ON, CW_QUICK_STOP, State.SWITCH_ON_DISABLED),  # 7
        (State.OPERATION_ENABLED, CW_SHUTDOWN, State.READY_TO_SWITCH_ON),  # 8
        (State.OPERATION_ENABLED, CW_DISABLE_VOLTAGE, State.SWITCH_ON_DISABLED),  # 9
        (State.SWITCHED_ON, CW_QUICK_STOP, State.SWITCH_ON_DISABLED),  # 10
        (State.OPERATION_ENABLED, CW_QUICK_STOP, State.QUICK_STOP_ACTIVE),  # 11
        (State.QUICK_STOP_ACTIVE, CW_DISABLE_VOLTAGE, State.SWITCH_ON_DISABLED),  # 12
        (State.QUICK_STOP_ACTIVE, CW_ENABLE_OPERATION, State.OPERATION_ENABLED),  # 16
        (State.SWITCH_ON_DISABLED, CW_ENABLE_OPERATION, State.SWITCH_ON_DISABLED),  # not valid: stays
        (State.FAULT, CW_SHUTDOWN, State.FAULT),  # only a fault reset leaves a fault
        (State.FAULT_REACTION_ACTIVE, CW_FAULT_RESET, State.FAULT_REACTION_ACTIVE),  # the drive's own
    ],
)
def test_drive_transitions(state, controlword, after):
    assert drive_transition(state, controlword, 0) is after


def test_a_fault_is_reset_on_the_rising_edge_of_bit_7_only():
    assert drive_transition(State.FAULT, CW_FAULT_RESET, 0) is State.SWITCH_ON_DISABLED  # 15
    assert drive_transition(State.FAULT, CW_FAULT_RESET, CW_FAULT_RESET) is State.FAULT  # held, no edge


@pytest.mark.parametrize("start", [s for s in State if s is not State.FAULT_REACTION_ACTIVE])
def test_the_master_walks_every_state_to_operation_enabled(start):
    state, previous = start, 0
    if start is State.NOT_READY_TO_SWITCH_ON:
        state = State.SWITCH_ON_DISABLED  # the drive leaves it on its own (transition 1)
    for _ in range(8):
        controlword = master_controlword(state, previous)
        state, previous = drive_transition(state, controlword, previous), controlword
        if state is State.OPERATION_ENABLED:
            break
    assert state is State.OPERATION_ENABLED
