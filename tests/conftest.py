"""Fixtures for every test package: free loopback ports, `axisflow` subprocesses, MCAP reading."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import time
from pathlib import Path
from typing import ClassVar

import pytest
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory

CLI = [sys.executable, "-c", "import sys; from axisflow.cli import main; sys.exit(main())"]
ENV = {**os.environ, "CI": "1", "RUST_LOG": "error"}


def free_port() -> int:
    """A TCP port on 127.0.0.1 that was free a moment ago."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Cli:
    """``axisflow`` subprocesses and MCAP reading (a fixture, so tests import nothing from here)."""

    @staticmethod
    def free_port() -> int:
        return free_port()

    started: ClassVar[list[subprocess.Popen]] = []
    """every process of :meth:`start`; the autouse fixture kills those still running after a test"""

    @staticmethod
    def start(*args: str) -> subprocess.Popen:
        """Start ``axisflow ARGS`` in the background (text output captured; killed after the test)."""
        proc = subprocess.Popen(
            [*CLI, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV
        )
        Cli.started.append(proc)
        return proc

    @staticmethod
    def kill_leftovers() -> None:
        """Kill and reap every started process still running (a failed test did not stop it)."""
        for proc in Cli.started:
            if proc.poll() is None:
                proc.kill()
                proc.communicate()
        Cli.started.clear()

    @staticmethod
    def run(*args: str, timeout: float = 120.0) -> subprocess.CompletedProcess:
        """Run ``axisflow ARGS``; raises TimeoutExpired (fails the test) if it does not exit in time."""
        return subprocess.run([*CLI, *args], capture_output=True, text=True, timeout=timeout, env=ENV)

    @staticmethod
    def finish(proc: subprocess.Popen, timeout: float = 60.0) -> tuple[str, str]:
        """Wait for a started process; fails the test (after killing it) if it hangs."""
        try:
            return proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            proc.kill()
            out, err = proc.communicate()
            pytest.fail(f"process did not exit within {timeout} s\nstdout:\n{out}\nstderr:\n{err}")

    @staticmethod
    def wait_for_file(path: Path, timeout: float = 10.0) -> None:
        deadline = time.monotonic() + timeout
        while not (path.exists() and path.stat().st_size > 0):
            if time.monotonic() > deadline:
                pytest.fail(f"{path} did not appear within {timeout} s")
            time.sleep(0.05)

    @staticmethod
    def decoded(path: Path, topic: str) -> list:
        """(mcap message, decoded ROS message) pairs of ``topic`` from a complete MCAP file."""
        with open(path, "rb") as fh:
            reader = make_reader(fh, decoder_factories=[DecoderFactory()])
            return [(m, d) for _s, _c, m, d in reader.iter_decoded_messages(topics=[topic])]


@pytest.fixture(scope="session")
def cli() -> Cli:
    return Cli()


@pytest.fixture(autouse=True)
def _no_leftover_processes():
    """After each test (pass or fail), no process started through ``cli.start`` keeps running."""
    yield
    Cli.kill_leftovers()


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
