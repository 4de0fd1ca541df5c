"""The online planner node: each move optimised while the previous one runs, sent to the bridge, and
followed on the bridge's typed move status — the paper's scheme on a live axis.

For each run (a case × law over the way points) the node

1. reads where the axis holds (its latest setpoint) and, if that is not the first way point, sends a
   minimum-time poly5 move there (way point index 0: not part of the experiment);
2. plans the move to way point 1 and sends it, then keeps ``lookahead`` planned moves queued behind
   the running one: each time a move starts, the next is planned (one solve of the planner back-end,
   the result object as it is) and sent appended, so it starts on the tick the previous one ends;
3. publishes each plan's :class:`~axisflow.acquisition.wire.plan_record.PlanRecord` on
   ``<prefix>/<axis>/plan`` before sending the move, so that a recording holds the plans;
4. follows every move through its statuses: a rejection, a drop, a stop or a vanished bridge ends the
   run with the bridge's reason; a move that starts later than the end of the one before (the queue
   ran dry: the plan was late) ends it too, naming the move and the idle ticks.

A move shorter than one encoder count (a repeated way point, a way point within a count of the one
before) is a zero move (:func:`~axisflow.planner.evaluation.zero_move_result`): nothing is sent or
published for it, and the next move follows the one before it (its start lies within one count of
the axis, inside the bridge's jump tolerance). The report counts such moves.

The node checks its stop event (set by SIGINT/SIGTERM) before each plan and while it waits for
statuses; every solve is bounded (the back-ends' iteration caps and deadlines), so a stop ends a run
within one solve.

Per move it reports the solve time and the **slack**: the drive time between the bridge accepting the
move (the plan ready, sent, validated) and the move's start. Drive time is the bridge's clock: at
``--speed 1`` it is wall time; at ``--speed 0`` the bridge runs as fast as its consumers allow and
the slack shrinks accordingly (use a larger lookahead there).

The node sits above the planner and acquisition layers and uses each as it is: a
:class:`~axisflow.planner.PlannerBackend` and its :class:`~axisflow.planner.PlanResult`, the bridge's
public move API (:class:`~axisflow.acquisition.bus.move_sender.MoveSender`).
"""

from __future__ import annotations

import itertools
import math
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import zenoh

from .acquisition import PLAN_TYPE, AxisKeys, MoveCommand, MoveState, MoveStatus, PlanRecord
from .acquisition.bus.axis_state import AxisState
from .acquisition.bus.move_sender import BRIDGE_TIMEOUT_S, MoveSender
from .acquisition.bus.publisher import SequencedPublisher, Traffic
from .model import AxisflowError, AxisParams, polynomial_law
from .planner import Case, ExactBackend, MoveProblem, PlannerBackend, PlanResult, SolveStatus

_REFUSED_STATUSES = (SolveStatus.DEADLINE, SolveStatus.FAILED, SolveStatus.INFEASIBLE)
"""plan statuses the node never sends (a capped IPOPT iterate is sent when it meets the limits)"""


class PlanLateError(AxisflowError):
    """A move started later than the end of the move before it: the queue ran dry."""


@dataclass(frozen=True)
class NodeRun:
    """One run of the node: a case and a law over the way points."""

    case: Case
    law: str


@dataclass
class MoveOutcome:
    """One move of a run: its plan and what the bridge did with it."""

    index: int
    """k for the move from way point k − 1 to k; 0 for the move to the first way point"""
    command: MoveCommand
    plan: PlanResult
    accepted: MoveStatus | None = None
    completed: MoveStatus | None = None

    @property
    def slack_s(self) -> float:
        """Drive time from the bridge accepting the move to its start [s]."""
        assert self.accepted is not None
        return (self.accepted.start_tick - self.accepted.tick) * 1e-3


@dataclass
class RunReport:
    run: NodeRun
    solver: str
    moves: list[MoveOutcome] = field(default_factory=list)
    zero_moves: list[int] = field(default_factory=list)
    """way point indices k whose move k − 1 → k is a zero move (not sent)"""

    @property
    def experiment(self) -> list[MoveOutcome]:
        """The moves between way points (without the move to the first one)."""
        return [m for m in self.moves if m.index > 0]

    @property
    def idle_ticks(self) -> list[int]:
        """Ticks between the end of each move and the start of the next, over the experiment."""
        ticks = [(m.accepted.start_tick, m.accepted.end_tick) for m in self.experiment if m.accepted]
        return [b[0] - a[1] for a, b in itertools.pairwise(ticks)]

    def summary(self) -> str:
        moves = self.experiment
        solve_ms = np.array([m.plan.solve_time_s * 1e3 for m in moves])
        slack_ms = np.array([m.slack_s * 1e3 for m in moves[1:]]) if len(moves) > 1 else np.array([math.nan])
        total = math.fsum(m.plan.duration_s for m in moves)
        energy = math.fsum(m.plan.energy_j for m in moves)
        zero = f" (+{len(self.zero_moves)} zero moves, not sent)" if self.zero_moves else ""
        head = f"{self.run.case.value} {self.run.law} ({self.solver}): {len(moves)} moves{zero}"
        if not moves:
            return head
        return (
            f"{head}, T = {total:.2f} s, "
            f"E_th = {energy:.1f} J, solve {solve_ms.mean():.3f} ± {solve_ms.std():.3f} ms, "
            f"slack min {np.min(slack_ms):.0f} ms, idle ticks {sum(self.idle_ticks)}"
        )


@dataclass(frozen=True)
class NodeSettings:
    keys: AxisKeys
    runs: tuple[NodeRun, ...]
    omega: float
    lookahead: int = 1
    """planned moves kept queued behind the running one (the paper: 1)"""
    lookahead_s: float = 0.0
    """and at least this much drive time queued behind it [s]: a bridge at --speed 0 runs ~10× real
    time, so a planner process that loses the CPU for 0.1 s needs a second of drive time queued"""
    label: str = ""
    """the plan records' ``run`` label (e.g. nominal, refit)"""

    def __post_init__(self) -> None:
        if not 1 <= self.lookahead <= 64:
            raise AxisflowError(f"lookahead = {self.lookahead} moves must be in [1, 64]")
        if not 0.0 <= self.lookahead_s <= 600.0:
            raise AxisflowError(f"lookahead = {self.lookahead_s} s of drive time must be in [0, 600] s")
        if not self.runs:
            raise AxisflowError("the planner node needs at least one case and one law")


class PlannerNode:
    """The node on one session (see the module docstring); use as a context manager."""

    def __init__(
        self,
        session: zenoh.Session,
        settings: NodeSettings,
        params: AxisParams,
        backend: PlannerBackend,
        progress: Callable[[str], None] | None = None,
        stop: threading.Event | None = None,
    ) -> None:
        self.settings, self.params, self.backend = settings, params, backend
        self._session = session
        self._say = progress or (lambda _line: None)
        self._stop = stop or threading.Event()

    def __enter__(self) -> PlannerNode:
        keys = self.settings.keys
        self._sender = MoveSender(self._session, keys)
        self._setpoint = AxisState(self._session, keys, "setpoint", follow=False)
        self._plans = SequencedPublisher(self._session, keys.plan, PLAN_TYPE, Traffic.COMMAND)
        try:
            self._sender.require_bridge(BRIDGE_TIMEOUT_S)
        except AxisflowError:
            self.__exit__()
            raise
        return self

    def __exit__(self, *_exc: object) -> None:
        self._plans.undeclare()
        self._setpoint.close()
        self._sender.close()

    # ---- a run -----------------------------------------------------------------------------------
    def run(self, waypoints_m: Sequence[float]) -> list[RunReport]:
        """Every run of the settings over ``waypoints_m``, one after the other."""
        reports = []
        x_now = self._setpoint.wait(BRIDGE_TIMEOUT_S).position_m
        for run in self.settings.runs:
            self._check_stop()
            report = self._run_one(run, waypoints_m, x_now)
            reports.append(report)
            x_now = float(waypoints_m[-1])
        return reports

    def _run_one(self, run: NodeRun, waypoints_m: Sequence[float], x_now: float) -> RunReport:
        report = RunReport(run, self.backend.name)
        law = polynomial_law(run.law)
        problems = [
            MoveProblem(float(a), float(b), law, run.case, self.settings.omega)
            for a, b in itertools.pairwise(waypoints_m)
        ]
        for p in problems:
            p.check_stroke(self.params)
        self.backend.prepare(problems[0], self.params)
        first = self._plan_exact(
            MoveProblem(x_now, float(waypoints_m[0]), polynomial_law("poly5"), Case.MIN_TIME)
        )
        if not first.zero_move:  # the axis is not within a count of the first way point
            self._send(report, run, 0, first)
        sent = 0
        while sent < len(problems) and self._wants_more(report, running=1):
            sent = self._plan_and_send(report, problems, sent)
        self._follow(report, problems, sent)
        return report

    def _check_stop(self) -> None:
        if self._stop.is_set():
            raise KeyboardInterrupt

    def _plan_and_send(self, report: RunReport, problems: list[MoveProblem], sent: int) -> int:
        """Plan problem ``sent`` and send it, or note it as a zero move; the next problem's index."""
        plan = self._plan(problems[sent])
        if plan.zero_move:
            report.zero_moves.append(sent + 1)
        else:
            self._send(report, report.run, sent + 1, plan)
        return sent + 1

    def _wants_more(self, report: RunReport, running: int) -> bool:
        """Whether fewer than the lookahead's moves (or drive time) are queued behind move ``running``."""
        behind = [m for m in report.moves if m.index > running]
        queued_s = math.fsum(m.plan.duration_s for m in behind)
        return len(behind) < self.settings.lookahead or queued_s < self.settings.lookahead_s

    def _plan(self, problem: MoveProblem) -> PlanResult:
        self._check_stop()
        result = self.backend.solve(problem, self.params)
        if result.status in _REFUSED_STATUSES:
            raise AxisflowError(
                f"the {result.solver} plan of the move {problem.x0_m:.6g} → {problem.x1_m:.6g} m "
                f"({problem.law.name}, {problem.case.value}) failed: status {result.status.value} "
                f"({result.message})"
            )
        if result.max_violation > 0.0:
            raise AxisflowError(
                f"the {result.solver} plan of the move {problem.x0_m:.6g} → {problem.x1_m:.6g} m "
                f"({problem.law.name}, {problem.case.value}) breaks a limit by {result.max_violation:.3g} "
                f"(relative) at the 1 kHz samples: status {result.status.value} ({result.message})"
            )
        return result

    def _plan_exact(self, problem: MoveProblem) -> PlanResult:
        self._check_stop()
        return ExactBackend().solve(problem, self.params)

    def _send(self, report: RunReport, run: NodeRun, index: int, plan: PlanResult) -> None:
        p = plan.problem
        move_id = self._sender.next_move_id
        record = PlanRecord(
            stamp_ns=time.time_ns(),
            axis=self.settings.keys.axis,
            move_id=move_id,
            sender=self._sender.sender_id,
            run=self.settings.label,
            waypoint_index=index,
            case=p.case.value,
            law=p.law.name,
            solver=plan.solver,
            omega=p.omega,
            start_position_m=p.x0_m,
            end_position_m=p.x1_m,
            duration_s=plan.duration_s,
            energy_j=plan.energy_j,
            energy_accounting=self.params.energy_accounting.value,
            objective=plan.objective,
            max_violation=plan.max_violation,
            status=plan.status.value,
            iterations=plan.iterations,
            solve_time_s=plan.solve_time_s,
            certificate=plan.certificate.to_dict() if plan.certificate is not None else {},
        )
        self._plans.put(record.encode(), record.stamp_ns)
        cmd = self._sender.send(p.x0_m, p.x1_m, plan.duration_s, law=p.law.name, move_id=move_id)
        report.moves.append(MoveOutcome(index, cmd, plan))

    def _follow(self, report: RunReport, problems: list[MoveProblem], sent: int) -> None:
        """Wait on the statuses of the run's moves; plan the next one each time one starts."""
        pending = {m.command.move_id: m for m in report.moves}
        while pending or sent < len(problems):
            self._check_stop()
            if not pending:  # nothing runs (the moves so far were zero moves): plan on
                count = len(report.moves)
                sent = self._plan_and_send(report, problems, sent)
                if len(report.moves) > count:
                    pending[report.moves[-1].command.move_id] = report.moves[-1]
                continue
            new = self._sender.poll_status()
            if not new:
                if not self._sender.bridge_alive:
                    raise AxisflowError(f"the bridge of axis {self.settings.keys.axis!r} disappeared mid-run")
                time.sleep(0.0005)
                continue
            for status in new:
                outcome = pending.get(status.move_id)
                if outcome is None:
                    continue
                self._on_status(report, outcome, status)
                if status.state is MoveState.COMPLETED:
                    del pending[status.move_id]
                # the move that started is k: keep the lookahead queued behind it
                while status.state is MoveState.STARTED and sent < len(problems):
                    if not self._wants_more(report, running=outcome.index):
                        break
                    count = len(report.moves)
                    sent = self._plan_and_send(report, problems, sent)
                    if len(report.moves) > count:
                        pending[report.moves[-1].command.move_id] = report.moves[-1]

    def _on_status(self, report: RunReport, outcome: MoveOutcome, status: MoveStatus) -> None:
        if status.state in (MoveState.REJECTED, MoveState.DROPPED, MoveState.STOPPED):
            raise AxisflowError(
                f"the bridge {status.state.name.lower()} move {status.move_id}: {status.text}"
            )
        if status.state is MoveState.ACCEPTED:
            outcome.accepted = status
            # the move sent before it (zero moves in between are not sent)
            k = report.moves.index(outcome)
            before = report.moves[k - 1] if k > 0 and report.moves[k - 1].index > 0 else None
            if before is not None and before.accepted is not None:
                idle = status.start_tick - before.accepted.end_tick
                if idle > 0:
                    raise PlanLateError(
                        f"move {outcome.index} ({report.run.case.value} {report.run.law}) started {idle} "
                        f"ticks after move {before.index} ended: the plan was late (solve "
                        f"{outcome.plan.solve_time_s * 1e3:.2f} ms); use a larger --lookahead or a slower "
                        "bridge"
                    )
        elif status.state is MoveState.COMPLETED:
            outcome.completed = status
            if outcome.index > 0 and outcome.index % 10 == 0:
                self._say(
                    f"  {report.run.case.value} {report.run.law}: move {outcome.index} done, "
                    f"solve {outcome.plan.solve_time_s * 1e3:.2f} ms, slack {outcome.slack_s * 1e3:.0f} ms"
                )
