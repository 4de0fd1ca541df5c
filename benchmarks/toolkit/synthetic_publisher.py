"""The synthetic 1 kHz publisher: N simulated axes ``axisflow/bench<i>`` played into Zenoh from a process
of their own, as bridges would publish them (the pipeline, cell and view benchmarks).

Each tick, each axis's ``state`` (and, with ``--setpoints``, its ``setpoint``) goes out as a JointState
pre-encoded once, with only its stamp patched (the wall clock), through a numbered publisher; at
``--speed`` > 0 on a real-time 1 kHz schedule, at 0 as fast as the subscribers take them (blocking
congestion control). The process waits up to 15 s for a subscriber first; once it has put its last
sample it says so (the launcher's ready byte, when started with ``ready=True``), then waits up to
:data:`CONFIRM_S` for the receipts of the joined subscribers, which learn its last sequence numbers from
them; it prints one JSON line: ``matched``, ``ticks``, ``axes``, ``published``, ``wall_s``,
``late_ticks`` (started more than 2 ms late), ``cpu_s`` (its own CPU time while it published) and
``confirmed`` (whether every receipt came back).

Start it with :data:`ENTRY` and :func:`arguments` through the launcher
(:meth:`~axisflow.deploy.processes.Launcher.start`).
"""

from __future__ import annotations

import argparse
import json
import struct
import time

from axisflow.model import EXECUTION_RATE_HZ

ENTRY = "axisflow.benchmarks.toolkit.synthetic_publisher:main"
"""the launcher's entry point of the publisher process"""
STAMP = struct.Struct("<iI")
"""header.stamp (sec, nanosec), at offset 4 of a CDR JointState"""
CONFIRM_S = 30.0
"""how long the publisher waits for its receipts before it closes its session [s]: a recorder that
was starved may need a while to take its backlog, and the tail it has not taken is lost at the close"""


def arguments(
    endpoint: str, axes: int, seconds: float, speed: float = 1.0, mode: str = "peer", setpoints: bool = False
) -> tuple[str, ...]:
    """The publisher's command line: ``axes`` axes for ``seconds`` of ticks, connecting to ``endpoint``
    as a Zenoh ``mode`` (peer or client); ``speed`` 0: unpaced; ``setpoints``: a setpoint per axis too."""
    extra = ("--setpoints",) if setpoints else ()
    return ("--connect", endpoint, "--mode", mode, "--axes", str(axes), "--seconds", str(seconds),
            "--speed", str(speed), *extra)  # fmt: skip


def payload_template(axis: str) -> bytearray:
    """The JointState every tick of ``axis`` publishes (its stamp patched per tick)."""
    from axisflow.acquisition import AxisSample

    return bytearray(AxisSample(0, axis, 0.4, 0.1, 12.0, 133.0, 33.0, 0.05).encode())


def play(pubs: list, templates: list[bytearray], n_ticks: int, paced: bool) -> tuple[float, int]:
    """Publish ``templates[i]`` on ``pubs[i]`` every tick, each stamped with the wall clock (only the
    stamp patched into the pre-encoded JointState); at 1 kHz if ``paced``, else as fast as possible.
    Returns the wall time [s] and the ticks started more than 2 ms late."""
    late = 0
    t0 = time.monotonic_ns()
    for k in range(n_ticks):
        if paced:
            deadline = t0 + k * 1_000_000
            now = time.monotonic_ns()
            if deadline > now:
                time.sleep((deadline - now) * 1e-9)
            elif now - deadline > 2_000_000:
                late += 1
        stamp = time.time_ns()
        sec_ns = divmod(stamp, 1_000_000_000)
        for pub, buf in zip(pubs, templates, strict=True):
            STAMP.pack_into(buf, 4, *sec_ns)
            pub.put(bytes(buf), stamp)
    return (time.monotonic_ns() - t0) * 1e-9, late


def main() -> None:
    """Entry of the publisher process (its options: :func:`arguments`); prints one JSON line."""
    from axisflow.acquisition import AxisKeys, ZenohOptions, open_session
    from axisflow.acquisition.bus.publisher import (
        SequencedPublisher,
        Traffic,
        confirm_delivered,
        wait_for_subscribers,
    )

    from axisflow.deploy.processes import notify_ready

    parser = argparse.ArgumentParser(prog="synthetic_publisher")
    parser.add_argument("--connect", required=True)
    parser.add_argument("--mode", default="peer")
    parser.add_argument("--axes", type=int, required=True)
    parser.add_argument("--seconds", type=float, required=True)
    parser.add_argument("--speed", type=float, default=1.0)
    parser.add_argument("--setpoints", action="store_true")
    args = parser.parse_args()
    traffic = Traffic.TELEMETRY if args.speed > 0 else Traffic.BULK
    with open_session(ZenohOptions(mode=args.mode, connect=(args.connect,))) as session:
        pubs, templates = [], []
        for i in range(args.axes):
            keys = AxisKeys(f"bench{i}")
            for key in (keys.state, keys.setpoint) if args.setpoints else (keys.state,):
                pubs.append(SequencedPublisher(session, key, "sensor_msgs/msg/JointState", traffic))
                templates.append(payload_template(f"bench{i}"))
        matched = wait_for_subscribers(pubs, 15.0)
        n_ticks = round(args.seconds * EXECUTION_RATE_HZ)
        cpu0 = time.process_time()
        wall, late = play(pubs, templates, n_ticks, paced=args.speed > 0)
        cpu_s = time.process_time() - cpu0
        notify_ready()
        confirmed = confirm_delivered(session, pubs, CONFIRM_S)
        for pub in pubs:
            pub.undeclare()
    published = n_ticks * len(pubs)
    print(json.dumps({"matched": matched, "ticks": n_ticks, "axes": args.axes, "published": published,
                      "wall_s": wall, "late_ticks": late, "cpu_s": cpu_s,
                      "confirmed": confirmed}))  # fmt: skip
