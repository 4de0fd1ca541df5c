"""Fixtures for every test package: `axisflow` processes (through axisflow's own launcher), free
loopback ports, MCAP reading, and waiting on facts."""

from __future__ import annotations

from pathlib import Path

import pytest
from axisflow.acquisition import RecordingError, iter_recording
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory

from axisflow.deploy.processes import Child, Exited, Launcher, free_port, wait_until


class Cli:
    """``axisflow`` processes of one test, started by a :class:`~axisflow.deploy.processes.Launcher` (their
    output goes to files; they end with the test process, however it ends), and MCAP reading."""

    def __init__(self, launcher: Launcher) -> None:
        self.launcher = launcher

    @staticmethod
    def free_port() -> int:
        return free_port()

    def start(self, *args: str, ready: bool = False) -> Child:
        """Start ``axisflow ARGS`` in the background (stopped after the test if still running);
        ``ready``: it says when it is ready (:meth:`wait_ready`: the recorder once it has joined, the
        bridge once it holds its token)."""
        return self.launcher.start(args[0] if args else "axisflow", *args, ready=ready)

    def wait_ready(self, proc: Child, timeout: float = 30.0) -> None:
        """Return once a process started with ``ready=True`` is ready; fail the test if it exits or
        stays silent."""
        try:
            self.launcher.wait_ready(proc, timeout)
        except Exception as exc:
            pytest.fail(str(exc))

    def run(self, *args: str, timeout: float = 120.0) -> Exited:
        """Run ``axisflow ARGS`` to its end; fails the test if it does not exit in time."""
        return self.finish_exited(self.start(*args), timeout)

    def finish(self, proc: Child, timeout: float = 60.0) -> tuple[str, str]:
        """Wait for a started process: its (stdout, stderr); fails the test (after killing it) if it
        hangs."""
        end = self.finish_exited(proc, timeout)
        return end.stdout, end.stderr

    def finish_exited(self, proc: Child, timeout: float = 60.0) -> Exited:
        end = self.launcher.wait(proc, timeout)
        if end.timed_out:
            output = f"stdout:\n{end.stdout}\nstderr:\n{end.stderr}"
            pytest.fail(f"{proc.command} did not exit within {timeout} s\n{output}")
        return end

    @staticmethod
    def wait_for_file(path: Path, timeout: float = 10.0) -> None:
        if not wait_until(lambda: path.exists() and path.stat().st_size > 0, timeout):
            pytest.fail(f"{path} did not appear within {timeout} s")

    @staticmethod
    def on_disk(path: Path, topic: str | None = None) -> int:
        """Messages (of ``topic``) flushed to a recording so far, read as a stream (0 before the file
        or its header is written)."""
        try:
            return sum(1 for r in iter_recording(path) if topic is None or r.channel.topic == topic)
        except RecordingError:
            return 0

    @staticmethod
    def decoded(path: Path, topic: str) -> list:
        """(mcap message, decoded ROS message) pairs of ``topic`` from a complete MCAP file."""
        with open(path, "rb") as fh:
            reader = make_reader(fh, decoder_factories=[DecoderFactory()])
            return [(m, d) for _s, _c, m, d in reader.iter_decoded_messages(topics=[topic])]


@pytest.fixture(scope="session")
def _launcher(tmp_path_factory):
    with Launcher(tmp_path_factory.mktemp("processes")) as launcher:
        yield launcher


@pytest.fixture(scope="session")
def cli(_launcher) -> Cli:
    return Cli(_launcher)


@pytest.fixture(autouse=True)
def _no_leftover_processes(_launcher):
    """After each test (pass or fail), no process started through ``cli.start`` keeps running: SIGINT,
    then a kill after 5 s."""
    yield
    _launcher.stop_running(timeout_s=5.0)


@pytest.fixture
def port() -> int:
    return free_port()


class ChunkDamage:
    """Copies of a real MCAP file with one chunk damaged on disk (a fixture: ``damage``)."""

    HOW = ("flip", "crc", "truncate")
    """bytes flipped in the compressed data, a wrong CRC in the chunk header, the compressed data cut
    short (the chunk's records_length halved; the record framing stays intact)"""

    @staticmethod
    def chunks(path: Path) -> list[tuple[int, int, int]]:
        """(record offset, data offset, data length) of each Chunk record, in file order."""
        data = path.read_bytes()
        out, pos = [], 8
        while pos + 9 <= len(data):
            opcode = data[pos]
            length = int.from_bytes(data[pos + 1 : pos + 9], "little")
            if opcode == 0x06:
                name_length = int.from_bytes(data[pos + 37 : pos + 41], "little")
                at = pos + 41 + name_length
                out.append((pos, at + 8, int.from_bytes(data[at : at + 8], "little")))
            if opcode == 0x02:  # footer
                break
            pos += 9 + length
        return out

    @staticmethod
    def damage(src: Path, dst: Path, chunk: int, how: str) -> int:
        """Write ``src`` to ``dst`` with chunk number ``chunk`` (from 0) damaged ``how``; returns the
        chunk's byte offset."""
        data = bytearray(src.read_bytes())
        record, start, length = ChunkDamage.chunks(src)[chunk]
        if how == "flip":
            middle = start + length // 2
            data[middle : middle + 16] = bytes(b ^ 0xFF for b in data[middle : middle + 16])
        elif how == "crc":
            crc = int.from_bytes(data[record + 33 : record + 37], "little")
            data[record + 33 : record + 37] = ((crc + 1) & 0xFFFFFFFF).to_bytes(4, "little")
        elif how == "truncate":
            data[start - 8 : start] = (length // 2).to_bytes(8, "little")
        else:
            raise ValueError(f"unknown damage {how!r}")
        dst.write_bytes(bytes(data))
        return record


@pytest.fixture(scope="session")
def damage() -> type[ChunkDamage]:
    return ChunkDamage


@pytest.fixture
def eventually():
    """``eventually(predicate, timeout_s, what)``: poll ``predicate`` until it holds; fail the test
    naming ``what`` if it does not within ``timeout_s``."""

    def wait(predicate, timeout_s: float = 10.0, what: str = "the condition") -> None:
        if not wait_until(predicate, timeout_s):
            pytest.fail(f"{what} did not hold within {timeout_s:g} s")

    return wait
