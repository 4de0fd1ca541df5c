"""The adaptation figure: E% of every move over axis time for several ways of choosing the parameters
(``axisflow bench adapt``: nominal, a one-time refit, online adaptation), with each minute's median |E%|.

Top: E% = (E_th − E_exp)/E_th·100 of each move [%] against the axis time since the way points began
[min], one colour per way, the ±1 % band and the ±3 % lines. Bottom: the median |E%| of each minute
(step lines), on the same time axis.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from .png import png_bytes, pyplot

COLOURS = {"nominal": "#d62728", "refit": "#ff7f0e", "adapt": "#1f77b4"}
"""colours of the benchmark's ways (others: matplotlib's cycle)"""


@dataclass(frozen=True)
class EnergyErrorSeries:
    """One way's moves: axis time since the way points began [min] and E% [%], and each minute's median
    |E%| [%] (minute k covers [k, k + 1))."""

    minutes: np.ndarray
    error_pct: np.ndarray
    median_abs_pct: np.ndarray


def adaptation_png(series: Mapping[str, EnergyErrorSeries], title: str) -> bytes:
    """The figure (see the module docstring) as PNG bytes."""
    plt = pyplot()
    fig, (top, bottom) = plt.subplots(
        2, 1, figsize=(12, 7), sharex=True, gridspec_kw={"height_ratios": [3, 1.4]}
    )
    for i, (name, s) in enumerate(series.items()):
        colour = COLOURS.get(name, f"C{i}")
        top.plot(s.minutes, s.error_pct, ".", ms=2.5, alpha=0.55, color=colour, label=name)
        edges = np.arange(s.median_abs_pct.size + 1, dtype=float)
        bottom.stairs(s.median_abs_pct, edges, color=colour, lw=1.8, label=name, baseline=None)
    top.axhspan(-1.0, 1.0, color="#2ca02c", alpha=0.12, label="±1 %")
    for level in (-3.0, 3.0):
        top.axhline(level, color="grey", ls="--", lw=0.8)
    top.axhline(0.0, color="black", lw=0.6)
    top.set_ylabel("E% per move [%]")
    every = np.concatenate([s.error_pct for s in series.values()]) if series else np.zeros(1)
    finite = every[np.isfinite(every)]
    if finite.size:  # the bulk of the moves, not the few short ones far out
        low, high = np.percentile(finite, [1.0, 99.0])
        top.set_ylim(min(low, -4.0) - 1.0, max(high, 4.0) + 1.0)
    top.legend(loc="upper left", ncol=4, fontsize=9)
    top.set_title(title)
    top.grid(alpha=0.3)
    bottom.axhline(1.0, color="#2ca02c", ls="--", lw=0.8)
    bottom.axhline(3.0, color="grey", ls="--", lw=0.8)
    bottom.set_ylabel("median |E%| [%]")
    bottom.set_xlabel("axis time since the way points began [min]")
    bottom.grid(alpha=0.3)
    bottom.legend(loc="upper left", ncol=3, fontsize=9)
    fig.tight_layout()
    return png_bytes(fig)
