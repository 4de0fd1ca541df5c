"""rerun views of the axis signals, live and from logs, and the paper's figures as pictures.

Installs as ``axisflow.viz`` from the folder ``viz/`` (pyproject.toml maps each top-level
folder to a sub-package of ``axisflow``; docs/architecture.md draws their imports).

Public API (each name is loaded with its module on first use, so importing the package stays light
and never loads zenoh; only the live view uses the network):

* :func:`write_session_rrd` — MCAP logs → one .rrd with the layout (``viz/session.py``);
* :func:`write_figures` / :func:`render_figures` — the paper's figures as PNG files / bytes
  (``viz/figures.py``);
* :class:`LiveView` — Zenoh keys → rerun, batch by batch (``viz/live_view.py``);
* :class:`RerunOutput`, :class:`ViewOutput` — where a view goes: .rrd, viewer, web viewer;
* :func:`view_blueprint` — the layout; :class:`AxisEntities` — the entity paths;
* :class:`VizError` — the exception root.

docs/viz.md describes the views, the commands and their measured figures.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..model import lazy_names

if TYPE_CHECKING:  # what a type checker sees; at run time __getattr__ loads each name from _HOMES
    from .blueprint import view_blueprint  # noqa: F401
    from .entities import AxisEntities  # noqa: F401
    from .errors import VizError  # noqa: F401
    from .figures import render_figures, save_figures, write_figures  # noqa: F401
    from .live_view import LiveView  # noqa: F401
    from .outputs import RerunOutput, ViewOutput  # noqa: F401
    from .session import SessionLogs, log_session, write_session_rrd  # noqa: F401

# each public name → its module, relative to this package
_HOMES: dict[str, str] = {
    "write_session_rrd": "session",
    "SessionLogs": "session",
    "log_session": "session",
    "write_figures": "figures",
    "render_figures": "figures",
    "save_figures": "figures",
    "LiveView": "live_view",
    "RerunOutput": "outputs",
    "ViewOutput": "outputs",
    "view_blueprint": "blueprint",
    "AxisEntities": "entities",
    "VizError": "errors",
}


__getattr__ = lazy_names(__name__, _HOMES)


__all__ = sorted(_HOMES)
