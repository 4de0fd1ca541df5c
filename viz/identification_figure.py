"""The paper's Fig. 2: measured against model effort over the excitation, and the residual.

Top panel: the measured effort (through the fit's filter) and the refit and nominal models; bottom
panel: measured minus model, for both. Samples the fit left out (stationary, saturated, trimmed) are
shaded and the models are not drawn there (at rest the filtered velocity hovers around zero and
a1·sign(ẋ) with it: no prediction to show). Each log is drawn from its first to its last usable
sample (one second more on each side), from at most :data:`MAX_POINTS` evenly spaced samples.
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..identification.refit import EffortTrace
from .png import pyplot

MAX_POINTS = 20_000


def identification_png(traces: Sequence[EffortTrace], title: str = "") -> bytes:
    """The figure as PNG bytes (written atomically by the caller); one column of two panels per trace."""
    plt = pyplot()
    n = len(traces)
    fig, axes = plt.subplots(2, n, figsize=(11 * n, 6.5), sharex="col", squeeze=False,
                             gridspec_kw={"height_ratios": [2, 1]})  # fmt: skip
    for col, tr in enumerate(traces):
        used = np.flatnonzero(tr.usable)
        first, last = (used[0], used[-1]) if used.size else (0, tr.t_s.size - 1)
        rate = (tr.t_s.size - 1) / max(tr.t_s[-1] - tr.t_s[0], 1e-9)
        lo_i, hi_i = max(0, first - round(rate)), min(tr.t_s.size, last + round(rate))
        step = max(1, (hi_i - lo_i) // MAX_POINTS)
        sl = slice(lo_i, hi_i, step)
        top, bottom = axes[0, col], axes[1, col]
        for ax in (top, bottom):  # one artist for all left-out stretches (an hour has thousands)
            ax.fill_between(tr.t_s[sl], 0, 1, where=~tr.usable[sl], step="mid", color="0.92", lw=0,
                            transform=ax.get_xaxis_transform())  # fmt: skip
        refit = np.where(tr.usable, tr.refit, np.nan)
        nominal = np.where(tr.usable, tr.nominal, np.nan)
        top.plot(tr.t_s[sl], tr.measured[sl], color="black", lw=0.8, label="measured")
        top.plot(tr.t_s[sl], refit[sl], color="tab:blue", lw=0.8, label="model, refit")
        top.plot(tr.t_s[sl], nominal[sl], color="tab:orange", lw=0.8, ls="--", label="model, nominal")
        top.set_ylabel(f"effort [{tr.unit}]")
        top.legend(loc="upper right", fontsize=8)
        top.set_title(title or Path(tr.source).name, fontsize=10)
        res_refit, res_nominal = tr.measured - refit, tr.measured - nominal
        bottom.plot(tr.t_s[sl], res_nominal[sl], color="tab:orange", lw=0.6, label="measured − nominal")
        bottom.plot(tr.t_s[sl], res_refit[sl], color="tab:blue", lw=0.6, label="measured − refit")
        bottom.axhline(0.0, color="0.5", lw=0.5)
        bottom.set_ylabel(f"residual [{tr.unit}]")
        bottom.set_xlabel("time [s]")
        bottom.legend(loc="upper right", fontsize=8)
    fig.text(0.01, 0.01, "grey: samples left out of the fit (stationary, saturated, edges)", fontsize=8)
    fig.tight_layout()
    png = io.BytesIO()
    try:
        fig.savefig(png, format="png", dpi=110)
    finally:
        plt.close(fig)
    return png.getvalue()
