"""``axisflow record``: record Zenoh keys to MCAP."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from ..acquisition.logs.chunking import COMPRESSION_NAMES, DEFAULT_BACKLOG_BYTES, DEFAULT_CHUNK_SIZE
from ..acquisition.logs.recorder_config import DEFAULT_QUEUE_CAPACITY, RecorderConfig
from ..acquisition.wire.keys import all_keys
from ..arguments import finite_float, positive_int
from ..deploy.processes import notify_ready, stop_on_signals
from ..model import AxisflowError
from .zenoh_options import add_zenoh_options, zenoh_options_from_args

_SIZE_SUFFIXES = {"": 1, "k": 10**3, "m": 10**6, "g": 10**9}


def byte_size(text: str) -> int:
    """argparse type: a size in bytes with an optional k/M/G suffix (decimal)."""
    t = text.strip().lower().removesuffix("b")
    suffix = t[-1:] if t[-1:] in ("k", "m", "g") else ""
    try:
        value = float(t[: len(t) - len(suffix)]) * _SIZE_SUFFIXES[suffix]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a size (e.g. 500M, 2G)") from None
    if not value >= 1:
        raise argparse.ArgumentTypeError(f"size {text!r} must be >= 1 byte")
    return int(value)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "record",
        help="record Zenoh keys to an MCAP file",
        description="Record every key matching --keys to MCAP (ROS 2 profile, chunk compression). "
        "Stops after --duration or on SIGINT/SIGTERM and prints a summary. A SIGKILL loses at most "
        "the last flush interval; `axisflow recover` rebuilds such a file.",
    )
    p.add_argument("-o", "--output", required=True, metavar="FILE.mcap", help="output file")
    p.add_argument("--keys", default=all_keys(), metavar="EXPR", help="key expression (default: axisflow/**)")
    p.add_argument("--duration", type=finite_float, default=None, metavar="S", help="record for S seconds")
    p.add_argument(
        "--compression", choices=sorted(COMPRESSION_NAMES), default="zstd", help="chunk compression"
    )
    p.add_argument(
        "--flush-interval",
        type=finite_float,
        default=1.0,
        metavar="S",
        help="write+fsync the open chunk every S seconds: the most a crash loses (default 1)",
    )
    p.add_argument("--split-size", type=byte_size, default=None, metavar="SIZE", help="new file past SIZE")
    p.add_argument(
        "--split-duration", type=finite_float, default=None, metavar="S", help="new file every S seconds"
    )
    p.add_argument(
        "--chunk-size",
        type=byte_size,
        default=DEFAULT_CHUNK_SIZE,
        metavar="SIZE",
        help=f"MCAP chunk size before compression (default {DEFAULT_CHUNK_SIZE // 1024} KiB)",
    )
    p.add_argument(
        "--queue",
        type=positive_int,
        default=DEFAULT_QUEUE_CAPACITY,
        metavar="N",
        help=f"receive queue capacity (messages, default {DEFAULT_QUEUE_CAPACITY})",
    )
    p.add_argument(
        "--backlog-mb",
        type=finite_float,
        default=DEFAULT_BACKLOG_BYTES / 2**20,
        metavar="MB",
        help="memory for messages received and not yet written [MiB]: past it, messages are dropped, "
        f"counted per topic, reported and recorded in the file (default {DEFAULT_BACKLOG_BYTES // 2**20})",
    )
    p.add_argument("--json", action="store_true", help="print the summary as one JSON object")
    p.add_argument(
        "--overwrite",
        action="store_true",
        help="replace an existing FILE (or its split files); without it, record refuses to start",
    )
    add_zenoh_options(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..acquisition.bus.session import open_session
    from ..acquisition.logs.recorder import Recorder

    config = RecorderConfig(
        output=Path(args.output),
        keys=args.keys,
        duration_s=args.duration,
        compression=args.compression,
        flush_interval_s=args.flush_interval,
        split_bytes=args.split_size,
        split_duration_s=args.split_duration,
        queue_capacity=args.queue,
        backlog_bytes=_backlog_bytes(args.backlog_mb),
        chunk_size=args.chunk_size,
        overwrite=args.overwrite,
    )
    recorder = Recorder(config)
    with stop_on_signals() as stop, open_session(zenoh_options_from_args(args)) as session:
        summary = recorder.run(session, stop, on_ready=notify_ready)
    print(json.dumps(summary.to_dict(), indent=2) if args.json else summary.format(), flush=True)
    return 0


def _backlog_bytes(mb: float) -> int:
    if not 1.0 <= mb <= 1 << 20:
        raise AxisflowError(f"--backlog-mb {mb:g} must be in 1…{1 << 20} MiB")
    return int(mb * 2**20)
