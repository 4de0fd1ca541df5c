"""A simulated CiA 402 servo drive on a CAN bus, around the simulated axis's plant.

What a real drive does, on its own canopen network (its own python-can bus):

* **CiA 301**: an SDO server, NMT, a heartbeat producer, emergency messages, SYNC and PDOs — the slave
  of :mod:`.sim_slave`, which this drive is the device profile of;
* **CiA 402**: the drive-side state machine (:func:`~.cia402.drive_transition`), cyclic synchronous
  position mode (0x6060 = 8, the only mode offered), the quick stop with its option code 0x605A
  (a ramp of 0x6085, or the torque limit, then switch on disabled or — 5…8 — holding in quick stop
  active), the fault reaction 0x605E then fault, a fault reset (a rising edge of controlword bit 7),
  the following-error monitor (0x6065 window for 0x6066 ms: fault 0x8611) and the software position
  limits 0x607D (targets are clamped to them);
* **per SYNC** (synchronous RPDOs latched, then): the actual values are sampled from the plant
  (:meth:`SimulatedAxis.read`) and quantised to the drive's units by
  :class:`~axisflow.model.drive_units.DriveUnits` — position in counts of a motor encoder, velocity in
  counts/s, torque in per mille of the rated torque (0x6076: a third of the plant's torque limit) — and
  sent in the TPDOs; then the position loop runs one 1 ms plant tick per bridge tick of the cycle
  (:meth:`SimulatedAxis.apply`, its PD loop with the torque offset as feed-forward), between cycles
  following the target with the velocity offset.

A switched-off power stage (switch on disabled, ready, switched on, fault) is modelled by a setpoint
equal to the plant's own measurement with no feed-forward: the plant's position loop then produces no
force and the axis coasts on friction.

Faults for tests and demos (:class:`FaultPlan`): a fault with a given code at a drive time, and a
silence (the drive's transmitter dead: no TPDOs, heartbeat, SDO answers or emergencies; it still hears
the master) from a drive time, for good or for a while. Drive time counts the plant ticks run in
OPERATIONAL (1 ms each).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import canopen
from canopen.objectdictionary import ObjectDictionary
from canopen.sdo import SdoAbortedError

from ....model import AxisParams, cart_force, cart_force_from_torque
from ....model.drive_units import DriveUnits
from ..drive import Setpoint
from ..plant import PlantConfig
from ..sim_axis import SimulatedAxis
from .cia402 import (
    STATE_BITS,
    SW_FOLLOWING_ERROR,
    SW_FOLLOWS_TARGET,
    SW_QUICK_STOP,
    SW_REMOTE,
    QuickStopOption,
    State,
    drive_transition,
)
from .config import CanSettings, DriveSettings
from .emergency import DEFAULT_FAULT_CODE, error_register_for
from .objects import (
    COMM_CYCLE_PERIOD,
    CONTROLWORD,
    DEVICE_NAME,
    DEVICE_TYPE,
    ERROR_CODE,
    ERROR_REGISTER,
    FAULT_REACTION,
    FOLLOWING_ERROR_TIMEOUT,
    FOLLOWING_ERROR_WINDOW,
    HEARTBEAT_TIME,
    INTERPOLATION_INDEX,
    INTERPOLATION_PERIOD,
    MANDATORY,
    MODE_CSP,
    MODES_DISPLAY,
    MODES_OF_OPERATION,
    OPTIONAL,
    POSITION_ACTUAL,
    PRODUCT_CODE,
    PROFILE_402,
    QUICK_STOP_DECELERATION,
    QUICK_STOP_OPTION,
    RATED_TORQUE,
    REVISION,
    SERIAL,
    SOFTWARE_LIMIT_MAX,
    SOFTWARE_LIMIT_MIN,
    STATUSWORD,
    SUPPORTED_CSP_BIT,
    SUPPORTED_MODES,
    TARGET_POSITION,
    TORQUE_ACTUAL,
    TORQUE_OFFSET,
    VELOCITY_ACTUAL,
    VELOCITY_OFFSET,
    VENDOR_ID,
    Entry,
    drive_dictionary,
)
from .sim_slave import ABORT_RANGE, ABORT_READ_ONLY, SimulatedSlave

log = logging.getLogger(__name__)

FOLLOWING_ERROR_CODE = 0x8611
DEVICE_TYPE_SERVO = PROFILE_402 | 0x0002_0000
"""0x1000: profile 402, additional information 2 (servo drive)"""
RATED_TORQUE_SHARE = 1.0 / 3.0
"""the simulated motor's rated torque as a share of the plant's torque limit (servo motors give
about three times their rated torque for a while)"""
FAULT_REACTION_DEFAULT = 2
_LIVE = (CONTROLWORD, STATUSWORD, TARGET_POSITION, VELOCITY_OFFSET, TORQUE_OFFSET, POSITION_ACTUAL,
         VELOCITY_ACTUAL, TORQUE_ACTUAL, MODES_OF_OPERATION, MODES_DISPLAY, ERROR_CODE,
         ERROR_REGISTER)  # fmt: skip
"""objects whose value lives in the drive's process image (SDO reads and writes go there)"""


@dataclass(frozen=True)
class FaultPlan:
    """Faults the simulated drive raises on its own (drive time: plant ticks in OPERATIONAL)."""

    fault_at_s: float | None = None
    """raise a fault at this drive time (0: the drive boots in fault)"""
    fault_code: int = DEFAULT_FAULT_CODE
    silent_at_s: float | None = None
    """stop transmitting anything at this drive time"""
    silent_for_s: float | None = None
    """for this long (None: for good)"""


class _Ramp:
    """A stop on a constant deceleration from (x0, v0), then holding at its end [SI units]."""

    def __init__(self, x0_m: float, v0_m_s: float, deceleration_m_s2: float) -> None:
        self.x0, self.v0, self.a = x0_m, v0_m_s, deceleration_m_s2
        self.duration_s = abs(v0_m_s) / deceleration_m_s2 if deceleration_m_s2 > 0 else 0.0
        self.t_s = 0.0

    def setpoint(self, params: AxisParams) -> Setpoint:
        t = min(self.t_s, self.duration_s)
        sign = math.copysign(1.0, self.v0)
        v = self.v0 - sign * self.a * t
        x = self.x0 + self.v0 * t - 0.5 * sign * self.a * t * t
        acceleration = -sign * self.a if self.t_s < self.duration_s else 0.0
        force = float(cart_force(v, acceleration, params)) if self.t_s < self.duration_s else 0.0
        return Setpoint(x, v, acceleration, force)

    @property
    def done(self) -> bool:
        return self.t_s >= self.duration_s


class SimulatedDrive:
    """A CiA 402 drive for ``settings`` (its node id, encoder, zero and polarity) on the bus ``can``,
    running ``plant`` (a context manager: entering boots it; see the module docstring). It is the device
    profile of its CiA 301 slave (:class:`~.sim_slave.SimulatedSlave`)."""

    def __init__(
        self,
        can: CanSettings,
        settings: DriveSettings,
        cycle_hz: int,
        plant: PlantConfig,
        nominal: AxisParams,
        faults: FaultPlan = FaultPlan(),
    ) -> None:
        self.can, self.settings, self.faults = can, settings, faults
        self.nominal = nominal
        self.ticks_per_sync = 1000 // cycle_hz
        self.axis = SimulatedAxis(plant, nominal, start_stamp_ns=0, axis=settings.axis or "a0")
        rated_nm = plant.axis.tau_max * RATED_TORQUE_SHARE
        self.rated_torque_mnm = max(1, round(rated_nm * 1000.0))
        self.units = DriveUnits.for_axis(
            nominal, settings.encoder_counts_per_rev, self.rated_torque_mnm / 1000.0, settings.zero_counts,
            settings.direction,
        )  # fmt: skip
        self.dictionary = self._dictionary()
        self.slave = SimulatedSlave(
            can, settings.node_id, self.dictionary, (*MANDATORY, *OPTIONAL), _LIVE, self
        )
        self._image = self.slave.image
        self._image[STATUSWORD] = STATE_BITS[State.SWITCH_ON_DISABLED] | SW_QUICK_STOP | SW_REMOTE
        self.state = State.SWITCH_ON_DISABLED
        self._previous_controlword = 0
        self.ticks = 0
        """plant ticks run in OPERATIONAL (the drive time, 1 ms each)"""
        self._ramp: _Ramp | None = None
        self._lag_ms = 0
        self._fault_raised = False
        self._silent_until_s: float | None = None
        self._measured = self.axis.read()

    # ---- set-up ----------------------------------------------------------------------------------------
    def _dictionary(self) -> ObjectDictionary:
        defaults: dict[Entry, int | bytes] = {
            DEVICE_TYPE: DEVICE_TYPE_SERVO, ERROR_REGISTER: 0, HEARTBEAT_TIME: 0, VENDOR_ID: 0,
            PRODUCT_CODE: 0x4158_4953, REVISION: 1, SERIAL: self.settings.node_id,
            DEVICE_NAME: b"axisflow simulated CiA 402 drive", COMM_CYCLE_PERIOD: 0,
            QUICK_STOP_OPTION: QuickStopOption.QUICK_STOP_RAMP.value,
            FAULT_REACTION: FAULT_REACTION_DEFAULT, RATED_TORQUE: self.rated_torque_mnm,
            FOLLOWING_ERROR_WINDOW: 0xFFFF_FFFF, FOLLOWING_ERROR_TIMEOUT: 0,
            SOFTWARE_LIMIT_MIN: -(1 << 31), SOFTWARE_LIMIT_MAX: (1 << 31) - 1,
            QUICK_STOP_DECELERATION: abs(self.units.counts_per_s2(5.0)), INTERPOLATION_PERIOD: 1,
            INTERPOLATION_INDEX: -3, SUPPORTED_MODES: SUPPORTED_CSP_BIT,
        }  # fmt: skip
        return drive_dictionary(self.settings.node_id, defaults)

    def __enter__(self) -> SimulatedDrive:
        self.start()
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()

    def start(self) -> None:
        """Boot: connect, boot-up message, pre-operational (a fault planned at 0 s is raised first)."""
        self.slave.start()
        if self.faults.fault_at_s == 0.0:
            self._raise_fault(self.faults.fault_code)

    def close(self) -> None:
        self.slave.close()
        self.axis.close()

    @property
    def node(self) -> canopen.LocalNode | None:
        """The slave's canopen node (None before :meth:`start`)."""
        return self.slave.node

    @property
    def operational(self) -> bool:
        return self.slave.operational

    def _setting(self, entry: Entry) -> int:
        return self.slave.setting(entry)

    # ---- the slave's device profile (its network's thread) -------------------------------------------
    def check_write(self, entry: Entry, value: int) -> None:
        """An SDO write to a 402 object: only cyclic synchronous position, option codes in range, the
        rated torque read-only."""
        if entry is MODES_OF_OPERATION:
            if value != MODE_CSP:
                raise SdoAbortedError(ABORT_RANGE)  # only cyclic synchronous position is offered
            self._image[MODES_DISPLAY] = value
        elif entry in (QUICK_STOP_OPTION, FAULT_REACTION):
            if not 0 <= value <= (8 if entry is QUICK_STOP_OPTION else 4):
                raise SdoAbortedError(ABORT_RANGE)
        elif entry is RATED_TORQUE:
            raise SdoAbortedError(ABORT_READ_ONLY)

    def written(self, entries: tuple[Entry, ...]) -> None:
        """A new controlword runs the state machine."""
        if CONTROLWORD in entries:
            self._state_machine()

    def sample(self) -> None:
        """Per SYNC, before its RPDOs apply: the actual values, planned faults, the following error."""
        sample = self.axis.read()
        u = self.units
        self._image[POSITION_ACTUAL] = u.counts(sample.position_m)
        self._image[VELOCITY_ACTUAL] = u.counts_per_s(sample.velocity_m_s)
        self._image[TORQUE_ACTUAL] = u.per_mille(sample.motor_torque_nm)
        self._measured = sample
        self._planned_faults()
        self._following_error()

    def latched(self) -> None:
        self._state_machine()

    def cycle(self) -> None:
        """The position loop until the next SYNC: one 1 ms plant tick per bridge tick."""
        for _ in range(self.ticks_per_sync):
            self._tick()

    # ---- the 402 state machine -------------------------------------------------------------------------
    def _state_machine(self) -> None:
        controlword = self._image[CONTROLWORD]
        state = self.state
        braking = self._ramp is not None and not self._ramp.done
        if not (state is State.QUICK_STOP_ACTIVE and braking):  # a quick stop runs to rest first
            new = drive_transition(state, controlword, self._previous_controlword)
            if state is State.FAULT and new is not State.FAULT:
                self._clear_fault()
            if new is State.QUICK_STOP_ACTIVE and state is State.OPERATION_ENABLED:
                self._start_quick_stop()
            if new is State.OPERATION_ENABLED and state is not State.OPERATION_ENABLED:
                self._ramp, self._lag_ms = None, 0
            self.state = new
        self._previous_controlword = controlword
        self._statusword()

    def _statusword(self) -> None:
        word = STATE_BITS[self.state] | SW_REMOTE
        if self.state not in (State.QUICK_STOP_ACTIVE,):
            word |= SW_QUICK_STOP
        if self.state is State.OPERATION_ENABLED:
            word |= SW_FOLLOWS_TARGET
            if self._lag_ms:
                word |= SW_FOLLOWING_ERROR
        self._image[STATUSWORD] = word

    def _start_quick_stop(self) -> None:
        option = QuickStopOption(self._setting(QUICK_STOP_OPTION))
        self._ramp = self._braking(option)

    def _braking(self, option: QuickStopOption) -> _Ramp:
        m = self._measured
        if option is QuickStopOption.DISABLE:
            return _Ramp(m.position_m, 0.0, 0.0)
        if option.at_limit:
            deceleration = 0.9 * self.nominal.f_max / self.nominal.M_eq
        else:
            deceleration = abs(float(self.units.acceleration_m_s2(self._setting(QUICK_STOP_DECELERATION))))
        return _Ramp(m.position_m, m.velocity_m_s, deceleration)

    def _raise_fault(self, code: int) -> None:
        """Fault reaction (0x605E), then fault: emergency message, 0x603F, 0x1001."""
        register = error_register_for(code)
        self._image[ERROR_CODE], self._image[ERROR_REGISTER] = code, register
        reaction = self._setting(FAULT_REACTION)
        if reaction == 0 or self.state not in (State.OPERATION_ENABLED, State.QUICK_STOP_ACTIVE):
            self.state, self._ramp = State.FAULT, None
        else:
            self.state = State.FAULT_REACTION_ACTIVE
            self._ramp = self._braking(QuickStopOption(reaction))
        self._statusword()
        assert self.node is not None
        self.node.emcy.send(code, register)
        log.warning("simulated drive node %d: fault 0x%04X", self.settings.node_id, code)

    def _clear_fault(self) -> None:
        self._image[ERROR_CODE] = self._image[ERROR_REGISTER] = 0
        self._lag_ms = 0
        self._ramp = None
        assert self.node is not None
        self.node.emcy.reset()

    # ---- faults ---------------------------------------------------------------------------------------
    @property
    def drive_time_s(self) -> float:
        return self.ticks * 1e-3

    def _planned_faults(self) -> None:
        plan, t = self.faults, self.drive_time_s
        if plan.fault_at_s is not None and not self._fault_raised and t >= plan.fault_at_s:
            self._fault_raised = True
            if self.state not in (State.FAULT, State.FAULT_REACTION_ACTIVE):
                self._raise_fault(plan.fault_code)
        if plan.silent_at_s is not None and t >= plan.silent_at_s and self._silent_until_s is None:
            self._silent_until_s = (
                math.inf if plan.silent_for_s is None else plan.silent_at_s + plan.silent_for_s
            )
            self._set_silent(True)
        elif (
            self._silent_until_s is not None
            and math.isfinite(self._silent_until_s)
            and t >= self._silent_until_s
        ):
            self._silent_until_s = -math.inf  # over (and not again)
            self._set_silent(False)

    def _set_silent(self, silent: bool) -> None:
        self.slave.set_silent(silent)

    def _following_error(self) -> None:
        if self.state is not State.OPERATION_ENABLED:
            return
        window = self._setting(FOLLOWING_ERROR_WINDOW)
        lag = abs(self._image[TARGET_POSITION] - self._image[POSITION_ACTUAL])
        if window == 0xFFFF_FFFF or lag <= window:
            self._lag_ms = 0
            return
        self._lag_ms += self.ticks_per_sync
        if self._lag_ms > self._setting(FOLLOWING_ERROR_TIMEOUT):
            self._raise_fault(FOLLOWING_ERROR_CODE)

    # ---- the position loop -----------------------------------------------------------------------------
    def _tick(self) -> None:
        self.axis.apply(self._setpoint())
        self.ticks += 1

    def _setpoint(self) -> Setpoint:
        state, u = self.state, self.units
        if state is State.OPERATION_ENABLED:
            low, high = self._setting(SOFTWARE_LIMIT_MIN), self._setting(SOFTWARE_LIMIT_MAX)
            target = min(max(self._image[TARGET_POSITION], low), high)
            v = float(u.velocity_m_s(self._image[VELOCITY_OFFSET]))
            since_sync_s = (self.ticks % self.ticks_per_sync) * 1e-3
            x = float(u.position_m(target)) + v * since_sync_s
            force = float(
                cart_force_from_torque(float(u.torque_nm(self._image[TORQUE_OFFSET])), self.nominal)
            )
            return Setpoint(x, v, 0.0, force)
        if state in (State.QUICK_STOP_ACTIVE, State.FAULT_REACTION_ACTIVE) and self._ramp is not None:
            ramp = self._ramp
            ramp.t_s += 1e-3
            if ramp.done:
                self._ramp_ended()
            return ramp.setpoint(self.nominal)
        first_tick_of_cycle = self.ticks % self.ticks_per_sync == 0
        m = self._measured if first_tick_of_cycle else self.axis.read()
        return Setpoint(m.position_m, m.velocity_m_s, 0.0, 0.0)

    def _ramp_ended(self) -> None:
        if self.state is State.FAULT_REACTION_ACTIVE:
            self.state, self._ramp = State.FAULT, None
        elif not QuickStopOption(self._setting(QUICK_STOP_OPTION)).stays:
            self.state, self._ramp = State.SWITCH_ON_DISABLED, None
        self._statusword()
