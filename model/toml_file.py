"""Reading the project's TOML files (parameters, plant) with user-facing errors.

The TOML parser and ``importlib.resources`` (which brings ``tempfile`` along) load on the first read, so
that importing the model costs none of them (the command line's ``--help`` reads no file)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from .errors import AxisflowError


def read_toml(
    path: str | Path | None, *, package: str, resource: str, kind: str, error: type[AxisflowError]
) -> tuple[dict[str, Any], str]:
    """The table in ``path`` (None: the packaged ``resource`` of ``package``) and a name for messages.

    A missing, unreadable or malformed file raises ``error`` naming the file and the ``kind`` of file.
    """
    import tomllib
    from importlib import resources

    if path is None:
        text = resources.files(package).joinpath(resource).read_text("utf-8")
        source = f"default {kind} ({resource})"
    else:
        p = Path(path)
        source = str(p)
        try:
            text = p.read_text("utf-8")
        except FileNotFoundError:
            raise error(f"{kind} file {p} does not exist") from None
        except OSError as exc:
            raise error(f"{kind} file {p} cannot be read: {exc.strerror}") from None
        except UnicodeDecodeError as exc:
            raise error(
                f"{kind} file {p} is not UTF-8 text (byte {exc.object[exc.start]:#04x} at offset {exc.start})"
            ) from None
    try:
        return tomllib.loads(text), source
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{source}: not valid TOML: {exc}") from None
