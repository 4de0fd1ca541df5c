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
   ran dry: the plan was late) ends it too, naming the move and the idle ticks — unless the settings
   say to carry on (``stop_when_late`` False: a long benchmark on a busy machine, where an idle stretch
   is counted, :attr:`RunReport.late_moves`, rather than fatal).

A move shorter than one encoder count (a repeated way point, a way point within a count of the one
before) is a zero move (:func:`~axisflow.planner.evaluation.zero_move_result`): nothing is sent or
published for it, and the next move follows the one before it (its start lies within one count of
the axis, inside the bridge's jump tolerance). The report counts such moves.

The node checks its stop event (set by SIGINT/SIGTERM) before each plan and while it waits for
statuses; every solve is bounded (the back-ends' iteration caps and deadlines), so a stop ends a run
within one solve.

**Adapting** (``adapt``: ``axisflow planner --adapt``): the node follows an adaptive node's (``axisflow
adapt``) accepted parameter sets on ``<prefix>/<axis>/params``
(:class:`~axisflow.acquisition.bus.accepted_params.AcceptedParams`): before each plan — between moves,
never during a solve — it takes the newest accepted set (its M_eq and a1…a4 over the node's own
parameters: :meth:`ParamsEstimate.applied_to`), prepares the back-end for it, and plans every following
move with it; each plan record names the version it used (``params_version``; 0: the node's own
parameters). The bridge validates every move against *its* parameters (the node's own, by convention the
same file): a plan that those say breaks a limit — an adapted set with less friction allows a faster
minimum-time move than the bridge's model does — is planned again no faster than the node's own
parameters' minimum time for that move.

Per move it reports the solve time and the **slack**: the drive time between the bridge accepting the
move (the plan ready, sent, validated) and the move's start. Drive time is the bridge's clock: at
``--speed 1`` it is wall time; at ``--speed 0`` the bridge runs as fast as its consumers allow and
the slack shrinks accordingly (use a larger lookahead there).

The node sits above the planner and acquisition layers and uses each as it is: a
:class:`~axisflow.planner.PlannerBackend` and its :class:`~axisflow.planner.PlanResult`, the bridge's
public move API (:class:`~axisflow.acquisition.bus.move_sender.MoveSender`).
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import zenoh

from ..acquisition import PLAN_TYPE, AxisKeys, MoveCommand, MoveState, MoveStatus, PlanRecord
from ..acquisition.bridge.move_queue import CHECK_POINTS
from ..acquisition.bus.accepted_params import AcceptedParams
from ..acquisition.bus.axis_state import AxisState
from ..acquisition.bus.move_sender import BRIDGE_TIMEOUT_S, MoveSender
from ..acquisition.bus.publisher import SequencedPublisher, Traffic
from ..acquisition.errors import WireError
from ..model import AxisflowError, AxisParams, Move, check_limits, polynomial_law
from ..planner import Case, ExactBackend, MoveProblem, PlannerBackend, PlanResult, SolveStatus

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
    params_version: int = 0
    """the parameter set the plan used (0: the node's own; N: an adaptive node's version N)"""

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
    late_moves: list[int] = field(default_factory=list)
    """way point indices k whose move started after the one before had ended (``stop_when_late`` off)"""

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
        versions = sorted({m.params_version for m in moves})
        if versions != [0]:
            head += f", parameter versions {versions[0]}…{versions[-1]}"
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
    adapt: bool = False
    """plan with the newest parameter set an adaptive node accepted (see the module docstring)"""
    stop_when_late: bool = True
    """a move that starts after the one before it ended ends the run (False: counted, the run goes on)"""

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
        self.base_params = params
        """the node's own parameters (version 0; what the bridge validates moves with, by convention)"""
        self.params_version = 0
        """the version of :attr:`params`"""
        self._accepted: AcceptedParams | None = None
        self._refused_version = 0
        self._session = session
        self._say = progress or (lambda _line: None)
        self._stop = stop or threading.Event()

    def __enter__(self) -> PlannerNode:
        keys = self.settings.keys
        self._sender = MoveSender(self._session, keys)
        self._setpoint = AxisState(self._session, keys, "setpoint", follow=False)
        self._plans = SequencedPublisher(self._session, keys.plan, PLAN_TYPE, Traffic.COMMAND)
        try:
            if self.settings.adapt:
                self._accepted = AcceptedParams(self._session, keys, self._stop).__enter__()
            self._sender.require_bridge(BRIDGE_TIMEOUT_S)
        except AxisflowError:
            self.__exit__()
            raise
        return self

    def __exit__(self, *_exc: object) -> None:
        if self._accepted is not None:
            self._accepted.__exit__()
            self._accepted = None
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
        self._take_newest_params(problem)
        result = self.backend.solve(problem, self.params)
        if self.params_version and not result.zero_move:
            result = self._within_base_limits(problem, result)
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

    def _take_newest_params(self, problem: MoveProblem) -> None:
        """Between moves: plan with the newest accepted set of the adaptive node, if there is one."""
        if self._accepted is None:
            return
        record = self._accepted.newest(max(self.params_version, self._refused_version))
        if record is None:
            return
        try:
            params = record.applied_to(self.base_params)
        except WireError as exc:
            self._refused_version = record.version
            self._say(f"  {self.settings.keys.axis}: parameter version {record.version} not taken: {exc}")
            return
        self.params, self.params_version = params, record.version
        self.backend.prepare(problem, params)  # its tables for the new set, outside the timed solve
        self._say(
            f"  {self.settings.keys.axis}: planning with parameter version {record.version} (M_eq "
            f"{params.M_eq:.4g} kg, a1 {params.a1:.4g} N, a2 {params.a2:.4g} N·s/m, a3 {params.a3:.4g} N)"
        )

    def _within_base_limits(self, problem: MoveProblem, result: PlanResult) -> PlanResult:
        """``result`` if the node's own parameters (the bridge's) find it inside the limits; else the
        plan again, no faster than their minimum time for the move."""
        move = Move(problem.x0_m, problem.x1_m, result.duration_s, problem.law)
        report = check_limits(move, self.base_params, min_points=CHECK_POINTS)
        if report.velocity_violation <= 0.0 and report.torque_violation <= 0.0:
            return result
        fastest = ExactBackend().solve(dataclasses.replace(problem, case=Case.MIN_TIME), self.base_params)
        assert problem.t_min_s is not None and problem.t_max_s is not None
        floor = min(max(fastest.duration_s, problem.t_min_s), problem.t_max_s)
        again = self.backend.solve(dataclasses.replace(problem, t_min_s=floor), self.params)
        spent = result.solve_time_s + fastest.solve_time_s + again.solve_time_s
        return dataclasses.replace(again, solve_time_s=spent)

    def _plan_exact(self, problem: MoveProblem) -> PlanResult:
        self._check_stop()
        result = ExactBackend().solve(problem, self.params)
        if self.params_version and not result.zero_move:
            result = self._within_base_limits(problem, result)
        return result

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
            params_version=self.params_version,
        )
        self._plans.put(record.encode(), record.stamp_ns)
        cmd = self._sender.send(p.x0_m, p.x1_m, plan.duration_s, law=p.law.name, move_id=move_id)
        report.moves.append(MoveOutcome(index, cmd, plan, params_version=self.params_version))

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
                if idle > 0 and not self.settings.stop_when_late:
                    report.late_moves.append(outcome.index)
                elif idle > 0:
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
