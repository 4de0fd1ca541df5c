"""What drives an axis: ``axisflow_msgs/msg/DriveInfo`` on ``<prefix>/<axis>/drive``.

A bridge publishes it when it starts and then once a second of drive time, so that a program that
joins later (the excitation run, a recorder) learns what it is talking to, and every recording says
what produced it: the simulated axis and its plant profile (``ideal``, ``realistic``, ``warm-up`` or a
user's plant file), or a real drive. The figures and the refit report name it from the recording.
"""

from __future__ import annotations

from dataclasses import dataclass

from .cdr import HEADER_DEPENDENCIES, CdrReader, CdrWriter, read_time, schema_with_dependencies, write_time

DRIVE_INFO_TYPE = "axisflow_msgs/msg/DriveInfo"
DRIVE_INFO_SCHEMA = schema_with_dependencies(
    "# What drives an axis. header.stamp: drive time of the bridge's tick (ns since the Unix epoch);\n"
    "# header.frame_id: the axis name.\n"
    "std_msgs/Header header\n"
    "# the kind of drive: 'simulated' (the built-in simulated axis) or a real drive's name\n"
    "string drive\n"
    "# the simulated axis's plant profile (ideal, realistic, warm-up, or a plant file's own name)\n"
    "string profile\n"
    "# where the plant came from (a packaged file or a path); empty for a real drive\n"
    "string source\n",
    *HEADER_DEPENDENCIES,
)
SIMULATED = "simulated"
PERIOD_TICKS = 1000
"""ticks between two DriveInfo records of a bridge (one second of drive time), from tick 0"""


@dataclass(frozen=True)
class DriveInfo:
    stamp_ns: int
    axis: str
    drive: str
    profile: str = ""
    source: str = ""

    def describe(self) -> str:
        """One line: ``simulated axis, plant realistic (packaged plant_realistic.toml)``."""
        if self.drive == SIMULATED:
            where = f" ({self.source})" if self.source else ""
            return f"simulated axis, plant {self.profile}{where}"
        return self.drive

    def encode(self) -> bytes:
        w = CdrWriter()
        write_time(w, self.stamp_ns)
        w.string(self.axis)
        w.string(self.drive)
        w.string(self.profile)
        w.string(self.source)
        return w.to_bytes()

    @classmethod
    def decode(cls, data: bytes | bytearray | memoryview) -> DriveInfo:
        r = CdrReader(data, DRIVE_INFO_TYPE)
        return cls(read_time(r), r.string(), r.string(), r.string(), r.string())
