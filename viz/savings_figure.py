"""The savings figure: energy per cycle against cycle time (``axisflow savings``).

One axes: the law's Pareto front over the cycle (its plans for ω from 0 to 1: cycle time [s] against
energy per cycle [J], a line), the baselines at their limits as points (the model's totals), and the
three runs of the comparison — the baseline, axisflow move by move at the baseline's durations,
axisflow at the matched ω — as the model predicts them (hollow) and as the axis measured them
(filled). The cycle time axis is logarithmic: the front spans the fastest plans to 20 s per move.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from .png import png_bytes, pyplot


@dataclass(frozen=True)
class SavingsPoint:
    """One run: its cycle time [s], modelled energy [J] and measured energy [J] (None if not run)."""

    label: str
    cycle_time_s: float
    energy_model_j: float
    energy_measured_j: float | None


MARKERS = {"baseline": "s", "equal-time": "o", "matched-omega": "D"}


def savings_png(
    front: Sequence[tuple[float, float]],
    law: str,
    baselines: Mapping[str, tuple[float, float]],
    runs: Sequence[SavingsPoint],
    title: str,
) -> bytes:
    """The figure (see the module docstring) as PNG bytes; ``front`` is (cycle time, energy) per ω."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(13, 6))
    pts = np.array(sorted(front))
    for ax in axes:
        if pts.size:
            ax.plot(
                pts[:, 0],
                pts[:, 1],
                "-",
                color="#1f77b4",
                lw=1.6,
                label=f"axisflow {law}: Pareto front over ω",
            )
        for i, (name, (t, e)) in enumerate(baselines.items()):
            ax.plot([t], [e], "^", ms=10, color=f"C{i + 1}", label=f"{name} at its limits (model)")
        for i, r in enumerate(runs):
            colour = f"C{i + 3}"
            marker = MARKERS.get(r.label, "o")
            ax.plot([r.cycle_time_s], [r.energy_model_j], marker, ms=11, mfc="none", mec=colour, mew=1.8,
                    label=f"{r.label}: model")  # fmt: skip
            if r.energy_measured_j is not None:
                ax.plot(
                    [r.cycle_time_s],
                    [r.energy_measured_j],
                    marker,
                    ms=7,
                    color=colour,
                    label=f"{r.label}: measured",
                )
        ax.set_xlabel("cycle time [s]")
        ax.set_ylabel("energy per cycle [J]")
        ax.grid(True, which="both", alpha=0.3)
    full, zoom = axes
    full.set_xscale("log")
    full.set_title("the whole front (ω from 0 to 1)")
    # the zoom: around the runs and the baselines, where the savings are
    times = [r.cycle_time_s for r in runs] + [t for t, _e in baselines.values()]
    energies = [r.energy_model_j for r in runs] + [e for _t, e in baselines.values()]
    energies += [r.energy_measured_j for r in runs if r.energy_measured_j is not None]
    t_lo, t_hi = min(times), max(times)
    e_lo, e_hi = min(energies), max(energies)
    zoom.set_xlim(t_lo - 0.25 * (t_hi - t_lo + 0.1 * t_lo), t_hi + 0.25 * (t_hi - t_lo + 0.1 * t_lo))
    zoom.set_ylim(e_lo - 0.4 * (e_hi - e_lo + 0.01 * e_lo), e_hi + 0.4 * (e_hi - e_lo + 0.01 * e_lo))
    zoom.set_title("near the baselines")
    zoom.legend(fontsize=8, loc="upper right")
    fig.suptitle(title)
    fig.tight_layout()
    return png_bytes(fig)
