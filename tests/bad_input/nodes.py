"""Bad input, catalogued: the planner node, the quick stop, the adaptive node and its parameters read
back, the ROS 2 node."""

from __future__ import annotations

from .case import case

CASES = [
    # the planner node, the quick stop
    case(
        "planner: missing way points",
        "planner",
        "--waypoints",
        "missing.txt",
        says=("way point file missing.txt does not exist",),
    ),
    case(
        "planner: way point out of the stroke",
        "planner",
        "--waypoints",
        "outside.txt",
        says=("line 2", "0.9 m is outside the stroke [0, 0.8] m"),
    ),
    case(
        "planner: way point not a number",
        "planner",
        "--waypoints",
        "words.txt",
        says=("line 2", "'abc' is not a number (in m)"),
    ),
    case(
        "planner: too few way points", "planner", "--waypoints", "one.txt", says=("has 1 way points", "2 to")
    ),
    case(
        "planner: omega > 1",
        "planner",
        "--random",
        "5",
        "--omega",
        "2",
        says=("--omega 2.0", "outside [0, 1]"),
    ),
    case(
        "planner: mass 1e308",
        "planner",
        "--random",
        "5",
        "--params",
        "huge-mass.toml",
        says=("m = 1e+308 kg", "outside the physical range [0.001, 10000] kg"),
    ),
    case(
        "planner: a1 beyond any belt",
        "planner",
        "--waypoints",
        "tiny.txt",
        "--params",
        "huge-friction.toml",
        says=("a1 = 1000000.0 N", "[0, 100000] N"),
    ),
    case(
        "planner: negative lookahead",
        "planner",
        "--random",
        "5",
        "--lookahead-s",
        "-1",
        says=("lookahead = -1.0 s", "[0, 600] s"),
    ),
    case("stop: negative timeout", "stop", "--timeout", "-1", says=("--timeout -1 s", "must be > 0 s")),
    # the adaptive node, and reading its parameters back
    case("adapt: window too short", "adapt", "--window", "1", says=("window = 1.0 s", "[2, 3600] s")),
    case(
        "adapt: hold-out over half the window",
        "adapt",
        "--window",
        "10",
        "--holdout",
        "6",
        says=("hold-out = 6 s", "at most half the window = 10 s"),
    ),
    case("adapt: unknown term", "adapt", "--terms", "M_eq,a9", says=("unknown a9", "choose from M_eq")),
    case(
        "adapt: coulomb with a1",
        "adapt",
        "--terms",
        "a1,coulomb",
        says=("coulomb scales a1 and a3 together",),
    ),
    case("adapt: zero duration", "adapt", "--duration", "0", says=("--duration 0 s", "must be > 0 s")),
    case(
        "params: --out without --from",
        "params",
        "--out",
        "p.toml",
        says=("--out and --version", "--from LOG.mcap"),
        untouched=("p.toml",),
    ),
    case(
        "params: a recording without estimates",
        "params",
        "--from",
        "still.mcap",
        "--out",
        "p.toml",
        says=("still.mcap", "no accepted parameter estimate"),
        untouched=("p.toml",),
    ),
    case(
        "params: --out not a .toml",
        "params",
        "--from",
        "still.mcap",
        "--out",
        "p.txt",
        says=("p.txt must end in .toml",),
        untouched=("p.txt",),
    ),
    # the ROS 2 node: refused before any ROS 2 call (no DDS discovery starts)
    case("ros2: rate 0", "ros2", "--rate", "0", says=("rate = 0.0 Hz", "(0, 1000] Hz")),
    case("ros2: rate above the drive's", "ros2", "--rate", "5000", says=("rate = 5000.0 Hz", "(0, 1000] Hz")),
    case("ros2: axis not a ROS 2 name", "ros2", "--axis", "a-0", says=("axis name 'a-0'", "ROS 2 name")),
    case("ros2: omega > 1", "ros2", "--omega", "2", says=("omega = 2.0", "outside [0, 1]")),
]
