"""Draw the figure of one supratrans HDF5 file (or Fig. 1 from its four timeseries files).

    python3 postprocess/plot.py out/fig2.h5                  # -> out/fig2.png
    python3 postprocess/plot.py out/fig11.h5 -o fig11.png    # any name; .pdf / .svg work too
    python3 postprocess/plot.py out/fig1_*.h5 -o fig1.png    # Fig. 1: 2 x 2 panels
    python3 postprocess/plot.py out/bif1.h5 --show           # open a window as well

The figure is chosen by the file's scene (timeseries, amplitude_sweep, map, bifurcation) and its input file
name (the paper's figure label); every parameter shown comes from the file. While a scene runs, or after it
was killed, `out/X.h5` does not exist yet: its partial snapshot `out/X.h5.partial.h5` is drawn instead, the
runs not done as gaps, the title marked `partial: k of n runs`.

The numbers the figure shows (thresholds, energies) are printed on stdout; the path written on stderr.
A file that cannot be drawn, or an image name whose format matplotlib does not know, gives the one line
`error: <file>: <what is wrong>` and exit status 2.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from . import cli, figures, style
from .reader import FIGURE_SCENES, PlotError, Scene, open_scene, output_path


def _parser(argv: list[str] | None = None) -> argparse.ArgumentParser:
    """The options of plot.py (usage and epilog from the module documentation)."""
    ap = cli.parser("plot.py", __doc__, argv)
    ap.add_argument("files", nargs="+", metavar="FILE.h5", help="HDF5 file(s) written by supratrans")
    ap.add_argument("-o", "--output", metavar="IMAGE", help="image to write (default: next to the file, .png)")
    ap.add_argument("--scene", choices=FIGURE_SCENES, help="refuse a file of another scene")
    ap.add_argument("--site", type=int, help="timeseries: probe site to draw (default 60, else the middle probe)")
    ap.add_argument("--surface", action="store_true", help="map: 3-D surfaces of log10 E instead of colour maps")
    ap.add_argument("--energy", choices=list(figures.ENERGIES), default="injected",
                    help="sweep, map: which energy of the file to draw (default: injected, the paper's total energy)")
    ap.add_argument("--dpi", type=cli.dpi, default=style.DPI, help=f"resolution of the image (default {style.DPI})")
    ap.add_argument("--show", action="store_true", help="also open the figure in a window")
    ap.add_argument("--numbers", action="store_true", help="print the numbers at every frequency, not a selection")
    ap.add_argument("-q", "--quiet", action="store_true", help="print nothing but errors")
    return ap


def _draw(scenes: list[Scene], args: argparse.Namespace):
    """The figure of the files read, as the options ask."""
    for s in scenes[1:]:
        if s.scene != "timeseries" or scenes[0].scene != "timeseries":
            bad = s if s.scene != "timeseries" else scenes[0]
            raise PlotError(bad.path, f"scene is '{bad.scene}': only timeseries files are drawn together "
                                      "(Fig. 1); draw the others one at a time")
    if scenes[0].scene == "timeseries":
        return figures.draw_timeseries(scenes, site=args.site)
    if scenes[0].scene == "map":
        return figures.draw_map(scenes[0], surface=args.surface, energy=args.energy)
    if scenes[0].scene == "amplitude_sweep":
        return figures.draw_sweep(scenes[0], energy=args.energy)
    return figures.draw(scenes[0])


def _notes(scenes: list[Scene], files: list[str]) -> None:
    """On stderr: a partial snapshot drawn in place of its file, a partial snapshot newer than its file."""
    for s, asked in zip(scenes, files):
        if Path(s.path) != Path(asked):
            print(f"note: {asked} is not there yet: drawing its partial snapshot {s.path} ({s.partial_note()})",
                  file=sys.stderr)
        newer = Path(str(s.path) + ".partial.h5")
        if newer.is_file() and newer.stat().st_mtime > Path(s.path).stat().st_mtime:
            print(f"note: {newer} is newer: the scene is running again (draw it with: plot.py {newer})",
                  file=sys.stderr)


def main(argv: list[str] | None = None) -> int:
    """The command line; returns the exit status (0, or 2 with one line on stderr)."""
    args = _parser(argv).parse_args(argv)
    try:
        if args.output:
            style.image_format(args.output)
        scenes = [open_scene(f, expect=args.scene or FIGURE_SCENES) for f in args.files]
        if args.show:
            style.allow_window()
        fig = _draw(scenes, args)
        if args.output:
            out = Path(args.output)
        elif len(scenes) > 1:
            out = Path(scenes[0].path).with_name(scenes[0].name + ".png")
        else:
            out = output_path(scenes[0].path)
        if not args.quiet:
            _notes(scenes, args.files)
            for s in scenes:
                print("\n".join(figures.summary(s, full=args.numbers)))
        if args.show:
            import matplotlib.pyplot as plt  # noqa: PLC0415

            with style.style_context():
                fig.savefig(out, dpi=args.dpi)
            plt.show()
        else:
            style.save(fig, out, dpi=args.dpi)
        if not args.quiet:
            print(f"wrote {out}", file=sys.stderr)
    except PlotError as exc:
        print(exc.line(), file=sys.stderr)
        return 2
    except OSError as exc:  # the image cannot be written
        print(f"error: {getattr(exc, 'filename', None) or args.output}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    return 0
