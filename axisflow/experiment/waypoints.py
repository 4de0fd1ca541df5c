"""Way points: drawn at random as in the paper's experiment (uniform in the stroke [0, L], seeded: the
same seed gives the same way points to the offline experiment, the planner node, the demo and the
figures), or read from a file (one position [m] per line, or a JSON list)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from ..model import AxisParams, MoveError

MAX_WAYPOINTS = 100_000
"""the most way points a run takes (random or from a file)"""


def random_waypoints(count: int, seed: int, params: AxisParams) -> np.ndarray:
    """``count`` way points [m] uniform in [0, L], from numpy's default generator seeded with ``seed``."""
    if isinstance(count, bool) or not isinstance(count, int) or not 2 <= count <= MAX_WAYPOINTS:
        raise MoveError(f"waypoints = {count!r} must be an integer in [2, {MAX_WAYPOINTS}]")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise MoveError(f"seed = {seed!r} must be a non-negative integer")
    return np.random.default_rng(seed).uniform(0.0, params.L, count)


def load_waypoints(path: str | Path, params: AxisParams) -> np.ndarray:
    """Positions [m] from ``path``: a JSON list, or text with one number per line (blank lines and
    ``#`` comments skipped; a CSV's first column). Each must lie in the stroke [0, L]."""
    p = Path(path)
    try:
        text = p.read_text("utf-8")
    except FileNotFoundError:
        raise MoveError(f"way point file {p} does not exist") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise MoveError(f"way point file {p} cannot be read: {exc}") from None
    values: list[tuple[str, float]] = []
    if text.lstrip().startswith("["):
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            raise MoveError(f"way point file {p}: not valid JSON: {exc}") from None
        values = [(f"item {i}", v) for i, v in enumerate(data)]
    else:
        for n, line in enumerate(text.splitlines(), start=1):
            field = line.split("#", 1)[0].split(",", 1)[0].strip()
            if field:
                try:
                    values.append((f"line {n}", float(field)))
                except ValueError:
                    raise MoveError(
                        f"way point file {p}, line {n}: {field!r} is not a number (in m)"
                    ) from None
    for where, value in values:
        if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
            raise MoveError(f"way point file {p}, {where}: {value!r} is not a finite number (in m)")
        if not 0.0 <= value <= params.L:
            raise MoveError(f"way point file {p}, {where}: {value} m is outside the stroke [0, {params.L}] m")
    if not 2 <= len(values) <= MAX_WAYPOINTS:
        raise MoveError(f"way point file {p} has {len(values)} way points; 2 to {MAX_WAYPOINTS} make moves")
    return np.array([v for _where, v in values], dtype=float)
