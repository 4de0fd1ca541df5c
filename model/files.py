"""Writing result files so that a crash or a bad input never leaves a half-written file: output folders
checked before any work, files written whole or not at all. (In the base layer: every command writes
results, the views and figures included.)"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from .errors import AxisflowError


class OutputError(AxisflowError):
    """An output location cannot be written (not an ``OSError``: a generic ``except OSError`` must not
    swallow it)."""


def ensure_dir(path: str | Path) -> Path:
    """Create ``path`` (and parents) if needed; a clear error if it is a file or not writable."""
    p = Path(path)
    try:
        p.mkdir(parents=True, exist_ok=True)
    except FileExistsError:
        raise OutputError(f"output directory {p} exists and is not a directory") from None
    except OSError as exc:
        raise OutputError(f"output directory {p} cannot be created: {exc.strerror}") from None
    return p


def check_output_dir(path: str | Path) -> Path:
    """Fail early, leaving nothing behind, if ``path`` could not be used by :func:`ensure_dir` later:
    it is a file, or its nearest existing ancestor is a file or takes no new entries.

    Whether a folder takes new entries is tried (a temporary folder made and removed), not asked:
    ``os.access`` says yes to root on a read-only or virtual file system such as /proc."""
    p = Path(path)
    if p.exists():
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
        raise OutputError(f"{message} ({exc.strerror})") from None


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """A temporary path beside ``path`` to write to (for writers that take a path, e.g. rerun's file
    sink); renamed onto ``path`` when the block ends normally, removed when it raises — so ``path`` is
    either the old file or the whole new one."""
    target = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".part", dir=target.parent)
    os.close(fd)
    part = Path(tmp)
    try:
        yield part
        os.chmod(part, 0o666 & ~_umask())  # mkstemp creates 0600; a result file gets the usual mode
        os.replace(part, target)
    except BaseException:
        part.unlink(missing_ok=True)
        raise


def write_atomic(path: str | Path, data: str | bytes) -> Path:
    """Write a whole file via a temporary file in the same directory and an atomic rename."""
    with atomic_path(path) as part:
        if isinstance(data, bytes):
            part.write_bytes(data)
        else:
            part.write_text(data, encoding="utf-8")
    return Path(path)
