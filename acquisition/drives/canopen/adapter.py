"""The bridge's drive interface for a CiA 402 drive on CANopen (cyclic synchronous position mode).

Per tick the bridge calls :meth:`CanopenDrive.read` (the latest measurement, from TPDO 1 and 2 of the
latest SYNC) and :meth:`CanopenDrive.apply` (the setpoint, converted to the drive's units by
:class:`~axisflow.model.drive_units.DriveUnits`: target position 0x607A in counts, velocity offset
0x60B1 in counts/s, torque offset 0x60B2 in per mille of the rated torque — the plan's feed-forward).
The cycle owner (:class:`~.cycle.SyncCycle`) sends the RPDOs and the SYNC for every drive of the bus.

The controlword of each cycle follows the drive's health (:class:`~.faults.DriveHealth`):

* following: enable operation (0x0F) with the bridge's setpoint;
* stopped (a fault, comm loss, the drive's own stop): quick stop (0x02) with the target at the
  measured position — a drive that still hears the master brakes on its own ramp and holds (quick stop
  option 5–8) or switches off (1–4); a drive in fault ignores it; this is how the bridge stops an axis
  it can no longer command setpoints for;
* resetting (a fault reset, or the enabling at start-up): the 402 walk to operation enabled
  (:func:`~.cia402.master_controlword`), the target at the measured position so that enabling never
  jumps.
"""

from __future__ import annotations

import logging
import time
from collections import deque
from dataclasses import dataclass

import canopen
from canopen.emcy import EmcyError
from canopen.sdo.exceptions import SdoError

from ....model import AxisParams, motor_torque
from ....model.drive_units import DriveUnits
from ...wire.messages import AxisSample
from ..drive import DriveEvent, DriveStatus, Setpoint
from .cia402 import CW_DISABLE_VOLTAGE, CW_QUICK_STOP, State, master_controlword
from .clock import BusClock
from .config import DriveSettings
from .faults import Condition, DriveHealth
from .objects import ERROR_CODE, ERROR_REGISTER, NMT_OPERATIONAL, RPDOS, TPDOS
from .startup import DriveInfo

log = logging.getLogger(__name__)

_RPDO1, _RPDO2 = (layout.struct for layout in RPDOS)
_TPDO1, _TPDO2 = (layout.struct for layout in TPDOS)
REST_SPEED_M_S = 1e-3
"""below this speed [m/s] a drive counts as at rest (at shutdown)"""
_NMT_NAMES = {0: "boot-up", 4: "STOPPED", 5: "OPERATIONAL", 127: "PRE-OPERATIONAL"}


@dataclass(frozen=True)
class _Received:
    """The latest frame of one TPDO: its bytes, the tick of the SYNC it answers, when it came. The
    receive thread replaces the whole record (one reference assignment), so readers need no lock. The
    SYNC it answers is the latest one sent when it arrived: at wall pacing a frame delayed past the next
    SYNC would be stamped a cycle late (docs/drives.md)."""

    data: bytes
    sync_tick: int
    arrived_s: float


_NOTHING = _Received(b"", -1, 0.0)


class CanopenDrive:
    """A :class:`~axisflow.acquisition.drives.drive.Drive` for one configured CiA 402 drive."""

    def __init__(
        self,
        network: canopen.Network,
        node: canopen.RemoteNode,
        settings: DriveSettings,
        info: DriveInfo,
        units: DriveUnits,
        params: AxisParams,
        clock: BusClock,
    ) -> None:
        assert settings.axis is not None  # DriveConfig.with_axis named it
        self.axis = settings.axis
        self.settings, self.info, self.units, self.params = settings, info, units, params
        self.node, self._network, self._clock = node, network, clock
        self.health = DriveHealth(f"drive {settings.name}", self._read_error_code)
        self._cob = [layout.cob_id(settings.node_id) for layout in (*RPDOS, *TPDOS)]
        self._tpdo: list[_Received] = [_NOTHING, _NOTHING]
        self._emergencies: deque[EmcyError] = deque()
        self._heartbeat = (time.monotonic(), NMT_OPERATIONAL)
        self._events: list[DriveEvent] = []
        self._controlword = 0
        self._target = (units.counts(0.0), 0, 0)
        """the setpoint of the next SYNC: target counts, velocity offset counts/s, torque offset ‰"""
        self._sample = AxisSample(clock.stamp_ns(0), self.axis, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
        self._position_counts = units.zero_counts
        self._collected_tick = -1
        """the SYNC tick of the measurement in :attr:`_sample`"""
        self._returned_tick = -1
        """the SYNC tick of the measurement :meth:`read` returned last"""
        self._fresh = False
        self._switched_off = False
        self._unanswered: tuple[int, float] | None = None
        """the oldest SYNC (tick, monotonic time sent) whose TPDO 1 has not come"""
        self._subscribe()

    # ---- receiving (the network's thread) ---------------------------------------------------------
    def _subscribe(self) -> None:
        self._network.subscribe(self._cob[2], self._on_tpdo1)
        self._network.subscribe(self._cob[3], self._on_tpdo2)
        self.node.emcy.add_callback(self._emergencies.append)
        self.node.nmt.add_heartbeat_callback(self._on_heartbeat)

    def _on_tpdo1(self, _cob: int, data: bytearray, _stamp: float) -> None:
        self._tpdo[0] = _Received(bytes(data), self._clock.sync_tick, time.monotonic())
        self._clock.notify_arrival()

    def _on_tpdo2(self, _cob: int, data: bytearray, _stamp: float) -> None:
        self._tpdo[1] = _Received(bytes(data), self._clock.sync_tick, time.monotonic())
        self._clock.notify_arrival()

    def _on_heartbeat(self, state: int) -> None:
        self._heartbeat = (time.monotonic(), state)

    def answered(self, sync_tick: int) -> bool:
        """Whether both TPDOs of the SYNC of ``sync_tick`` have come (or the drive is known lost, so no
        one waits for it)."""
        if not self.health.comm_ok:
            return True
        return self._tpdo[0].sync_tick >= sync_tick and self._tpdo[1].sync_tick >= sync_tick

    # ---- the cycle (the bridge's thread) ----------------------------------------------------------
    def collect(self) -> None:
        """Take in what arrived since the last call: emergencies, the latest measurement, the
        communication's state; the drive's health turns them into events."""
        while self._emergencies:
            e = self._emergencies.popleft()
            self.health.emergency(e.code, e.register)
        first = self._tpdo[0]
        statusword = None
        if first.sync_tick > self._collected_tick:
            statusword = self._take_measurement(first)
        self._events += self.health.update(statusword, self._comm_problem())

    def _take_measurement(self, first: _Received) -> int:
        statusword, position, torque = _TPDO1.unpack(first.data[: _TPDO1.size])
        second = self._tpdo[1]
        velocity = _TPDO2.unpack(second.data[: _TPDO2.size])[0] if second.data else 0
        u, p = self.units, self.params
        x = float(u.position_m(position))
        v = float(u.velocity_m_s(velocity))
        tau = float(u.torque_nm(torque))
        self._sample = AxisSample(
            stamp_ns=self._clock.stamp_ns(first.sync_tick),
            axis=self.axis,
            position_m=x,
            velocity_m_s=v,
            force_n=tau * p.transmission.force_per_torque,
            motor_angle_rad=x * p.transmission.radians_per_metre,
            motor_speed_rad_s=v * p.transmission.radians_per_metre,
            motor_torque_nm=tau,
        )
        self._position_counts = position
        self._collected_tick = first.sync_tick
        return statusword

    def _comm_problem(self) -> str | None:
        now = time.monotonic()
        clock = self._clock
        if self._unanswered is not None and self._collected_tick >= self._unanswered[0]:
            answered_all = self._collected_tick >= clock.sync_tick
            self._unanswered = None if answered_all else (clock.sync_tick, clock.sync_sent_s)
        if self._unanswered is not None:
            waited_ms = (now - self._unanswered[1]) * 1e3
            if waited_ms > self.settings.pdo_timeout_ms:
                return (
                    f"no process data (TPDO 1, COB-ID 0x{self._cob[2]:03X}) for {waited_ms:.0f} ms after a "
                    f"SYNC (pdo_timeout_ms = {self.settings.pdo_timeout_ms} ms)"
                )
        seen_s, state = self._heartbeat
        silent_ms = (now - seen_s) * 1e3
        if silent_ms > self.settings.heartbeat_timeout_ms:
            limit = self.settings.heartbeat_timeout_ms
            return f"no heartbeat for {silent_ms:.0f} ms (heartbeat_timeout_ms = {limit} ms)"
        if state != NMT_OPERATIONAL:
            return f"left NMT OPERATIONAL: its heartbeat says {_NMT_NAMES.get(state, state)} (it restarted?)"
        return None

    def on_sync(self, sync_tick: int, sent_s: float) -> None:
        """The cycle owner sent the SYNC of ``sync_tick`` at ``sent_s``."""
        if self._unanswered is None:
            self._unanswered = (sync_tick, sent_s)

    def rpdo_frames(self) -> list[tuple[int, bytes]]:
        """(COB-ID, data) of RPDO 1 and 2 for the coming SYNC: controlword and setpoint by the health
        (see the module docstring)."""
        condition, state = self.health.condition, self.health.state
        if self._switched_off:
            self._controlword = CW_DISABLE_VOLTAGE
            return [(self._cob[0], _RPDO1.pack(CW_DISABLE_VOLTAGE, self._position_counts, 0)),
                    (self._cob[1], _RPDO2.pack(0))]  # fmt: skip
        if condition is Condition.FOLLOWING and state is State.OPERATION_ENABLED:
            controlword = master_controlword(state, self._controlword)
            target, velocity, torque = self._target
        else:
            held = self._position_counts
            self._target = (held, 0, 0)
            target, velocity, torque = self._target
            if condition is Condition.STOPPED:
                controlword = CW_QUICK_STOP
            else:
                controlword = master_controlword(state, self._controlword)
        self._controlword = controlword
        return [
            (self._cob[0], _RPDO1.pack(controlword, target, torque)),
            (self._cob[1], _RPDO2.pack(velocity)),
        ]

    def stop_for_shutdown(self) -> None:
        """From now on command the drive's own quick stop (the bridge has stopped)."""
        self.health.shut_down()

    def at_rest(self) -> bool:
        """Whether the drive no longer drives the axis and the axis is still (after a quick stop)."""
        return (
            self.health.state is not State.OPERATION_ENABLED
            and abs(self._sample.velocity_m_s) < REST_SPEED_M_S
        )

    def switch_off(self) -> None:
        """From now on command disable voltage (power stage off)."""
        self._switched_off = True

    def _read_error_code(self) -> tuple[int, int]:
        """0x603F and 0x1001 over SDO (a fault came without an emergency message); (0, 0) if the drive
        does not answer (the event then says so by its missing code)."""
        try:
            code = ERROR_CODE.unpack(self.node.sdo.upload(ERROR_CODE.index, 0))
            register = ERROR_REGISTER.unpack(self.node.sdo.upload(ERROR_REGISTER.index, 0))
        except SdoError as exc:
            log.warning("drive %s: 0x603F error code unreadable: %s", self.settings.name, exc)
            return 0, 0
        return code, register

    # ---- the Drive interface ----------------------------------------------------------------------
    @property
    def stamp_ns(self) -> int:
        return self._clock.stamp_ns(self._clock.tick)

    def read(self) -> AxisSample:
        self.collect()
        self._fresh = self._collected_tick > self._returned_tick and self.health.comm_ok
        self._returned_tick = self._collected_tick
        return self._sample

    def status(self) -> DriveStatus:
        fresh = self._fresh
        following = (
            self.health.condition is Condition.FOLLOWING and self.health.state is State.OPERATION_ENABLED
        )
        return DriveStatus(following=following, fresh=fresh, commanded=self._clock.is_sync_tick)

    def apply(self, setpoint: Setpoint) -> None:
        """The setpoint of the current tick (sent with the next SYNC while the drive follows)."""
        u = self.units
        torque_nm = float(motor_torque(setpoint.force_ff_n, self.params))
        self._target = (
            u.counts(setpoint.position_m),
            u.counts_per_s(setpoint.velocity_m_s),
            u.per_mille(torque_nm),
        )

    def events(self) -> list[DriveEvent]:
        events, self._events = self._events, []
        return events

    def reset_fault(self) -> None:
        self._events += self.health.request_reset()

    def close(self) -> None:
        """Stop listening (the cycle owner has brought the drive to a stop and switched it off)."""
        for cob, callback in ((self._cob[2], self._on_tpdo1), (self._cob[3], self._on_tpdo2)):
            if callback in self._network.subscribers.get(cob, []):
                self._network.unsubscribe(cob, callback)
