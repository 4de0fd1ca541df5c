"""Faults: the data path's processes killed, fuzzed, flooded and starved; what survives, counted.

Every scenario runs real processes — ``axisflow bridge --sim``, ``record``, ``planner``, ``recover``,
started by axisflow's :class:`~axisflow.deploy.processes.Launcher` on free loopback ports — with real
Zenoh sessions and real MCAP files, measures what happened, and returns a result object: the numbers,
the contract it checks (``passed``) and the command that reproduces it (:mod:`.outcome`).
tests/benchmarks/fault_scenarios asserts on the same objects; ``axisflow bench faults [--json]`` runs
them and prints them as one table (docs/trust.md has a measured one). A rig of the benchmarks and the
tests, not a part of the product. One scenario per module:

===================  ==========================================================================
scenario             fault → what must hold
===================  ==========================================================================
:mod:`.recorder_kill` recorder SIGKILL mid-session → ≤ 1 s of the bridge's samples lost (flush +
                     fsync every second), ``axisflow recover`` gives a file rosbags and rerun open
:mod:`.bridge_kill`  bridge SIGKILL mid-move → the recording so far complete; the recorder lists
                     the restarted bridge as a new publisher; the restart (same ``--plant-state``)
                     starts at rest where the axis coasted to
:mod:`.planner_kill` planner SIGKILL → its queued moves dropped, the axis at rest within [0, L]
                     (the test is tests/nodes/test_planner_restart.py)
:mod:`.bad_payloads` ≥ 1000 malformed, truncated, oversized, random payloads on the trajectory key
                     from a live sender and from a session that is not one → each rejected with a
                     reason; every tick recorded, 1 ms apart
:mod:`.move_flood`   thousands of valid moves → the queue holds MAX_QUEUED_MOVES, the rest "queue
                     is full"; the bridge's memory flat; telemetry complete
:mod:`.session_faults` a full disk, a second recorder on the same file, 30 Zenoh peers coming and
                     going → a clear outcome each; the first recording complete
:mod:`.quick_stop`   a quick stop at full speed → distance and time against the physical minimum
===================  ==========================================================================

Shared parts: :mod:`.rig` (the processes and what watches them), :mod:`.ticks` (a recording tick by
tick), :mod:`.payloads` (the bad payloads).
"""
