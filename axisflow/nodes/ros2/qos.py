"""The QoS the axis node offers and asks for: one home for each profile (docs/ros2.md explains them).

**joint_states: reliable, keep last 10 000, volatile.** A reliable publisher matches every subscriber:
reliable ones (``ros2 topic echo``, rosbag2, a node that must count every sample) and best-effort
ones (``qos_profile_sensor_data``), whereas a best-effort publisher would leave reliable subscribers
unmatched and silent. Keep-last 10 000 is ten seconds of samples at 1 kHz (~2 MB): a reliable
subscriber that falls behind by less than that loses nothing (a Python subscriber on a loaded machine
lags by seconds); one that falls further behind loses the oldest. The publisher never waits: a
keep-last history drops, where keep-all would let one slow subscriber hold up the node. A subscriber
that only wants the newest state can ask for best effort and pays nothing for retransmissions.

**joint_trajectory: reliable, keep last 10, volatile** (rclpy's default for a depth of 10): a command
must not be lost, so publishers of trajectories must be reliable (a best-effort publisher does not
match a reliable subscription).

**/diagnostics: reliable, keep last 10, volatile**, as diagnostic_updater and the diagnostic
aggregator use; the node publishes the statuses once a second and at each event, so a late listener
learns them within a second.
"""

from __future__ import annotations

from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

JOINT_STATES_DEPTH = 10_000
"""samples a reliable JointState subscriber may fall behind by without a loss (10 s at 1 kHz)"""


def _reliable(depth: int) -> QoSProfile:
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=depth,
        reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.VOLATILE,
    )


JOINT_STATES_QOS = _reliable(JOINT_STATES_DEPTH)
TRAJECTORY_QOS = _reliable(10)
DIAGNOSTICS_QOS = _reliable(10)
