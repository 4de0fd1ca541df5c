"""Bad input of `axisflow savings` and the baseline laws of `axisflow plan`."""

from __future__ import annotations

from .case import case

CASES = [
    case(
        "savings: a log without moves",
        "savings",
        "still.mcap",
        "--model-only",
        "--out",
        "sv",
        says=("still.mcap", "no move that ran on axis 'a0'", "nothing to compare"),
        untouched=("sv",),
    ),
    case(
        "savings: a velocity limit above v_max",
        "savings",
        "--random",
        "5",
        "--limits",
        "2,1",
        "--out",
        "sv",
        says=("baseline velocity limit 2 m/s", "v_max = 1.5 m/s"),
        untouched=("sv",),
    ),
    case(
        "savings: an acceleration the torque cannot give after friction",
        "savings",
        "--random",
        "5",
        "--limits",
        "1.5,5,50",
        "--out",
        "sv",
        says=("baseline acceleration limit 5 m/s²", "at 1.5 m/s: 3.04 m/s²", "tau_max = 4 N·m"),
        untouched=("sv",),
    ),
    case(
        "savings: an unknown baseline",
        "savings",
        "--random",
        "5",
        "--baseline",
        "sine",
        "--out",
        "sv",
        says=("--baseline", "'sine'", "trapezoid", "scurve"),
        untouched=("sv",),
    ),
    case(
        "plan: a baseline's velocity limit above v_max",
        "plan",
        "0.1",
        "0.5",
        "--law",
        "trapezoid",
        "--limits",
        "2,1",
        says=("baseline velocity limit 2 m/s", "v_max = 1.5 m/s"),
    ),
]
