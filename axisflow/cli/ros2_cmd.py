"""``axisflow ros2``: the axis as a ROS 2 node (``pip install "axisflow[ros2]"``; docs/ros2.md)."""

from __future__ import annotations

import argparse
import json
import sys

from ..acquisition.wire.keys import DEFAULT_AXIS, DEFAULT_PREFIX, AxisKeys
from ..arguments import add_params_option, add_solver_options, finite_float
from ..model.motion_laws import POLYNOMIAL_LAWS
from ..planner.problem import DEFAULT_OMEGA, Case
from .zenoh_options import add_zenoh_options, zenoh_options_from_args


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "ros2",
        help="the axis as a ROS 2 node: joint states, trajectories, quick stop, diagnostics",
        description="Run a ROS 2 node (rclpy) for a running bridge's axis: it publishes the samples as "
        "sensor_msgs/JointState on /axisflow/<axis>/joint_states, plans the way points of each "
        "trajectory_msgs/JointTrajectory received on /axisflow/<axis>/joint_trajectory with axisflow's "
        "planner and sends them as moves, serves std_srvs/Trigger on /axisflow/<axis>/quick_stop and "
        "/axisflow/<axis>/reset_fault, and publishes the move status and drive faults on /diagnostics. "
        'Needs ROS 2 from wheels: pip install "axisflow[ros2]". DDS discovery follows ROS_DOMAIN_ID and '
        "ROS_AUTOMATIC_DISCOVERY_RANGE (LOCALHOST keeps it on this host). Runs until SIGINT/SIGTERM, then "
        "prints what it relayed and sent (docs/ros2.md).",
    )
    p.add_argument("--axis", default=DEFAULT_AXIS, help=f"axis name (default: {DEFAULT_AXIS})")
    p.add_argument("--prefix", default=DEFAULT_PREFIX, help=f"key prefix (default: {DEFAULT_PREFIX})")
    p.add_argument(
        "--rate",
        type=finite_float,
        default=None,
        metavar="HZ",
        help="JointState messages per second of drive time (default: every sample, 1 kHz)",
    )
    p.add_argument(
        "--case",
        choices=[c.value for c in Case],
        default=Case.MIN_TIME.value,
        help="the planner's objective for a way point without time_from_start (default: min-time)",
    )
    p.add_argument(
        "--law",
        choices=list(POLYNOMIAL_LAWS),
        default="poly5",
        help="motion law of every move (default poly5)",
    )
    p.add_argument(
        "--omega",
        type=finite_float,
        default=DEFAULT_OMEGA,
        help=f"ω of min-time-energy (default {DEFAULT_OMEGA})",
    )
    p.add_argument(
        "--json", action="store_true", help="print the last words as one JSON object (no progress)"
    )
    add_params_option(p)
    add_solver_options(p)
    add_zenoh_options(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..acquisition.bus.session import open_session
    from ..arguments import backend_from_args, params_from_args
    from ..deploy.processes import notify_ready, stop_on_signals
    from ..nodes.ros2.environment import RosEnvironment, require_rclpy
    from ..nodes.ros2.settings import MotionSettings, NodeSettings
    from ..nodes.ros2.trajectory_plan import TrajectoryPlanner

    settings = NodeSettings(
        AxisKeys(args.axis, args.prefix), MotionSettings(Case(args.case), args.law, args.omega), args.rate
    )
    params = params_from_args(args)
    planner = TrajectoryPlanner(backend_from_args(args), params, settings.motion)
    require_rclpy()
    environment = RosEnvironment.from_environ()
    planner.prepare()
    from ..nodes.ros2.node import AxisNode, run_node  # rclpy: only now

    def announce(node: AxisNode) -> None:
        if not args.json:
            names, rate = node.names, "every sample" if args.rate is None else f"{args.rate:g} Hz"
            print(
                f"axisflow ros2: node {names.node} on {environment.describe()}: {settings.keys.state} → "
                f"{names.joint_states} ({rate}); takes {names.joint_trajectory} ({args.case}, {args.law}, "
                f"{planner.backend.name}); serves {names.quick_stop}, {names.reset_fault}; "
                f"diagnostics on {names.diagnostics}",
                file=sys.stderr,
                flush=True,
            )
        notify_ready()

    with stop_on_signals() as stop, open_session(zenoh_options_from_args(args)) as session:
        report = run_node(session, settings, planner, stop, announce)
    print(json.dumps(report.to_dict()) if args.json else report.summary())
    return 0
