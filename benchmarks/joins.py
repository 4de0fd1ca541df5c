"""Joins: a subscriber joining a running bridge, declared at once against joined on facts (hellos).

A bridge process (``axisflow bridge --sim``) runs at ``--speed 0`` (flat out for a keeper subscriber)
and at 1× real time. A fresh session joins it ``--joins`` times and reads ``--seconds`` of its state,
setpoint and event keys, counting the gaps in each publisher's sequence numbers
(:class:`~axisflow.acquisition.wire.sequence.SequenceTracker`). Baseline: the subscriber declared
right after its session opened; against it: :class:`~axisflow.acquisition.bus.readiness.JoinedSubscriber`
(a hello before and after the declaration). The table gives, per way and speed, the joins that lost
samples, the samples lost, and the time the join took (open → ready).
"""

from __future__ import annotations

import argparse
import json
import statistics
import tempfile
import time
from pathlib import Path
from typing import Any

from axisflow.arguments import finite_float, positive_int


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--joins", type=positive_int, default=100, help="joins per row (default 100)")
    parser.add_argument(
        "--seconds", type=finite_float, default=0.3, help="reading time after each join [s] (default 0.3)"
    )


def _join_once(port: int, joined: bool, seconds: float) -> tuple[int, float]:
    """(samples missed, seconds from opening the session to the subscriber being ready)."""
    import zenoh
    from axisflow.acquisition import ZenohOptions, open_session
    from axisflow.acquisition.bus.readiness import JoinedSubscriber
    from axisflow.acquisition.wire.attachment import unpack_attachment
    from axisflow.acquisition.wire.sequence import SequenceTracker

    trackers: dict[str, SequenceTracker] = {}
    t0 = time.monotonic()
    with open_session(ZenohOptions.loopback(connect_port=port)) as session:
        handler = lambda: zenoh.handlers.FifoChannel(1 << 16)  # noqa: E731
        join = JoinedSubscriber(session, "axisflow/a0/*", handler) if joined else None
        if join is not None:
            join.__enter__()
            sub = join.subscriber
        else:
            sub = session.declare_subscriber("axisflow/a0/*", handler())
        ready_s = time.monotonic() - t0
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            sample = sub.try_recv()
            if sample is None:
                time.sleep(0.0005)
                continue
            seq, _stamp, gid = unpack_attachment(sample.attachment.to_bytes())
            trackers.setdefault(str(sample.key_expr), SequenceTracker()).add(gid, seq)
        if join is not None:
            join.__exit__()
        else:
            sub.undeclare()
    return sum(t.missed for t in trackers.values()), ready_s


def run(args: argparse.Namespace) -> int:
    import zenoh
    from axisflow.acquisition import AxisKeys, ZenohOptions, open_session

    from axisflow.deploy.processes import Launcher, free_port

    rows: list[dict[str, Any]] = []
    with tempfile.TemporaryDirectory(prefix="axisflow-joins-") as tmp, Launcher(Path(tmp)) as launcher:
        for speed in ("0", "1"):
            port = free_port()
            bridge = launcher.start(
                f"bridge-{speed}", "bridge", "--sim", "--speed", speed, "--listen", f"tcp/127.0.0.1:{port}",
                ready=True,
            )  # fmt: skip
            launcher.wait_ready(bridge, 60.0)
            with (
                open_session(ZenohOptions.loopback(connect_port=port)) as keeper,
                keeper.declare_subscriber(AxisKeys().state, zenoh.handlers.RingChannel(1)),
            ):
                for joined in (False, True):
                    results = [_join_once(port, joined, args.seconds) for _ in range(args.joins)]
                    missed = [m for m, _s in results]
                    rows.append(
                        {
                            "speed": float(speed),
                            "way": "hellos (JoinedSubscriber)" if joined else "declared at once (baseline)",
                            "joins": len(results),
                            "joins_with_gap": sum(m > 0 for m in missed),
                            "samples_lost": sum(missed),
                            "ready_ms_median": statistics.median(s for _m, s in results) * 1e3,
                        }
                    )
                    if not args.json:
                        r = rows[-1]
                        print(f"  … speed {speed}, {r['way']}: {r['joins_with_gap']} gaps", flush=True)
            launcher.stop(bridge)
    if args.json:
        print(json.dumps({"rows": rows}, indent=1))
        return 0
    print(f"joins of a running bridge ({args.seconds:g} s read after each)")
    print(f"{'speed':>5}  {'way':<30} {'joins':>5} {'with a gap':>10} {'lost':>6} {'ready ms':>9}")
    for r in rows:
        print(
            f"{r['speed']:>5g}  {r['way']:<30} {r['joins']:>5} {r['joins_with_gap']:>10} "
            f"{r['samples_lost']:>6} {r['ready_ms_median']:>9.1f}"
        )
    return 0
