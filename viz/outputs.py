"""Where a view goes: an .rrd file (written atomically), a native viewer, or a web viewer served on
loopback — any combination, through one rerun recording stream.

* **File** (``-o FILE.rrd``): the stream is saved to a temporary file beside FILE and renamed onto it
  when the view finished; a failure (bad input found late, Ctrl-C or SIGTERM of a log view, a crash)
  leaves nothing half-written. :func:`check_rrd_path` refuses an unusable FILE before any work: one
  not ending in ``.rrd``, one of the view's inputs, an existing one without ``overwrite``.
* **Viewer** (``--spawn``): the rerun viewer is started as a process of its own (detached: it stays
  when the command ends), its server bound to 127.0.0.1, and the stream connects to it.
* **Web** (``--serve``): ``rerun --serve-web`` as a child process, its gRPC proxy and its web viewer
  both bound to 127.0.0.1 (the SDK's ``serve_grpc``/``serve_web_viewer`` bind every interface); it
  stops when the command ends.

Every rerun process started here runs with ``CI=1`` (the rerun CLI's analytics stay off).
"""

from __future__ import annotations

import os
import resource
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import uuid
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from types import TracebackType
from typing import Any
from urllib.parse import quote

import rerun as rr
import rerun.blueprint as rrb

from ..model.files import OutputError, atomic_path, check_output_file
from .errors import VizError


def _quiet_half_built_streams(previous: Any) -> Any:
    """A ``sys.unraisablehook`` that drops one message and passes on the rest.

    rerun wraps its native streams in :class:`rerun.RecordingStream` objects as it goes (``__new__``,
    then ``inner`` set); a Ctrl-C or SIGTERM that lands between the two leaves a wrapper without
    ``inner``, whose ``__del__`` then prints a traceback ("Exception ignored in … no attribute
    'inner'") under the command's clean one-line stop. Such a wrapper holds nothing to flush. A stop
    that lands inside a stream's ``__del__`` would be printed and lost (an exception there cannot
    propagate): it is delivered to the main thread again instead."""

    def hook(unraisable: Any) -> None:
        exc = unraisable.exc_value
        if getattr(unraisable.object, "__qualname__", "") == "RecordingStream.__del__":
            if isinstance(exc, AttributeError) and getattr(exc, "name", None) == "inner":
                return
            if isinstance(exc, KeyboardInterrupt):  # a stop landed in the stream's flush: deliver it again
                # from another thread, once this hook has returned (raised here, it would be lost too),
                # as a signal to the main thread: it also ends a sleep or a wait the thread is in
                signum = getattr(exc, "signum", signal.SIGINT)
                main = threading.main_thread().ident
                threading.Timer(0.05, signal.pthread_kill, (main, signum)).start()
                return
        previous(unraisable)

    return hook


sys.unraisablehook = _quiet_half_built_streams(sys.unraisablehook)

APPLICATION_ID = "axisflow_view"
LOOPBACK = "127.0.0.1"
VIEWER_START_TIMEOUT_S = 20.0
_STOP_TIMEOUT_S = 5.0
FLUSH_TIMEOUT_S = 60.0
"""how long the final flush may take [s]: rerun's own default waits for ever"""
MIN_FREE_BYTES = 16 * 2**20
"""room an .rrd needs before a view starts [bytes]: rerun's file writer that fails on its first write
makes ``set_sinks`` never return, so the room is checked up front; a writer that fails later makes
the final flush raise, which :class:`RerunOutput` reports (docs/viz.md)"""
RRD_BYTES_PER_LOG_BYTE = 1.5
"""the size of a log view's .rrd over that of its MCAP logs, rounded up from the ratios measured in
docs/viz.md"""


def rerun_env() -> dict[str, str]:
    """The environment of a rerun process we start: ours with analytics off (``CI=1``)."""
    return {**os.environ, "CI": "1", "RUST_LOG": os.environ.get("RUST_LOG", "warn")}


def check_rrd_path(path: str | Path, inputs: Sequence[str | Path] = (), overwrite: bool = False) -> Path:
    """``path`` if an .rrd can be written there: it ends in ``.rrd``, its folder exists and is
    writable, it is no folder, none of ``inputs`` (the same file under any name), and, unless
    ``overwrite``, no existing file; else an :class:`OutputError` naming it. Creates nothing."""
    return check_output_file(path, inputs=inputs, overwrite=overwrite, suffix=".rrd")


def view_size_estimate(logs: Sequence[str | Path]) -> int:
    """About how large the .rrd of a view of ``logs`` will be [bytes] (:data:`RRD_BYTES_PER_LOG_BYTE`
    times their size; a log that is not a file counts 0, it is refused later)."""
    return int(RRD_BYTES_PER_LOG_BYTE * sum(_size(log) for log in logs))


def _size(path: str | Path) -> int:
    try:
        return os.stat(path).st_size
    except OSError:
        return 0


def room_for_file(folder: Path) -> tuple[int, str]:
    """Bytes a new file in ``folder`` may take: the file system's free space for this user, or the
    process's file-size limit (RLIMIT_FSIZE) if lower; with what bounds it."""
    stat = os.statvfs(folder)
    room, why = stat.f_bavail * stat.f_frsize, f"free on the file system of {folder}"
    limit = resource.getrlimit(resource.RLIMIT_FSIZE)[0]
    if limit != resource.RLIM_INFINITY and limit < room:
        room, why = limit, "the process's file-size limit (ulimit -f)"
    return room, why


def check_room(path: Path, needed_bytes: int = 0) -> None:
    """An :class:`OutputError` if ``path`` cannot take ``needed_bytes`` (at least
    :data:`MIN_FREE_BYTES`): see :data:`MIN_FREE_BYTES` for why a view checks before it starts."""
    needed = max(needed_bytes, MIN_FREE_BYTES)
    room, why = room_for_file(path.parent if str(path.parent) else Path("."))
    if room < needed:
        raise OutputError(
            f"output {path}: {room / 1e6:.1f} MB of room ({why}), the view needs about "
            f"{needed / 1e6:.0f} MB: free some space, or write elsewhere with -o"
        )


def check_display() -> None:
    """A :class:`VizError` on a Linux machine without a display, where the native viewer cannot open
    (it would start, listen and die: ``neither WAYLAND_DISPLAY nor … DISPLAY is set``)."""
    if sys.platform.startswith("linux") and not (
        os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
    ):
        raise VizError(
            "--spawn needs a display (neither DISPLAY nor WAYLAND_DISPLAY is set): use -o FILE.rrd, or "
            "--serve for a web viewer on 127.0.0.1"
        )


def _free_port() -> int:
    with socket.socket() as s:
        s.bind((LOOPBACK, 0))
        return s.getsockname()[1]


def _start_rerun(args: list[str]) -> subprocess.Popen:
    """``rerun ARGS`` as a process in a process group of its own (``python -m rerun`` runs the rerun
    binary as its child: stopping it means signalling the group); its error output goes to a temporary
    file (read if it fails)."""
    errors = tempfile.TemporaryFile()  # noqa: SIM115 - owned by the process object, closed with it
    proc = subprocess.Popen(
        [sys.executable, "-m", "rerun", *args],
        stdin=subprocess.DEVNULL,
        stdout=subprocess.DEVNULL,
        stderr=errors,
        env=rerun_env(),
        start_new_session=True,
    )
    proc.errors = errors  # type: ignore[attr-defined]
    return proc


def _wait_listening(proc: subprocess.Popen, port: int, what: str) -> None:
    deadline = time.monotonic() + VIEWER_START_TIMEOUT_S
    while True:
        if proc.poll() is not None:
            proc.errors.seek(0)  # type: ignore[attr-defined]
            err = proc.errors.read().decode("utf-8", "replace").strip()  # type: ignore[attr-defined]
            last = err.splitlines()[-1] if err else "no output"
            raise VizError(f"{what} exited with code {proc.returncode} before listening: {last}")
        with socket.socket() as s:
            s.settimeout(0.2)
            if s.connect_ex((LOOPBACK, port)) == 0:
                return
        if time.monotonic() > deadline:
            raise VizError(f"{what} did not listen on {LOOPBACK}:{port} within {VIEWER_START_TIMEOUT_S:g} s")
        time.sleep(0.05)


def proxy_url(port: int) -> str:
    """The gRPC proxy URL of a rerun server on loopback."""
    return f"rerun+http://{LOOPBACK}:{port}/proxy"


@dataclass(frozen=True)
class ViewOutput:
    """Where the view goes (at least one)."""

    rrd: Path | None = None
    spawn: bool = False
    serve: bool = False
    web_port: int = 0
    """port of the web viewer for ``serve`` (0: a free one)"""
    expected_bytes: int = 0
    """about how large the .rrd will be (e.g. :func:`view_size_estimate`): refused up front if the
    room for it is smaller (and always below :data:`MIN_FREE_BYTES`)"""
    inputs: tuple[Path, ...] = ()
    """the files the view reads: the .rrd must be none of them"""
    overwrite: bool = False
    """replace an existing .rrd (without it, one is refused)"""

    def __post_init__(self) -> None:
        if self.rrd is None and not self.spawn and not self.serve:
            raise VizError("nowhere to send the view: give -o FILE.rrd, --spawn or --serve")
        if self.rrd is not None:
            check_rrd_path(self.rrd, self.inputs, self.overwrite)
            check_room(self.rrd, self.expected_bytes)
        if self.spawn:
            check_display()


class RerunOutput:
    """A recording stream connected to the outputs of a :class:`ViewOutput` (a context manager).

    On a clean exit the stream is flushed and the .rrd renamed into place; on an exception the
    temporary file is removed. A served web viewer stops on exit; a spawned viewer stays.
    """

    def __init__(self, output: ViewOutput, blueprint: rrb.Blueprint | None = None) -> None:
        self.output = output
        self.blueprint = blueprint
        self.rec = rr.RecordingStream(APPLICATION_ID, recording_id=uuid.uuid4())
        self.web_url: str | None = None
        self._file: Any = None
        """the open :func:`atomic_path` context of the .rrd"""
        self._server: subprocess.Popen | None = None

    def __enter__(self) -> RerunOutput:
        sinks: list[object] = []
        try:
            if self.output.rrd is not None:
                self._file = atomic_path(self.output.rrd)
                sinks.append(rr.FileSink(str(self._file.__enter__())))
            if self.output.spawn:
                sinks.append(rr.GrpcSink(self._spawn_viewer()))
            if self.output.serve:
                sinks.append(rr.GrpcSink(self._serve_web()))
            self.rec.set_sinks(*sinks, default_blueprint=self.blueprint)  # type: ignore[arg-type]
        except BaseException:
            self._cleanup(success=False)
            raise
        return self

    def send_blueprint(self, blueprint: rrb.Blueprint) -> None:
        """Make ``blueprint`` the active layout (e.g. when a live view finds another axis)."""
        self.blueprint = blueprint
        self.rec.send_blueprint(blueprint, make_active=True, make_default=True)

    def __exit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        self._cleanup(success=exc_type is None)

    def _cleanup(self, success: bool) -> None:
        start = time.monotonic()
        try:
            self.rec.flush(timeout_sec=FLUSH_TIMEOUT_S)
            self.rec.disconnect()
        except RuntimeError as exc:  # rerun's writer stopped (measured: a file-size limit, EFBIG)
            success = False
            if time.monotonic() - start >= FLUSH_TIMEOUT_S:  # the writer hangs rather than died
                exc.__traceback__ = None  # its frames hold the stream: let it go with the stream
                self._abandon_stream()
            rrd = self.output.rrd
            raise OutputError(
                f"rerun could not finish the view: {str(exc).rstrip('.')} (its own log line above says "
                "why: a full disk, a file-size limit, a viewer gone)"
                + (f"; {rrd} was not written" if rrd is not None else "")
            ) from None
        except BaseException:
            success = False
            raise
        finally:
            self._stop_server()
            file, self._file = self._file, None
            if file is not None:
                if success:
                    file.__exit__(None, None, None)
                else:
                    file.__exit__(VizError, VizError("view not finished"), None)

    def _abandon_stream(self) -> None:
        """Let go of a stream whose file writer does not answer, without waiting for it.

        Measured with a file-size limit, on a loaded machine: now and then rerun's writer thread stops
        in a state where a flush, dropping the stream, or rerun's own shutdown at exit waits for ever
        for an answer the writer will never give. The stream is dropped on a daemon thread instead (if
        that waits, the process ends anyway) and rerun's shutdown at exit is not run; nothing of this
        stream is kept."""
        holder = [self.rec]
        del self.rec
        rr.unregister_shutdown()
        threading.Thread(target=holder.clear, name="rerun-stream-drop", daemon=True).start()

    def _spawn_viewer(self) -> str:
        port = _free_port()
        # not stopped on exit: the viewer stays open after the command
        proc = _start_rerun(["--port", str(port), "--bind", LOOPBACK, "--expect-data-soon"])
        try:
            _wait_listening(proc, port, "the rerun viewer")
        finally:
            proc.errors.close()  # type: ignore[attr-defined]
        return proxy_url(port)

    def _serve_web(self) -> str:
        grpc_port = _free_port()
        web_port = self.output.web_port or _free_port()
        self._server = _start_rerun(
            ["--serve-web", "--bind", LOOPBACK, "--port", str(grpc_port), "--web-viewer-port", str(web_port)]
        )
        _wait_listening(self._server, grpc_port, "the rerun web server")
        _wait_listening(self._server, web_port, "the rerun web server")
        url = proxy_url(grpc_port)
        self.web_url = f"http://{LOOPBACK}:{web_port}/?url={quote(url, safe='')}"
        return url

    def _stop_server(self) -> None:
        proc, self._server = self._server, None
        if proc is None:
            return
        try:
            os.killpg(proc.pid, signal.SIGTERM)  # the wrapper and the rerun binary
            proc.wait(_STOP_TIMEOUT_S)
        except ProcessLookupError:
            pass
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
        proc.errors.close()  # type: ignore[attr-defined]
