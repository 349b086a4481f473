"""What every figure and chart shares: matplotlib without a window and without chatter, the number format of the
labels, and saving (a PNG above a size budget is stored with a 256-colour palette; an image format matplotlib does
not know is a one-line PlotError)."""
from __future__ import annotations

import io
import logging
import math
import os
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from .reader import PlotError

#: The folder of the committed figures, postprocess/figures/ (the default of make_figures and the charts).
FIGURE_DIR = Path(__file__).resolve().parents[1] / "figures"
#: Resolution of saved figures (dots per inch).
DPI = 96
#: PNGs larger than this are stored with a 256-colour palette (line plots: a third of the size, no visible change).
PNG_BUDGET = 120_000

#: Whether figures may open a window (plot.py --show); otherwise matplotlib draws into files only (Agg).
_WINDOW = {"allowed": False}


def allow_window() -> None:
    """Let the next figures use matplotlib's interactive backend (for `plot.py --show`)."""
    _WINDOW["allowed"] = True


def pyplot():
    """matplotlib.pyplot with a file backend (unless MPLBACKEND is set or a window is allowed) and the house
    style, without chatter on stderr."""
    logging.getLogger("matplotlib").setLevel(logging.ERROR)
    import matplotlib  # noqa: PLC0415 (importing matplotlib takes a second: only when drawing)

    if "MPLBACKEND" not in os.environ and not _WINDOW["allowed"]:
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # noqa: PLC0415

    plt.rcParams.update({"font.size": 9, "axes.titlesize": 9, "legend.fontsize": 8, "figure.titlesize": 10,
                         "axes.grid": True, "grid.alpha": 0.25, "lines.linewidth": 1.3,
                         "savefig.bbox": "tight", "figure.constrained_layout.use": True})
    return plt


def cmap(name: str):
    """A matplotlib colour map by name."""
    import matplotlib  # noqa: PLC0415

    return matplotlib.colormaps[name]


def fmt(x: Any, digits: int = 4) -> str:
    """A parameter as short text: 0.9, 1.8, 0.0025, 200."""
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "nan"
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    return f"{x:.{digits}g}"


def image_format(path: Any) -> str:
    """The image format of `path` from its extension ('png' when it has none); PlotError for one that matplotlib
    cannot write."""
    from matplotlib.backend_bases import FigureCanvasBase  # noqa: PLC0415

    path = Path(path)
    suffix = path.suffix.lower().lstrip(".")
    if not suffix:
        return "png"
    known = FigureCanvasBase.get_supported_filetypes()
    if suffix not in known:
        raise PlotError(path, f"unknown image format '.{suffix}' (one of {', '.join('.' + k for k in sorted(known))})")
    return suffix


def save(fig, path: Any, dpi: int = DPI) -> Path:
    """Write a figure, creating the folder; returns the path. A PNG above PNG_BUDGET bytes is stored with a
    256-colour palette. The figure is closed, also when it cannot be written."""
    import matplotlib.pyplot as plt  # noqa: PLC0415

    path = Path(path)
    try:
        kind = image_format(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if kind != "png":
                fig.savefig(path, dpi=dpi, format=kind)
            else:
                buf = io.BytesIO()
                fig.savefig(buf, dpi=dpi, format="png")
                path.write_bytes(_palette(buf.getvalue()))
    finally:
        plt.close(fig)
    return path


def _palette(data: bytes) -> bytes:
    """A PNG above PNG_BUDGET bytes with a 256-colour palette (Pillow, a dependency of matplotlib); others as
    they are."""
    if len(data) <= PNG_BUDGET:
        return data
    try:
        from PIL import Image  # noqa: PLC0415
    except ImportError:
        return data
    with Image.open(io.BytesIO(data)) as im:
        out = io.BytesIO()
        im.convert("RGB").quantize(colors=256, method=Image.Quantize.FASTOCTREE).save(out, format="PNG",
                                                                                      optimize=True)
    return out.getvalue()
