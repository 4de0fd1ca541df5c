"""The rclpy node of one axis (see :mod:`axisflow.nodes.ros2` for its topics and services).

Threads: rclpy's executor runs on the caller's thread (:meth:`AxisNode.spin`): the trajectory
subscription, the two services and two timers — one polls the bridge's statuses every
:data:`POLL_PERIOD_S` (diagnostics, the trajectories' progress), one publishes the diagnostics every
``diagnostics_period_s``. The samples go from Zenoh to the JointState publisher on the relay's own
thread (:mod:`.joint_state_relay`). A service call waits for the bridge's answer on the executor's
thread, polling the statuses itself.

:func:`run_node` owns the rclpy context (made and shut down here: nothing global; rclpy installs no
signal handler, the command's own SIGINT/SIGTERM handling stops the spin).
"""

from __future__ import annotations

import datetime
import threading
import time
from collections.abc import Callable
from contextlib import ExitStack
from dataclasses import asdict, dataclass
from typing import Any

import rclpy
import zenoh
from diagnostic_msgs.msg import DiagnosticArray
from rclpy.executors import SingleThreadedExecutor
from rclpy.signals import SignalHandlerOptions
from sensor_msgs.msg import JointState
from std_srvs.srv import Trigger
from trajectory_msgs.msg import JointTrajectory

from ...acquisition.bus.axis_state import AxisState
from ...acquisition.bus.move_sender import MoveSender
from ...acquisition.wire.move_status import MoveState, MoveStatus
from ...model import AxisflowError
from .axis_commands import AxisCommands
from .axis_health import DRIVE_EVENT_LEVELS, MOVE_LEVELS, AxisHealth, Level
from .event_watch import EventWatch
from .joint_state_relay import JointStateRelay
from .qos import DIAGNOSTICS_QOS, JOINT_STATES_QOS, TRAJECTORY_QOS
from .ros_messages import diagnostic_array
from .settings import NodeSettings
from .trajectory_plan import TrajectoryPlanner
from .trajectory_request import read_trajectory

POLL_PERIOD_S = 0.01
"""how often the node reads the bridge's statuses [s]"""
SPIN_TIMEOUT_S = 0.1
"""the longest the executor waits before the node looks at its stop event [s]"""


@dataclass(frozen=True)
class NodeReport:
    """What a node did, for the command's last words."""

    samples_received: int
    samples_published: int
    samples_lost: int
    samples_malformed: int
    trajectories_sent: int
    trajectories_refused: int
    trajectories_done: int
    moves_sent: int
    quick_stops: int

    def summary(self) -> str:
        return (
            f"{self.samples_published} JointState published of {self.samples_received} samples received "
            f"({self.samples_lost} lost on Zenoh, {self.samples_malformed} malformed); "
            f"{self.trajectories_sent} trajectories sent ({self.moves_sent} moves, "
            f"{self.trajectories_done} done), {self.trajectories_refused} refused; "
            f"{self.quick_stops} quick stops"
        )

    def to_dict(self) -> dict[str, int]:
        return asdict(self)


class AxisNode:
    """The node of one axis on a Zenoh session (use as a context manager, then :meth:`spin`)."""

    def __init__(
        self,
        context: Any,
        session: zenoh.Session,
        settings: NodeSettings,
        planner: TrajectoryPlanner,
        stop: threading.Event,
    ) -> None:
        self.settings, self.planner = settings, planner
        self._context, self._session, self._stop = context, session, stop
        self.names = settings.names
        self.health = AxisHealth(self.names.node, settings.keys.axis)
        self.quick_stops = 0

    def __enter__(self) -> AxisNode:
        with ExitStack() as stack:
            keys, names = self.settings.keys, self.names
            self.node = rclpy.create_node(names.node, context=self._context)
            stack.callback(self.node.destroy_node)
            self.log = self.node.get_logger()
            self._joint_states = self.node.create_publisher(JointState, names.joint_states, JOINT_STATES_QOS)
            self._diagnostics = self.node.create_publisher(
                DiagnosticArray, names.diagnostics, DIAGNOSTICS_QOS
            )
            # the event watch before the sender: its hello covers the watch's declaration too
            self._events = stack.enter_context(EventWatch(self._session, keys))
            sender = stack.enter_context(MoveSender(self._session, keys))
            setpoint = stack.enter_context(AxisState(self._session, keys, "setpoint"))
            self.commands = AxisCommands(sender, setpoint, self.planner)
            self.relay = stack.enter_context(
                JointStateRelay(self._session, keys, self._joint_states, self.settings.rate_hz, self._stop)
            )
            self.node.create_subscription(
                JointTrajectory, names.joint_trajectory, self._on_trajectory, TRAJECTORY_QOS
            )
            self.node.create_service(Trigger, names.quick_stop, self._on_quick_stop)
            self.node.create_service(Trigger, names.reset_fault, self._on_reset_fault)
            self.node.create_timer(POLL_PERIOD_S, self._poll)
            self.node.create_timer(self.settings.diagnostics_period_s, self._publish_diagnostics)
            self._exit = stack.pop_all()
        return self

    def __exit__(self, *_exc: object) -> None:
        self._exit.close()

    def spin(self, executor: Any) -> None:
        """Run the node's callbacks until the stop event is set."""
        executor.add_node(self.node)
        try:
            self._publish_diagnostics()
            while not self._stop.is_set():
                executor.spin_once(timeout_sec=SPIN_TIMEOUT_S)
        finally:
            executor.remove_node(self.node)

    def report(self) -> NodeReport:
        trajectories = self.commands.trajectories
        return NodeReport(
            samples_received=self.relay.received,
            samples_published=self.relay.published,
            samples_lost=self.relay.lost,
            samples_malformed=self.relay.malformed,
            trajectories_sent=len(trajectories),
            trajectories_refused=self.health.refusals,
            trajectories_done=sum(1 for t in trajectories if t.done),
            moves_sent=sum(len(t.move_ids) for t in trajectories),
            quick_stops=self.quick_stops,
        )

    # ---- statuses and diagnostics --------------------------------------------------------------------
    def _poll(self) -> None:
        self._poll_statuses()

    def _poll_statuses(self) -> list[MoveStatus]:
        """Read the bridge's statuses and the liveliness of its token; publish the diagnostics if they
        changed. Returns the statuses read."""
        statuses = self._events.poll()
        self.commands.drain()
        alive = self.commands.sender.bridge_alive
        changed = self.health.bridge(alive)
        if changed and not alive:
            self.commands.bridge_lost()
            self.log.error(f"the bridge of axis {self.settings.keys.axis!r} is gone")
        for status in statuses:
            self.health.on_status(status, self.commands.on_status(status))
            self._log_status(status)
        if statuses or changed:
            self._publish_diagnostics()
        return statuses

    def _log_status(self, status: MoveStatus) -> None:
        level = DRIVE_EVENT_LEVELS.get(status.state, MOVE_LEVELS.get(status.state))
        if level is Level.ERROR:
            self.log.error(status.text)
        elif level is Level.WARN:
            self.log.warning(status.text)

    def _publish_diagnostics(self) -> None:
        if self.relay.last_arrival_s is not None:
            self.health.sample_arrived(self.relay.last_arrival_s)
        self.health.bridge(self.commands.sender.bridge_alive)
        statuses = self.health.statuses(self.relay.counts())
        self._diagnostics.publish(diagnostic_array(statuses, time.time_ns()))

    # ---- callbacks ---------------------------------------------------------------------------------
    def _on_trajectory(self, message: JointTrajectory) -> None:
        try:
            sent = self.commands.submit(read_trajectory(message))
        except AxisflowError as exc:
            self.log.warning(f"trajectory refused: {exc}")
            self.health.on_refusal(str(exc))
            self._publish_diagnostics()
            return
        plan = sent.plan
        line = (
            f"trajectory {sent.number}: {len(sent.move_ids)} moves through {len(plan.moves)} way points "
            f"from {plan.start_position_m:.6g} m, {plan.duration_s:.6g} s, {plan.energy_j:.4g} J (model)"
        )
        self.log.info(line)
        if not sent.move_ids:
            line = f"trajectory {sent.number} done: the axis is at its way points already"
        self.health.on_motion(Level.OK, line)
        self._publish_diagnostics()

    def _on_quick_stop(self, _request: Trigger.Request, response: Trigger.Response) -> Trigger.Response:
        return self._answer(
            response, lambda: self.commands.quick_stop("ROS 2 quick_stop", self._poll_statuses)
        )

    def _on_reset_fault(self, _request: Trigger.Request, response: Trigger.Response) -> Trigger.Response:
        return self._answer(response, lambda: self.commands.reset_fault(self._poll_statuses), reset=True)

    def _answer(
        self, response: Trigger.Response, call: Callable[[], MoveStatus], reset: bool = False
    ) -> Trigger.Response:
        try:
            status = call()
        except AxisflowError as exc:
            response.success, response.message = False, str(exc)
            self.log.error(str(exc))
            return response
        if reset:
            response.success = status.state is MoveState.ENABLED
            response.message = status.text
        else:
            self.quick_stops += 1
            response.success = True
            response.message = (
                f"{status.text} (bridge tick {status.tick}, drive time {_iso(status.stamp_ns)})"
            )
            sample = self.commands.setpoint.latest()
            if sample is not None:
                response.message += f"; setpoint {sample.position_m:.6g} m"
        self.log.info(response.message)
        return response


def _iso(stamp_ns: int) -> str:
    seconds, ns = divmod(stamp_ns, 1_000_000_000)
    when = datetime.datetime.fromtimestamp(seconds, datetime.UTC).strftime("%Y-%m-%dT%H:%M:%S")
    return f"{when}.{ns:09d}Z"


def run_node(
    session: zenoh.Session,
    settings: NodeSettings,
    planner: TrajectoryPlanner,
    stop: threading.Event,
    ready: Callable[[AxisNode], None] | None = None,
) -> NodeReport:
    """Run the node of ``settings`` on ``session`` until ``stop`` is set; ``ready`` is called once
    the node has joined its keys and made its ROS 2 entities."""
    context = rclpy.Context()
    rclpy.init(context=context, signal_handler_options=SignalHandlerOptions.NO)
    try:
        executor = SingleThreadedExecutor(context=context)
        try:
            with AxisNode(context, session, settings, planner, stop) as node:
                if ready is not None:
                    ready(node)
                node.spin(executor)
                return node.report()
        finally:
            executor.shutdown()
    finally:
        context.try_shutdown()
