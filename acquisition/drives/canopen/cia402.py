"""The CiA 402 drive state machine: the statusword and controlword bits, both sides of it.

The drive's states and how the statusword (0x6041) shows them (x: any value)::

    state                    bits 6 5 3 2 1 0   mask   value
    not ready to switch on        0 x 0 0 0 0   0x4F   0x00
    switch on disabled            1 x 0 0 0 0   0x4F   0x40
    ready to switch on            0 1 0 0 0 1   0x6F   0x21
    switched on                   0 1 0 0 1 1   0x6F   0x23
    operation enabled             0 1 0 1 1 1   0x6F   0x27
    quick stop active             0 0 0 1 1 1   0x6F   0x07
    fault reaction active         0 x 1 1 1 1   0x4F   0x0F
    fault                         0 x 1 0 0 0   0x4F   0x08

Other statusword bits: 4 voltage enabled, 7 warning, 9 remote, 10 target reached, 12 (CSP) the drive
follows the target, 13 (CSP) following error. The controlword (0x6040) commands, bits 7 3 2 1 0
(bit 2 "quick stop" is active low)::

    shutdown              0 x 1 1 0   0x06     transitions 2, 6, 8
    switch on             0 0 1 1 1   0x07     3 (and 5: disable operation)
    enable operation      0 1 1 1 1   0x0F     4, 16
    disable voltage       0 x x 0 x   0x00     7, 9, 10, 12
    quick stop            0 x 0 1 x   0x02     7, 10, 11
    fault reset           0 → 1       0x80     15 (on the rising edge of bit 7)

:func:`drive_transition` is the drive's side (the simulated drive); :func:`master_controlword` is the
master's: the next controlword on the way to operation enabled from the state a statusword shows.
"""

from __future__ import annotations

from enum import Enum


class State(Enum):
    NOT_READY_TO_SWITCH_ON = "not ready to switch on"
    SWITCH_ON_DISABLED = "switch on disabled"
    READY_TO_SWITCH_ON = "ready to switch on"
    SWITCHED_ON = "switched on"
    OPERATION_ENABLED = "operation enabled"
    QUICK_STOP_ACTIVE = "quick stop active"
    FAULT_REACTION_ACTIVE = "fault reaction active"
    FAULT = "fault"


# statusword bits
SW_VOLTAGE_ENABLED = 1 << 4
SW_QUICK_STOP = 1 << 5
"""0: a quick stop is active"""
SW_WARNING = 1 << 7
SW_REMOTE = 1 << 9
SW_TARGET_REACHED = 1 << 10
SW_FOLLOWS_TARGET = 1 << 12
"""CSP: the drive follows the target position"""
SW_FOLLOWING_ERROR = 1 << 13
"""CSP: the position lags the target by more than the window 0x6065 for longer than 0x6066"""

# controlword commands
CW_SHUTDOWN = 0x06
CW_SWITCH_ON = 0x07
CW_ENABLE_OPERATION = 0x0F
CW_DISABLE_VOLTAGE = 0x00
CW_QUICK_STOP = 0x02
CW_FAULT_RESET = 0x80
_CW_BITS = 0x8F
"""the controlword bits the state machine reads (7, 3, 2, 1, 0)"""

_DECODE: tuple[tuple[int, int, State], ...] = (
    (0x4F, 0x00, State.NOT_READY_TO_SWITCH_ON),
    (0x4F, 0x40, State.SWITCH_ON_DISABLED),
    (0x6F, 0x21, State.READY_TO_SWITCH_ON),
    (0x6F, 0x23, State.SWITCHED_ON),
    (0x6F, 0x27, State.OPERATION_ENABLED),
    (0x6F, 0x07, State.QUICK_STOP_ACTIVE),
    (0x4F, 0x0F, State.FAULT_REACTION_ACTIVE),
    (0x4F, 0x08, State.FAULT),
)
STATE_BITS: dict[State, int] = {
    State.NOT_READY_TO_SWITCH_ON: 0x00,
    State.SWITCH_ON_DISABLED: 0x40,
    State.READY_TO_SWITCH_ON: 0x21,
    State.SWITCHED_ON: 0x23 | SW_VOLTAGE_ENABLED,
    State.OPERATION_ENABLED: 0x27 | SW_VOLTAGE_ENABLED,
    State.QUICK_STOP_ACTIVE: 0x07 | SW_VOLTAGE_ENABLED,
    State.FAULT_REACTION_ACTIVE: 0x0F | SW_QUICK_STOP | SW_VOLTAGE_ENABLED,
    State.FAULT: 0x08 | SW_QUICK_STOP,
}
"""the statusword bits a drive sets for each state (bits 0–6)"""


def state_of(statusword: int) -> State | None:
    """The state a statusword shows (None for a combination the standard does not define)."""
    for mask, value, state in _DECODE:
        if statusword & mask == value:
            return state
    return None


def drive_transition(state: State, controlword: int, previous_controlword: int) -> State:
    """The drive's state after it reads ``controlword`` in ``state`` (CiA 402 transitions 2–12, 15, 16;
    the automatic ones — 0, 1, 13, 14 and the end of a quick stop or fault reaction — are the drive's
    own). A command that is not valid in a state leaves the state unchanged."""
    cw = controlword & _CW_BITS
    voltage = bool(cw & 0x02)
    quick_stop = voltage and not cw & 0x04  # bit 2 is active low
    if state is State.FAULT:
        rising = cw & CW_FAULT_RESET and not previous_controlword & CW_FAULT_RESET
        return State.SWITCH_ON_DISABLED if rising else state  # 15
    if state in (State.NOT_READY_TO_SWITCH_ON, State.FAULT_REACTION_ACTIVE):
        return state
    if not voltage:
        return State.SWITCH_ON_DISABLED  # 7, 9, 10, 12
    if state is State.QUICK_STOP_ACTIVE:
        return State.OPERATION_ENABLED if cw & 0x0F == CW_ENABLE_OPERATION else state  # 16
    if quick_stop:
        return State.QUICK_STOP_ACTIVE if state is State.OPERATION_ENABLED else State.SWITCH_ON_DISABLED
    low = cw & 0x07
    if state is State.SWITCH_ON_DISABLED:
        return State.READY_TO_SWITCH_ON if low == CW_SHUTDOWN else state  # 2
    if low == CW_SHUTDOWN:
        return State.READY_TO_SWITCH_ON  # 6, 8
    if state is State.READY_TO_SWITCH_ON:
        return State.SWITCHED_ON if low == CW_SWITCH_ON else state  # 3
    if state is State.SWITCHED_ON:
        return State.OPERATION_ENABLED if cw & 0x0F == CW_ENABLE_OPERATION else state  # 4
    # operation enabled
    return State.SWITCHED_ON if cw & 0x0F == CW_SWITCH_ON else state  # 5


def master_controlword(state: State | None, previous_controlword: int) -> int:
    """The next controlword on the way to operation enabled from ``state`` (what a master sends each
    cycle): a fault is reset on a rising edge of bit 7 (0x80 after a cycle without it); a quick stop
    is left through switch on disabled (disable voltage), which works whatever the quick-stop option
    code; a state in which the drive acts on its own (fault reaction, not ready) gets no command."""
    if state is State.FAULT:
        return CW_DISABLE_VOLTAGE if previous_controlword & CW_FAULT_RESET else CW_FAULT_RESET
    if state in (State.QUICK_STOP_ACTIVE, State.FAULT_REACTION_ACTIVE, State.NOT_READY_TO_SWITCH_ON, None):
        return CW_DISABLE_VOLTAGE
    return {
        State.SWITCH_ON_DISABLED: CW_SHUTDOWN,
        State.READY_TO_SWITCH_ON: CW_SWITCH_ON,
        State.SWITCHED_ON: CW_ENABLE_OPERATION,
        State.OPERATION_ENABLED: CW_ENABLE_OPERATION,
    }[state]


class QuickStopOption(Enum):
    """0x605A quick stop option codes (and, 0–4, the 0x605E fault reaction codes)."""

    DISABLE = 0
    """switch the power stage off at once: the axis coasts"""
    SLOW_DOWN_RAMP = 1
    QUICK_STOP_RAMP = 2
    CURRENT_LIMIT = 3
    VOLTAGE_LIMIT = 4
    SLOW_DOWN_RAMP_STAY = 5
    QUICK_STOP_RAMP_STAY = 6
    CURRENT_LIMIT_STAY = 7
    VOLTAGE_LIMIT_STAY = 8

    @property
    def stays(self) -> bool:
        """Whether the drive stays in quick stop active, holding, once at rest (5–8); otherwise it
        goes to switch on disabled (power off)."""
        return self.value >= 5

    @property
    def at_limit(self) -> bool:
        """Whether it brakes at the current (torque) or voltage limit instead of on a ramp."""
        return self.value in (3, 4, 7, 8)
