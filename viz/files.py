"""Result files of the views and figures: written atomically, into folders checked before any work.
(No rerun here: the figures need none.)"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from .errors import OutputError


@contextmanager
def atomic_file(path: str | Path) -> Iterator[Path]:
    """A temporary path beside ``path`` to write to; renamed onto ``path`` when the block ends
    normally, removed when it raises — so ``path`` is either the old file or the whole new one."""
    target = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".part", dir=target.parent)
    os.close(fd)
    part = Path(tmp)
    try:
        yield part
        os.chmod(part, 0o666 & ~_umask())  # mkstemp makes 0600; a result file gets the usual mode
        os.replace(part, target)
    except BaseException:
        part.unlink(missing_ok=True)
        raise


def check_output_folder(path: str | Path) -> Path:
    """``path`` if it is a folder that exists or can be created (its nearest existing ancestor is a
    writable folder); else an :class:`OutputError`. Creates nothing."""
    p = Path(path)
    if p.exists():
        if not p.is_dir():
            raise OutputError(f"output folder {p} exists and is not a folder")
        if not os.access(p, os.W_OK | os.X_OK):
            raise OutputError(f"output folder {p} is not writable")
        return p
    ancestor = p.absolute().parent
    while not ancestor.exists():
        ancestor = ancestor.parent
    if not ancestor.is_dir() or not os.access(ancestor, os.W_OK | os.X_OK):
        raise OutputError(f"output folder {p} cannot be created: {ancestor} is not a writable folder")
    return p


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
