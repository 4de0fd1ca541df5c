"""Writing a folder of keys and configurations all at once, or not at all.

Every file is first written into a private temporary folder (mode 0700) beside the target, each
through the atomic writer of :mod:`axisflow.model.files` and given its exact mode (private keys 0600)
there, where no one else can see it. Then either the temporary folder is renamed onto the target
(:meth:`FolderWriter.commit`: a new folder, or one replaced as a whole) or its files are renamed into
the existing target one by one (:meth:`FolderWriter.merge`, which takes the already moved ones back
out on failure). On any error the temporary folder is removed: nothing is left half-written.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from ...model.files import atomic_path, check_writable
from .errors import SecurityError

PRIVATE_MODE = 0o600
PUBLIC_MODE = 0o644
DIR_MODE = 0o700


@dataclass(frozen=True)
class WrittenFile:
    path: Path
    mode: int
    """permission bits, e.g. 0o600"""
    what: str


def file_lines(files: list[WrittenFile]) -> list[str]:
    """One line per file: mode, name, what it is."""
    return [f"  {oct(f.mode)[2:]:>4}  {f.path.name:<18} {f.what}" for f in files]


class FolderWriter:
    """Files written into a private temporary folder beside ``target``, moved into place at the end."""

    def __init__(self, target: Path) -> None:
        self.target = target
        try:
            self.tmp = Path(tempfile.mkdtemp(prefix=f".{target.name}.", dir=target.parent))
        except OSError as exc:
            raise SecurityError(
                f"cannot create a temporary folder in {target.parent}: {exc.strerror}"
            ) from None
        self.files: list[WrittenFile] = []

    def write(self, name: str, data: bytes, mode: int, what: str) -> None:
        """``data`` as ``name`` in the temporary folder, flushed to disk, with exactly ``mode``."""
        path = self.tmp / name
        with atomic_path(path) as part, open(part, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(path, mode)  # exact, whatever the umask (the folder is private meanwhile)
        self.files.append(WrittenFile(self.target / name, mode, what))

    def commit(self) -> None:
        """Rename the temporary folder onto the target (replacing an existing one as a whole)."""
        os.chmod(self.tmp, DIR_MODE)
        if not self.target.exists():
            os.replace(self.tmp, self.target)
            return
        old = Path(tempfile.mkdtemp(prefix=f".{self.target.name}.old.", dir=self.target.parent))
        os.replace(self.target, old / "replaced")
        try:
            os.replace(self.tmp, self.target)
        except BaseException:
            os.replace(old / "replaced", self.target)  # put the old folder back
            raise
        finally:
            shutil.rmtree(old, ignore_errors=True)

    def merge(self) -> None:
        """Rename the files one by one into the existing target, in the order written (the last one
        last); on failure the ones already moved are removed again."""
        moved: list[Path] = []
        try:
            for f in self.files:
                os.replace(self.tmp / f.path.name, f.path)
                moved.append(f.path)
        except BaseException:
            for path in moved:
                path.unlink(missing_ok=True)
            raise
        finally:
            self.discard()

    def discard(self) -> None:
        shutil.rmtree(self.tmp, ignore_errors=True)

    @contextmanager
    def discarded_on_error(self, what: str) -> Iterator[None]:
        """Discard everything written on any error in the block; an :class:`OSError` becomes a
        :class:`SecurityError` saying ``cannot write WHAT``."""
        try:
            yield
        except BaseException as exc:
            self.discard()
            if isinstance(exc, OSError):
                raise SecurityError(f"cannot write {what}: {exc.strerror or exc}") from None
            raise


def check_new_folder(directory: Path, force: bool) -> Path:
    """The absolute path of ``directory`` if a new folder may be written there: it does not exist
    (or ``force`` and it is a folder, not a link), and its parent can be created and written."""
    target = Path(directory).absolute()
    if target.exists() or target.is_symlink():
        if not target.is_dir() or target.is_symlink():
            raise SecurityError(f"{directory} exists and is not a directory: not replacing it")
        if not force:
            count = sum(1 for _ in target.iterdir())
            raise SecurityError(
                f"{directory} exists ({count} entries): not overwriting its keys; pass --force to "
                "replace it, or choose a new folder"
            )
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise SecurityError(f"cannot create {target.parent}: {exc.strerror}") from None
    check_writable(target.parent, f"cannot write into {target.parent}")
    return target
