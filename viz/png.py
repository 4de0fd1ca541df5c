"""Rendering matplotlib figures to PNG bytes, headless (the Agg back-end), for the caller to write."""

from __future__ import annotations

import io
from typing import Any

DPI = 100
"""pixels per inch of the figures in docs/figures (a 12-inch-wide figure is 1200 px)"""


def pyplot() -> Any:
    """``matplotlib.pyplot`` on the Agg back-end (no display needed); imported on first use."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


PALETTE_COLOURS = 128
"""colours of the PNG palette: line plots need few, and a palette PNG is a fraction of an RGB one"""


def png_bytes(fig: Any, dpi: int = DPI) -> bytes:
    """The figure as PNG bytes (a palette image of :data:`PALETTE_COLOURS` colours); the figure is
    closed."""
    from PIL import Image

    plt = pyplot()
    rgba = io.BytesIO()
    try:
        fig.savefig(rgba, format="png", dpi=dpi, metadata={"Software": None})
    finally:
        plt.close(fig)
    rgba.seek(0)
    with Image.open(rgba) as image:
        palette = image.convert("RGB").quantize(PALETTE_COLOURS, dither=Image.Dither.NONE)
    out = io.BytesIO()
    palette.save(out, format="PNG", optimize=True)
    return out.getvalue()
