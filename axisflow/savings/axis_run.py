"""The savings runs on a simulated axis: bridge and recorder on loopback, the moves sent from here.

As the demo does, a :class:`~axisflow.processes.Launcher` starts the drive bridge (the simulated axis
with the packaged nominal parameters and a plant profile, ``--speed 0``: as fast as the recorder takes
its samples) and, once it is ready, the recorder, on an embedded Zenoh peer network on loopback
(``tcp/127.0.0.1:<free port>``). This process then sends each run of the comparison
(:mod:`.comparison`) through the bridge's public move API, one run after the other:

1. a positioning move (minimum-time poly5, way point index 0, not measured) wherever the axis is not
   within a micrometre of the run's first start (and before any move that does not start where the
   one before ended: a log's moves need not chain);
2. every move appended with no idle tick, each after its plan record (``<prefix>/<axis>/plan``,
   labelled with the run: ``baseline``, ``equal-time``, ``matched-omega``), so that the recording alone
   holds what was planned next to what the axis did — the polynomial laws by name, the baselines as the
   wire's sampled paths (:meth:`~axisflow.planner.baseline_laws.BaselineMove.trajectory`);
3. at most :data:`QUEUE_WINDOW` moves queued at once; a rejected, dropped or stopped move ends the run
   with the bridge's reason.

The recorder stops after the last move's completion (its stop proves nothing was still on the way),
then the bridge. What each move cost is read back from the recording by :mod:`.measurement`.
"""

from __future__ import annotations

import socket
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from ..acquisition import PLAN_TYPE, AxisKeys, MoveState, PlanRecord
from ..acquisition.bus.axis_state import AxisState
from ..acquisition.bus.move_sender import BRIDGE_TIMEOUT_S, MoveSender
from ..acquisition.bus.publisher import SequencedPublisher, Traffic
from ..acquisition.drives.plant import load_profile
from ..acquisition.drives.plant_profiles import DEFAULT_PROFILE
from ..acquisition.wire.keys import recorder_token
from ..deploy.processes import READY_TIMEOUT_S, Launcher, free_port
from ..model import AxisflowError, AxisParams, load_params
from ..planner import Case, ExactBackend, MoveProblem
from .comparison import PlannedMove, PlannedRun

QUEUE_WINDOW = 256
"""moves of a run queued on the bridge at once (its queue holds 1024)"""
POSITION_TOLERANCE_M = 1e-6
"""a move that starts farther than this from where the axis is gets a positioning move first [m]"""
STALL_TIMEOUT_S = 120.0
"""the longest wall time without any move status while moves are queued [s]"""


@dataclass(frozen=True)
class AxisRunSettings:
    """Where and on what the runs go."""

    out: Path
    """the folder of the recording and the processes' logs"""
    plant_profile: str = DEFAULT_PROFILE
    speed: float = 0.0
    """the bridge's --speed (0: as fast as the recorder takes the samples)"""
    recording: str = "savings.mcap"
    overwrite: bool = False
    """replace an earlier recording of that name"""


@dataclass(frozen=True)
class AxisRun:
    """What the runs left behind: the recording and the simulated plant it was made on."""

    recording: Path
    plant: str
    wall_time_s: float


def run_on_axis(
    runs: Sequence[PlannedRun],
    params: AxisParams,
    settings: AxisRunSettings,
    progress: Callable[[str], None],
    stop: threading.Event | None = None,
) -> AxisRun:
    """Run ``runs`` on a simulated axis (see the module docstring) into ``settings.out``; ``params``
    plan the positioning moves."""
    from ..acquisition.bus.readiness import wait_for_token
    from ..acquisition.bus.session import ZenohOptions, open_session

    stop = stop or threading.Event()
    out = settings.out
    out.mkdir(parents=True, exist_ok=True)
    path = out / settings.recording
    plant = load_profile(settings.plant_profile, load_params(None)).describe()
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    t0 = time.monotonic()
    with Launcher(out / "logs") as children:
        progress(f"bridge (simulated axis, plant {plant}, --speed {settings.speed:g}) on {endpoint}")
        bridge = children.start(
            "bridge", "bridge", "--plant-profile", settings.plant_profile, "--speed", f"{settings.speed:g}",
            "--listen", endpoint, ready=True,
        )  # fmt: skip
        children.wait_ready(bridge, READY_TIMEOUT_S)
        with open_session(ZenohOptions(connect=(endpoint,))) as session:
            again = ("--overwrite",) if settings.overwrite else ()
            recorder = children.start(
                "recorder", "record", "-o", str(path), "--connect", endpoint, *again, ready=True
            )
            children.wait_ready(recorder, READY_TIMEOUT_S)
            token = recorder_token(socket.gethostname(), recorder.pid)
            if not wait_for_token(session, token, READY_TIMEOUT_S):
                raise AxisflowError(f"the recorder of {path} was ready, but its token {token} never came")
            send_runs(session, AxisKeys(), runs, params, progress, stop)
            end = children.stop(recorder)
            if end.returncode != 0:
                raise AxisflowError(
                    f"the recorder of {path} exited with {end.returncode}; "
                    f"see {end.name}.err in {children.logs}"
                )
        children.stop(bridge)
    return AxisRun(path, plant, time.monotonic() - t0)


def send_runs(
    session: object,
    keys: AxisKeys,
    runs: Sequence[PlannedRun],
    params: AxisParams,
    progress: Callable[[str], None],
    stop: threading.Event,
) -> None:
    """Send ``runs`` one after the other to the bridge of ``keys`` on ``session`` (a Zenoh session a
    recorder listens on), each move after its plan record; return once every move has completed."""
    with _Sender(session, keys, params, progress, stop) as sender:
        for run in runs:
            sender.run(run)


class _Sender:
    """Sends the runs' moves with their plan records and follows their statuses."""

    def __init__(
        self,
        session: object,
        keys: AxisKeys,
        params: AxisParams,
        progress: Callable[[str], None],
        stop: threading.Event,
    ) -> None:
        self.session, self.keys, self.params, self.say, self.stop = session, keys, params, progress, stop

    def __enter__(self) -> _Sender:
        self.moves = MoveSender(self.session, self.keys)  # type: ignore[arg-type]
        self.plans = SequencedPublisher(self.session, self.keys.plan, PLAN_TYPE, Traffic.COMMAND)  # type: ignore[arg-type]
        try:
            self.moves.require_bridge(BRIDGE_TIMEOUT_S)
            with AxisState(self.session, self.keys, "setpoint", follow=False) as state:  # type: ignore[arg-type]
                self.x_now = state.wait(BRIDGE_TIMEOUT_S).position_m
        except BaseException:
            self.__exit__()
            raise
        return self

    def __exit__(self, *_exc: object) -> None:
        self.plans.undeclare()
        self.moves.close()

    def run(self, run: PlannedRun) -> None:
        """Send every move of ``run`` (positioning moves where needed), wait until all completed."""
        pending: set[int] = set()
        last = 0
        t0 = time.monotonic()
        for move in run.moves:
            if move.zero_move:
                continue
            if abs(move.x0_m - self.x_now) > POSITION_TOLERANCE_M:
                pending.add(self._position(run.label, move.x0_m))
            while len(pending) >= QUEUE_WINDOW:
                self._follow(pending)
            last = self._send(run.label, move)
            pending.add(last)
            self.x_now = move.x1_m
        while pending:
            self._follow(pending)
        self.say(f"  {run.label}: {len(run.moves)} moves ran in {time.monotonic() - t0:.1f} s")

    def _follow(self, pending: set[int]) -> None:
        """Wait for the next statuses; drop completed moves from ``pending``; a refusal is an error."""
        deadline = time.monotonic() + STALL_TIMEOUT_S
        while True:
            if self.stop.is_set():
                raise KeyboardInterrupt
            new = self.moves.poll_status()
            for status in new:
                if status.move_id not in pending:
                    continue
                if status.state in (MoveState.REJECTED, MoveState.DROPPED, MoveState.STOPPED):
                    raise AxisflowError(
                        f"the bridge {status.state.name.lower()} move {status.move_id}: {status.text}"
                    )
                if status.state is MoveState.COMPLETED:
                    pending.discard(status.move_id)
            if new:
                return
            if not self.moves.bridge_alive:
                raise AxisflowError(f"the bridge of axis {self.keys.axis!r} disappeared mid-run")
            if time.monotonic() > deadline:
                raise AxisflowError(f"no move status from the bridge within {STALL_TIMEOUT_S:g} s")
            time.sleep(0.001)

    def _position(self, label: str, x_m: float) -> int:
        """A minimum-time poly5 move from where the axis is to ``x_m`` (index 0: not measured)."""
        problem = MoveProblem(self.x_now, x_m, "poly5", Case.MIN_TIME)
        r = ExactBackend(deadline_s=30.0).solve(problem, self.params)
        move = PlannedMove.of_plan(0, r, self.params)
        self.x_now = x_m
        return self._send(label, move)

    def _send(self, label: str, move: PlannedMove) -> int:
        move_id = self.moves.next_move_id
        record = PlanRecord(
            stamp_ns=time.time_ns(),
            axis=self.keys.axis,
            move_id=move_id,
            sender=self.moves.sender_id,
            run=label,
            waypoint_index=move.index,
            case=move.case,
            law=move.law,
            solver=move.solver,
            omega=move.omega,
            start_position_m=move.x0_m,
            end_position_m=move.x1_m,
            duration_s=move.duration_s,
            energy_j=move.score.energy_j,
            energy_accounting=self.params.energy_accounting.value,
            objective=move.objective,
            max_violation=move.max_violation,
            status=move.status,
            iterations=0,
            solve_time_s=move.solve_time_s,
            certificate=move.certificate or {},
        )
        self.plans.put(record.encode(), record.stamp_ns)
        if move.path is not None:
            self.moves.send_trajectory(move.path, move_id=move_id)
        else:
            self.moves.send(move.x0_m, move.x1_m, move.duration_s, law=move.law, move_id=move_id)
        return move_id
