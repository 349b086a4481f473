"""What every figure and chart shares: the house style of matplotlib, set only while a figure is made and saved
(`style_context`, `styled`: never in the global rcParams), figures made without pyplot and without a window
(unless `plot.py --show` asks for one), the number format of the labels, and saving (a PNG above a size budget is
stored with a 256-colour palette; an image format matplotlib does not know is a one-line PlotError).

The house style, for figures fit to publish: PNGs at 200 dpi (DPI) and, with `vector_copies(True)` (make_figures),
a vector PDF beside each PNG; a colour-blind-safe palette (PALETTE: Okabe and Ito's eight colours, the default
colour cycle of every axes); titles in words (`figures.common.title`: the paper's figure, or what the file shows,
never a file stem), quick files (make_figures --quick) marked as quick in the title; legends placed off the data
(beside or below the axes where a chart is full); markers on coarse curves.

Importing the package, drawing and saving leave matplotlib's global state (rcParams, the backend, pyplot's
figures) as they found it."""
from __future__ import annotations

import contextlib
import functools
import io
import logging
import math
import warnings
from pathlib import Path
from typing import Any, Callable, Iterator

import numpy as np

from . import cli
from .reader import PlotError

#: Resolution of saved figures (dots per inch): 200, print quality at the figures' size (5-8 inches wide).
DPI = 200
#: The colour-blind-safe palette (Okabe and Ito, "Color Universal Design"): black first, then the seven colours,
#: by name. Families of curves and every chart take their colours from it.
PALETTE = {"black": "#000000", "blue": "#0072B2", "vermillion": "#D55E00", "green": "#009E73",
           "purple": "#CC79A7", "orange": "#E69F00", "sky": "#56B4E9", "yellow": "#F0E442"}
#: PNGs larger than this are stored with a 256-colour palette (line plots: a third of the size, no visible change).
PNG_BUDGET = 120_000
#: The house style: matplotlib's rcParams while a figure is made and saved.
STYLE = {"font.size": 9, "axes.titlesize": 9, "legend.fontsize": 8, "figure.titlesize": 10, "axes.grid": True,
         "grid.alpha": 0.25, "lines.linewidth": 1.3, "savefig.bbox": "tight", "figure.constrained_layout.use": True,
         "pdf.fonttype": 42}
#: The colour cycle of every axes: the palette without black (black is kept for the reference curves).
CYCLE = [v for k, v in PALETTE.items() if k not in ("black", "yellow")]

#: Whether `save` writes a vector PDF beside each PNG (`vector_copies`; make_figures turns it on).
_VECTOR = {"pdf": False}

#: Whether figures may open a window (plot.py --show): then they are made by pyplot, else as plain Figures.
_WINDOW = {"allowed": False}


def figure_dir() -> Path:
    """The folder of the committed figures, postprocess/figures/ of the checkout (the default of make_figures and
    the charts); PlotError outside a checkout (an installed package run elsewhere: say where with an option)."""
    root = cli.checkout()
    if root is None:
        raise PlotError(Path.cwd(), "not in a supratrans checkout (no fpm.toml with postprocess/ here or above): "
                                    "say where the images go (-o, --outdir)")
    return root / "postprocess" / "figures"


def vector_copies(on: bool = True) -> None:
    """Whether `save` writes a vector PDF (same name, `.pdf`) beside every PNG it writes."""
    _VECTOR["pdf"] = bool(on)


def allow_window() -> None:
    """Let the next figures be made by pyplot, for a window (`plot.py --show`)."""
    _WINDOW["allowed"] = True


@contextlib.contextmanager
def style_context() -> Iterator[None]:
    """The house style (STYLE) within the block, matplotlib's rcParams as they were after it; matplotlib's
    chatter on stderr silenced."""
    import matplotlib  # noqa: PLC0415 (importing matplotlib takes a second: only when drawing)

    logger = logging.getLogger("matplotlib")
    level = logger.level
    logger.setLevel(logging.ERROR)
    try:
        from cycler import cycler  # noqa: PLC0415 (a dependency of matplotlib)

        with matplotlib.rc_context({**STYLE, "axes.prop_cycle": cycler(color=CYCLE)}):
            yield
    finally:
        logger.setLevel(level)


def styled(draw: Callable) -> Callable:
    """A drawing function run within `style_context` (the figure it returns carries the style: fonts, grid and
    layout are fixed when the figure is made)."""

    @functools.wraps(draw)
    def wrapper(*args, **kwargs):
        with style_context():
            return draw(*args, **kwargs)

    return wrapper


def subplots(*args, **kwargs):
    """(figure, axes) as `pyplot.subplots(*args, **kwargs)` makes them, in the current style: a plain
    matplotlib Figure (no pyplot, no backend, nothing to close), or pyplot's when a window is allowed."""
    if _WINDOW["allowed"]:
        import matplotlib.pyplot as plt  # noqa: PLC0415

        return plt.subplots(*args, **kwargs)
    from matplotlib.figure import Figure  # noqa: PLC0415

    fig = Figure(figsize=kwargs.pop("figsize", None))
    return fig, fig.subplots(*args, **kwargs)


def close(fig) -> None:
    """Forget a figure: pyplot's are closed, plain ones need nothing."""
    if fig.canvas.manager is not None:
        import matplotlib.pyplot as plt  # noqa: PLC0415

        plt.close(fig)


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
    256-colour palette; with `vector_copies(True)` a PNG gets a vector PDF beside it (same stem). The figure is
    closed, also when it cannot be written."""
    path = Path(path)
    try:
        kind = image_format(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        with warnings.catch_warnings(), style_context():
            warnings.simplefilter("ignore")
            if kind != "png":
                fig.savefig(path, dpi=dpi, format=kind)
            else:
                buf = io.BytesIO()
                fig.savefig(buf, dpi=dpi, format="png")
                path.write_bytes(_palette(buf.getvalue()))
                if _VECTOR["pdf"]:
                    fig.savefig(path.with_suffix(".pdf"), format="pdf")
    finally:
        close(fig)
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
        extra = {"dpi": im.info["dpi"]} if "dpi" in im.info else {}  # the resolution recorded stays (pHYs)
        im.convert("RGB").quantize(colors=256, method=Image.Quantize.FASTOCTREE).save(out, format="PNG",
                                                                                      optimize=True, **extra)
    return out.getvalue()
