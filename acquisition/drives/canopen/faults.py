"""A drive's health as the master sees it, and the typed events it reports.

:class:`DriveHealth` watches one drive cycle by cycle — its statusword (0x6041), its emergency
messages (EMCY: CiA 301 error code and error register) and whether its process data and heartbeat
arrive — and turns what changes into :class:`~axisflow.acquisition.drives.drive.DriveEvent` s:

* **fault** — the statusword shows fault reaction active or fault; the code is the emergency message's
  (or, when none came, the drive's 0x603F read over SDO);
* **comm lost** — no process data for ``pdo_timeout_ms``, no heartbeat for ``heartbeat_timeout_ms``,
  or a heartbeat that says the drive left NMT OPERATIONAL (it rebooted);
* **drive stopped** — the drive left operation enabled without being told (its own quick stop);
* **warning** — the statusword's warning or following-error bit rose, or an emergency message came
  that no fault followed within a cycle.

After a stopping event the drive is *stopped* until :meth:`DriveHealth.request_reset`; the master
then walks the state machine back to operation enabled (:func:`~.cia402.master_controlword`) and
reports **enabled**, or **fault** ("reset failed") if the drive is not back within
:data:`RESET_TIMEOUT_S`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from enum import Enum

from ..drive import DriveEvent, DriveEventKind
from .cia402 import SW_FOLLOWING_ERROR, SW_WARNING, State, state_of
from .emergency import describe_code

RESET_TIMEOUT_S = 2.0
"""wall time a fault reset may take before it counts as failed (drives re-energise in 0.1–1 s)"""


class Condition(Enum):
    FOLLOWING = "following"
    """enabled (or being enabled at start-up) and following the setpoints"""
    STOPPED = "stopped"
    """after a fault, comm loss or the drive's own stop: no setpoints until a reset"""
    RESETTING = "resetting"
    """a fault reset walks the state machine back to operation enabled"""


@dataclass(frozen=True)
class Emergency:
    code: int
    register: int


class DriveHealth:
    """The health of one drive (see the module docstring). ``name`` names it in every event's text;
    ``read_error_code`` returns (0x603F, 0x1001) when a fault comes without an emergency message."""

    def __init__(
        self,
        name: str,
        read_error_code: Callable[[], tuple[int, int]],
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.name = name
        self._read_error_code = read_error_code
        self._clock = clock
        self.condition = Condition.FOLLOWING
        self.state: State | None = None
        self.statusword = 0
        self._comm_problem: str | None = None
        self._pending: list[Emergency] = []
        """emergencies of this cycle, not yet explained by a fault"""
        self._held: list[Emergency] = []
        """emergencies of the previous cycle: a warning unless a fault follows now"""
        self._reset_deadline = 0.0

    @property
    def comm_ok(self) -> bool:
        return self._comm_problem is None

    def emergency(self, code: int, register: int) -> None:
        """An EMCY arrived (code 0: the drive's "error reset", which needs no event)."""
        if code:
            self._pending.append(Emergency(code, register))

    def update(self, statusword: int | None, comm_problem: str | None) -> list[DriveEvent]:
        """One cycle: the statusword of fresh process data (None: none came) and what is wrong with the
        communication (None: nothing). Returns the events of this cycle, oldest first."""
        events: list[DriveEvent] = []
        if comm_problem is not None:
            if self._comm_problem is None:
                events.append(self._event(DriveEventKind.COMM_LOST, f"{self.name}: {comm_problem}"))
            if self.condition is Condition.RESETTING:
                events.append(
                    self._event(DriveEventKind.FAULT, f"{self.name}: fault reset failed: {comm_problem}")
                )
            self._comm_problem = comm_problem
            self.condition = Condition.STOPPED
            return events
        if self._comm_problem is not None:
            self._comm_problem = None
            shown = f"statusword 0x{statusword:04X}" if statusword is not None else "no process data yet"
            events.append(
                self._event(
                    DriveEventKind.WARNING, f"{self.name} answers again ({shown}): reset the fault to go on"
                )
            )
        if statusword is not None:
            events += self._statusword(statusword)
        events += self._unexplained_emergencies()
        if self.condition is Condition.RESETTING and self._clock() > self._reset_deadline:
            self.condition = Condition.STOPPED
            events.append(
                self._fault(f"fault reset failed: still {self._state_text()} after {RESET_TIMEOUT_S:g} s")
            )
        return events

    def request_reset(self) -> list[DriveEvent]:
        """Start a fault reset, or the enabling at start-up (the caller walks the state machine); an
        enabled event at once if the drive follows already."""
        if self.condition is Condition.FOLLOWING and self.state is State.OPERATION_ENABLED:
            return [self._event(DriveEventKind.ENABLED, f"{self.name}: no fault to reset; operation enabled")]
        self.condition = Condition.RESETTING
        self._reset_deadline = self._clock() + RESET_TIMEOUT_S
        return []

    def shut_down(self) -> None:
        """The master stops the drive for good (no event: nothing went wrong)."""
        self.condition = Condition.STOPPED

    # ---- the steps of one cycle -----------------------------------------------------------------------
    def _statusword(self, statusword: int) -> list[DriveEvent]:
        previous_word, previous_state = self.statusword, self.state
        self.statusword, self.state = statusword, state_of(statusword)
        events = []
        faulted = self.state in (State.FAULT_REACTION_ACTIVE, State.FAULT)
        was_faulted = previous_state in (State.FAULT_REACTION_ACTIVE, State.FAULT)
        if faulted and not was_faulted and self.condition is not Condition.RESETTING:
            self.condition = Condition.STOPPED
            events.append(self._fault(f"faulted ({self._state_text()})"))
        elif self.condition is Condition.RESETTING and self.state is State.OPERATION_ENABLED:
            self.condition = Condition.FOLLOWING
            events.append(self._event(DriveEventKind.ENABLED, f"{self.name}: fault reset; operation enabled"))
        elif (
            self.condition is Condition.FOLLOWING
            and previous_state is State.OPERATION_ENABLED
            and self.state is not State.OPERATION_ENABLED
            and not faulted
        ):
            self.condition = Condition.STOPPED
            events.append(
                self._event(
                    DriveEventKind.DRIVE_STOPPED,
                    f"{self.name} left operation enabled on its own: now {self._state_text()}",
                )
            )
        rose = statusword & ~previous_word
        if rose & SW_WARNING and not faulted:
            events.append(
                self._event(DriveEventKind.WARNING, f"{self.name}: warning bit set ({self._state_text()})")
            )
        if rose & SW_FOLLOWING_ERROR and not faulted:
            events.append(
                self._event(
                    DriveEventKind.WARNING,
                    f"{self.name}: following error (0x6065 window exceeded for 0x6066)",
                )
            )
        return events

    def _unexplained_emergencies(self) -> list[DriveEvent]:
        events = [
            self._event(
                DriveEventKind.WARNING, f"{self.name}: emergency {describe_code(e.code)} without a fault", e
            )
            for e in self._held
        ]
        self._held, self._pending = self._pending, []
        return events

    def _fault(self, what: str) -> DriveEvent:
        emergencies = self._pending + self._held
        self._pending, self._held = [], []
        cause = emergencies[-1] if emergencies else Emergency(*self._read_error_code())
        text = f"{self.name} {what}: {describe_code(cause.code)}" if cause.code else f"{self.name} {what}"
        return self._event(DriveEventKind.FAULT, text, cause)

    def _event(self, kind: DriveEventKind, text: str, cause: Emergency | None = None) -> DriveEvent:
        code, register = (cause.code, cause.register) if cause is not None else (0, 0)
        return DriveEvent(kind, text, code, register, self.statusword)

    def _state_text(self) -> str:
        state = self.state.value if self.state is not None else "in an undefined state"
        return f"{state}, statusword 0x{self.statusword:04X}"
