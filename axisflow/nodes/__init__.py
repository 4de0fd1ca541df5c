"""The nodes: programs that talk to a bridge over Zenoh as clients of the data path — the online
planner, the adaptive node, the identification excitation's run, and the ROS 2 node."""
