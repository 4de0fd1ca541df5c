"""The axis as a ROS 2 node: ``axisflow ros2 --axis A`` (``pip install "axisflow[ros2]"``).

One rclpy node per axis bridges axisflow's Zenoh keys and ROS 2 (docs/ros2.md):

==============================================  ===================================================
ROS 2                                           axisflow
==============================================  ===================================================
``/axisflow/<axis>/joint_states``               the bridge's 1 kHz samples (``<prefix>/<axis>/state``),
(``sensor_msgs/msg/JointState``, published)     every one or decimated to ``--rate``, drive stamps
``/axisflow/<axis>/joint_trajectory``           way points planned by axisflow's planner and sent as
(``trajectory_msgs/msg/JointTrajectory``, taken) moves (``<prefix>/<axis>/trajectory``)
``/axisflow/<axis>/quick_stop``,                a quick stop (``<prefix>/<axis>/stop``), with the
``/axisflow/<axis>/reset_fault``                drive's fault reset for the second
(``std_srvs/srv/Trigger``, served)
``/diagnostics``                                the bridge's move status and drive events
(``diagnostic_msgs/msg/DiagnosticArray``)       (``<prefix>/<axis>/event``), as levels
==============================================  ===================================================

Modules, one concept each:

* :mod:`.names` — the topic, service and node names of an axis;
* :mod:`.settings` — what a node is told (axis, rate, planner options);
* :mod:`.trajectory_request` — a JointTrajectory read as way points;
* :mod:`.trajectory_plan` — way points planned into moves;
* :mod:`.axis_commands` — trajectories, quick stops and fault resets sent and followed;
* :mod:`.axis_health` — the bridge's statuses as diagnostic levels;
* :mod:`.event_watch` — the bridge's statuses from Zenoh;
* :mod:`.joint_state_relay` — the samples from Zenoh to ROS 2;
* :mod:`.qos` — the QoS the node offers and asks for;
* :mod:`.ros_messages` — our records as ROS 2 messages;
* :mod:`.node` — the rclpy node and its run;
* :mod:`.environment` — the ROS 2 environment a node runs in;
* :mod:`.private_network` — a private network namespace for DDS runs that must stay on this machine.

rclpy is imported only by :mod:`.qos`, :mod:`.ros_messages`, :mod:`.joint_state_relay` and
:mod:`.node`, so the rest (and ``import axisflow.nodes.ros2``) works without ROS 2 installed.
"""

from .errors import Ros2Error, Ros2UnavailableError, TrajectoryRefusedError

__all__ = ["Ros2Error", "Ros2UnavailableError", "TrajectoryRefusedError"]
