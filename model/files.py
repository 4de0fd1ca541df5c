"""Reading inputs and writing result files so that a bad path, a crash or a signal never loses or
half-writes a file. (In the base layer: every command reads and writes files, the views and figures
included.)

Inputs. :func:`check_input_file` turns every way a path can fail (missing, a directory, a name too
long, no permission) into one line naming the path and the reason; :func:`check_distinct_inputs`
refuses one file named twice (the same file under two names, hard or symbolic links included:
files are compared by device and inode, never by name); :func:`read_json` reads a JSON result file
back with the same kind of one-line error.

Outputs. :func:`check_output_dir` and :func:`check_output_file` refuse an unusable output before any
work; :func:`check_output_file` also refuses an output that is one of the command's inputs (whatever
``--overwrite`` says) and an existing file without ``overwrite``. Files are then written whole or not
at all: :func:`atomic_path` hands out a temporary path beside the target, fsyncs what was written
there and renames it onto the target (then fsyncs the folder); on any exception — and the command
line turns SIGTERM and SIGHUP into one (:mod:`axisflow.cli.interrupts`) — the temporary file is
removed. :func:`write_atomic` writes one file that way, :func:`write_atomic_files` several that land
together.
"""

from __future__ import annotations

import errno
import os
import signal
import stat
import tempfile
import threading
from collections.abc import Iterable, Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from .errors import AxisflowError

PART_SUFFIX = ".part"
"""the suffix of :func:`atomic_path`'s temporary files (a leading dot hides them)"""
_PART_NAME_CHARS = 64
"""characters of the target's name kept in its temporary file's name: a target whose name is near
the file system's limit (255 bytes) still gets a temporary file beside it"""
_HELD_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


class InputError(AxisflowError):
    """An input file cannot be used: missing, a directory, unreadable, named twice."""


class OutputError(AxisflowError):
    """An output location cannot be written (not an ``OSError``: a generic ``except OSError`` must not
    swallow it)."""


# ---- inputs ------------------------------------------------------------------------------------------


def _reason(exc: OSError) -> str:
    return exc.strerror or str(exc)


def check_input_file(path: str | Path, what: str = "input") -> Path:
    """``path`` as a Path if it names a readable regular file; else an :class:`InputError` naming it
    (``what`` says what it is: "recording", "log"): it does not exist, is a directory, its name is too
    long, it cannot be read."""
    p = Path(path)
    try:
        st = p.stat()
    except FileNotFoundError:
        raise InputError(f"{what} {p} does not exist") from None
    except OSError as exc:
        raise InputError(f"{what} {p} cannot be read: {_reason(exc)}") from None
    if stat.S_ISDIR(st.st_mode):
        raise InputError(f"{what} {p} is a directory, not a file")
    if not stat.S_ISREG(st.st_mode):
        raise InputError(f"{what} {p} is not a regular file")
    try:
        with open(p, "rb"):
            pass
    except OSError as exc:
        raise InputError(f"{what} {p} cannot be read: {_reason(exc)}") from None
    return p


def file_identity(path: str | Path) -> tuple[int, int] | None:
    """(device, inode) of the file ``path`` names (through symbolic links), or None if it names none.
    Two paths with the same identity are the same file, whatever their names."""
    try:
        st = os.stat(path)
    except (FileNotFoundError, NotADirectoryError):
        return None
    except OSError as exc:
        if exc.errno in (errno.ELOOP, errno.ENAMETOOLONG):
            return None
        raise
    return st.st_dev, st.st_ino


def check_distinct_inputs(paths: Iterable[str | Path], what: str = "input") -> None:
    """An :class:`InputError` if two of ``paths`` are the same file (same name, hard link or symbolic
    link), naming both as given."""
    seen: dict[tuple[int, int], Path] = {}
    for path in paths:
        identity = file_identity(path)
        if identity is None:
            continue
        if identity in seen:
            raise InputError(f"{what} {seen[identity]} and {what} {path} are the same file: give each once")
        seen[identity] = Path(path)


def read_json(path: str | Path, error: type[AxisflowError]) -> Any:
    """The JSON value in the file ``path``: a result file read back. A missing file, one that cannot be
    read or is not JSON raises ``error`` (the reader's own exception) in one line naming the path."""
    import json

    try:
        return json.loads(Path(path).read_text("utf-8"))
    except FileNotFoundError:
        raise error(f"{path} does not exist") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise error(f"{path} cannot be read as JSON: {exc}") from None


# ---- outputs -----------------------------------------------------------------------------------------


def ensure_dir(path: str | Path) -> Path:
    """Create ``path`` (and parents) if needed; a clear error if it is a file or not writable."""
    p = Path(path)
    try:
        p.mkdir(parents=True, exist_ok=True)
    except FileExistsError:
        raise OutputError(f"output directory {p} exists and is not a directory") from None
    except OSError as exc:
        raise OutputError(f"output directory {p} cannot be created: {_reason(exc)}") from None
    return p


def check_output_dir(path: str | Path) -> Path:
    """Fail early, leaving nothing behind, if ``path`` could not be used by :func:`ensure_dir` later:
    it is a file, its name is too long, or its nearest existing ancestor is a file or takes no new
    entries.

    Whether a folder takes new entries is tried (a temporary folder made and removed), not asked:
    ``os.access`` says yes to root on a read-only or virtual file system such as /proc."""
    p = Path(path)
    try:
        exists = p.exists()
    except OSError as exc:
        raise OutputError(f"output directory {p} cannot be created: {_reason(exc)}") from None
    if exists:
        if not p.is_dir():
            raise OutputError(f"output directory {p} exists and is not a directory")
        check_writable(p, f"output directory {p} is not writable")
        return p
    ancestor = p.absolute().parent
    while not ancestor.exists():
        ancestor = ancestor.parent
    if not ancestor.is_dir():
        raise OutputError(f"output directory {p} cannot be created: {ancestor} is not a directory")
    check_writable(ancestor, f"output directory {p} cannot be created: {ancestor} is not writable")
    return p


def check_writable(folder: Path, message: str) -> None:
    """Make and remove a temporary folder in ``folder``; an :class:`OutputError` with ``message`` and
    the system's reason if that fails (tried, not asked: see :func:`check_output_dir`)."""
    try:
        os.rmdir(tempfile.mkdtemp(prefix=".axisflow-write-test-", dir=folder))
    except OSError as exc:
        raise OutputError(f"{message} ({_reason(exc)})") from None


def check_output_file(
    path: str | Path,
    *,
    inputs: Iterable[str | Path] = (),
    overwrite: bool = False,
    suffix: str | None = None,
    what: str = "output",
) -> Path:
    """``path`` if a result file can be written there by :func:`atomic_path`; else an
    :class:`OutputError` naming it. Refused: a name not ending in ``suffix`` (e.g. ``.rrd``), a name
    too long, a directory, a missing or unwritable folder, one of ``inputs`` (the same file under any
    name, even with ``overwrite``), and an existing file unless ``overwrite``. Creates nothing."""
    p = Path(path)
    if suffix is not None and p.suffix != suffix:
        raise OutputError(f"{what} {p} must end in {suffix}")
    try:
        exists = os.path.lexists(p)
        os.stat(p)
    except FileNotFoundError:
        pass
    except OSError as exc:  # a name too long, a loop of links, a path through a file
        raise OutputError(f"{what} {p} cannot be written: {_reason(exc)}") from None
    folder = p.parent
    if not folder.is_dir():
        raise OutputError(f"{what} {p}: folder {folder} does not exist")
    if p.is_dir():
        raise OutputError(f"{what} {p} is a directory, not a file")
    identity = file_identity(p)
    for source in inputs:
        if identity is not None and identity == file_identity(source):
            alias = "" if os.path.abspath(source) == os.path.abspath(p) else " under another name (a link)"
            raise OutputError(
                f"{what} {p} is the input {source}{alias}: an output must never write over an input; "
                "choose another name"
            )
    if exists and not overwrite:
        raise OutputError(f"{what} {p} already exists: choose another name or pass --overwrite")
    check_writable(folder, f"{what} {p}: folder {folder} is not writable")
    return p


def check_output_files(
    folder: str | Path,
    names: Iterable[str],
    *,
    inputs: Iterable[str | Path] = (),
    overwrite: bool = False,
) -> Path:
    """:func:`check_output_dir` for ``folder`` and :func:`check_output_file` for each of its files
    ``names`` that exists already (e.g. params.toml, report.json of an earlier run)."""
    out = check_output_dir(folder)
    sources = list(inputs)
    if out.is_dir():
        for name in names:
            target = out / name
            if os.path.lexists(target):
                check_output_file(target, inputs=sources, overwrite=overwrite)
    return out


# ---- atomic writing ----------------------------------------------------------------------------------


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _fsync_path(path: Path, directory: bool = False) -> None:
    fd = os.open(path, os.O_RDONLY | (os.O_DIRECTORY if directory else 0))
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _new_part(target: Path) -> Path:
    """A new, empty temporary file beside ``target``. Call it with signals held
    (:func:`signals_held`) until its name is stored where the clean-up finds it: a signal in between
    would leave the file behind."""
    fd, tmp = tempfile.mkstemp(
        prefix=f".{target.name[:_PART_NAME_CHARS]}.", suffix=PART_SUFFIX, dir=target.parent
    )
    os.close(fd)
    return Path(tmp)


def _finish_part(part: Path) -> None:
    """Give ``part`` the usual mode of a new file (mkstemp creates 0600) and put its data on disk."""
    os.chmod(part, 0o666 & ~_umask())
    _fsync_path(part)


@contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """A temporary path beside ``path`` to write to (for writers that take a path, e.g. rerun's file
    sink or the MCAP writer); when the block ends normally it is fsynced and renamed onto ``path`` (a
    symbolic link there is replaced, never written through), when it raises — SIGTERM and SIGHUP too,
    through the command line — it is removed. So ``path`` is either the old file or the whole new
    one."""
    target = Path(path)
    part: Path | None = None
    try:
        with signals_held():
            part = _new_part(target)
        yield part
        _finish_part(part)
        os.replace(part, target)
    except BaseException as exc:
        if part is not None:
            part.unlink(missing_ok=True)
        if isinstance(exc, OSError) and part is None:
            raise OutputError(f"cannot write {target}: {_reason(exc)}") from None
        raise
    _fsync_path(target.parent if str(target.parent) else Path("."), directory=True)


@contextmanager
def signals_held() -> Iterator[None]:
    """Within the block, SIGINT, SIGTERM and SIGHUP are noted instead of handled; on leaving it the
    previous handlers are back and each noted signal is raised again (so it acts after the block).
    Only in the main thread, where Python runs its signal handlers; elsewhere a no-op."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {s: signal.getsignal(s) for s in _HELD_SIGNALS}
    restorable = {s: h for s, h in previous.items() if h is not None}
    noted: list[int] = []
    for sig in restorable:
        signal.signal(sig, lambda signum, _frame: noted.append(signum))
    try:
        yield
    finally:
        for sig, handler in restorable.items():
            signal.signal(sig, handler)
        for signum in noted:
            signal.raise_signal(signum)


def _write_part(part: Path, data: str | bytes) -> None:
    if isinstance(data, bytes):
        part.write_bytes(data)
    else:
        part.write_text(data, encoding="utf-8")


def write_atomic(path: str | Path, data: str | bytes) -> Path:
    """Write a whole file via a temporary file in the same directory, fsync and an atomic rename."""
    with atomic_path(path) as part:
        _write_part(part, data)
    return Path(path)


def write_atomic_files(folder: str | Path, files: Mapping[str, str | bytes]) -> list[Path]:
    """Write the files ``{name: content}`` into ``folder`` so that they land together: every one is
    written to its temporary file and fsynced first, then all are renamed with SIGINT, SIGTERM and
    SIGHUP held back (:func:`signals_held`). A failure before the renames leaves none of them.
    Returns the paths written, in order."""
    out = Path(folder)
    parts: dict[Path, Path] = {}
    try:
        for name, data in files.items():
            target = out / name
            with signals_held():
                part = parts[target] = _new_part(target)
            _write_part(part, data)
            _finish_part(part)
        with signals_held():
            for target, part in parts.items():
                os.replace(part, target)
    except OSError as exc:
        raise OutputError(f"cannot write into {out}: {_reason(exc)}") from None
    finally:
        for part in parts.values():
            part.unlink(missing_ok=True)
    _fsync_path(out, directory=True)
    return list(parts)
