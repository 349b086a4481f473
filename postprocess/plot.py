#!/usr/bin/env python3
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
A file that cannot be drawn gives the one line `error: <file>: <what is wrong>` and exit status 2.
"""
import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import supratrans_plot as sp  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n\n".join(__doc__.split("\n\n")[1:]))
    ap.add_argument("files", nargs="+", metavar="FILE.h5", help="HDF5 file(s) written by supratrans")
    ap.add_argument("-o", "--output", metavar="IMAGE", help="image to write (default: next to the file, .png)")
    ap.add_argument("--scene", choices=sp.SCENES, help="refuse a file of another scene")
    ap.add_argument("--site", type=int, help="timeseries: probe site to draw (default 60, else the middle probe)")
    ap.add_argument("--surface", action="store_true", help="map: 3-D surfaces of log10 E instead of colour maps")
    ap.add_argument("--energy", choices=list(sp.ENERGIES), default="injected",
                    help="sweep, map: which energy of the file to draw (default: injected, the paper's total energy)")
    ap.add_argument("--dpi", type=int, default=sp.DPI, help=f"resolution of the image (default {sp.DPI})")
    ap.add_argument("--show", action="store_true", help="also open the figure in a window")
    ap.add_argument("--numbers", action="store_true", help="print the numbers at every frequency, not a selection")
    ap.add_argument("-q", "--quiet", action="store_true", help="print nothing but errors")
    args = ap.parse_args(argv)
    if args.output:
        import matplotlib.pyplot as plt

        kinds = plt.gcf().canvas.get_supported_filetypes()
        plt.close("all")
        suffix = Path(args.output).suffix.lower().lstrip(".")
        if suffix not in kinds:
            print(f"error: {args.output}: unknown image type '.{suffix}' (known: {', '.join(sorted(kinds))})",
                  file=sys.stderr)
            return 2
    try:
        scenes = [sp.open_scene(f, expect=args.scene) for f in args.files]
        for s in scenes[1:]:
            if s.scene != "timeseries" or scenes[0].scene != "timeseries":
                bad = s if s.scene != "timeseries" else scenes[0]
                raise sp.PlotError(bad.path, f"scene is '{bad.scene}': only timeseries files are drawn together "
                                             "(Fig. 1); draw the others one at a time")
        if args.show:
            sp._pyplot.interactive = True
        if scenes[0].scene == "timeseries":
            fig = sp.draw_timeseries(scenes, site=args.site)
        elif scenes[0].scene == "map":
            fig = sp.draw_map(scenes[0], surface=args.surface, energy=args.energy)
        elif scenes[0].scene == "amplitude_sweep":
            fig = sp.draw_sweep(scenes[0], energy=args.energy)
        else:
            fig = sp.draw(scenes[0])
        if args.output:
            out = Path(args.output)
        elif len(scenes) > 1:
            out = Path(scenes[0].path).with_name(scenes[0].name + ".png")
        else:
            out = sp.output_path(scenes[0].path)
        if not args.quiet:
            for s in scenes:
                if Path(s.path) != Path(args.files[scenes.index(s)]):
                    print(f"note: {args.files[scenes.index(s)]} is not there yet: drawing its partial snapshot "
                          f"{s.path} ({s.partial_note()})", file=sys.stderr)
                newer = Path(str(s.path) + ".partial.h5")
                if newer.is_file() and newer.stat().st_mtime > Path(s.path).stat().st_mtime:
                    print(f"note: {newer} is newer: the scene is running again (draw it with: plot.py {newer})",
                          file=sys.stderr)
                print("\n".join(sp.summary(s, full=args.numbers)))
        if args.show:
            import matplotlib.pyplot as plt

            fig.savefig(out, dpi=args.dpi)
            plt.show()
        else:
            sp.save(fig, out, dpi=args.dpi)
        if not args.quiet:
            print(f"wrote {out}", file=sys.stderr)
    except sp.PlotError as exc:
        print(exc.line(), file=sys.stderr)
        return 2
    except OSError as exc:  # the image cannot be written
        print(f"error: {getattr(exc, 'filename', None) or args.output}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
