"""A synthetic recording of a cell: several axes in one MCAP file, as one recorder writes them."""

from __future__ import annotations

import heapq
import tempfile
from collections.abc import Sequence
from pathlib import Path

from axisflow.acquisition import iter_recording
from axisflow.acquisition.logs.mcap_writer import Ros2McapWriter
from axisflow.acquisition.logs.synthetic_log import SyntheticLogSpec, write_synthetic_log


def write_cell_log(path: Path, specs: Sequence[SyntheticLogSpec]) -> Path:
    """The synthetic logs of ``specs`` (one axis each) merged into one file at ``path``, their
    messages in the order of their log times (as one recorder would have written them)."""
    with tempfile.TemporaryDirectory() as tmp:
        parts = [write_synthetic_log(Path(tmp) / f"{i}.mcap", spec).path for i, spec in enumerate(specs)]
        streams = [((r.message.log_time, i, r) for r in iter_recording(part)) for i, part in enumerate(parts)]
        writer = Ros2McapWriter(path)
        for _log_time, _i, r in heapq.merge(*streams, key=lambda item: (item[0], item[1])):
            channel = writer.channel_for(r.channel.topic, r.schema.name if r.schema else None)
            m = r.message
            writer.add(channel, m.log_time, m.publish_time, m.sequence, m.data)
        writer.finish()
    return path
