"""Chart of the scene `stability`: the largest stable time step of each integrator against the coupling c, next
to the paper's necessary condition and RK4's linear limit.

    python3 postprocess/chart_stability.py out/stability.h5                      # -> postprocess/figures/stability.png
    python3 postprocess/chart_stability.py out/stability.h5 -o stab.png

One column per curve of the scene (e.g. beta = 0, 0.25, 1). Top row: dt against c, log-log. Bottom row: the
same as the Courant number c dt, where the differences of a few per cent show. Lines:

- markers: the observed boundary of each method (`/boundary/observed`, the largest dt found stable by
  bisection; the smallest unstable one is within the scene's `resolution` above it);
- black: the paper's necessary condition (c^2 - m^2/4) dt^2 < 1 + (gamma/4 + beta) dt, its critical dt(c)
  computed from the file's parameters (checked against `/boundary/paper`);
- grey dashed: RK4's linear limit (`/boundary/rk4`, from the spectrum of the linearised chain).

Shaded red: where the paper's condition holds but the energy-conserving scheme (newton) is unstable: there
the condition is necessary but not sufficient. Shaded green: where the condition is violated and newton is
nevertheless stable (the condition is then not even necessary: it ignores the on-site term V''(0) = 1). Between
the c of the scene, newton's boundary is interpolated linearly in log c; the markers are the measurements.

Numbers are printed on stdout. A file that cannot be used gives the one line `error: <file>: <what is wrong>`
and exit status 2.
"""
from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Any

import numpy as np

from .. import cli
from ..reader import PlotError, Scene, open_scene
from ..style import DPI, figure_dir, fmt, image_format, save, styled, subplots

#: Style of each method's observed boundary.
STYLE = {"newton": dict(color="black", marker="o"), "linearized": dict(color="#0072B2", marker="s"),
         "rk4": dict(color="#009E73", marker="^"), "rk8": dict(color="#D55E00", marker="D"),
         "avf4": dict(color="#56B4E9", marker="v"), "avf8": dict(color="#999933", marker="P")}
#: Symbols of the parameters a curve may vary.
SYMBOL = {"gamma": r"\gamma", "beta": r"\beta", "m2": "m^2"}


def read_stability(path: Any) -> Scene:
    """The stability file (see `reader.open_scene`: its datasets and shapes checked), with a 'newton' method."""
    s = open_scene(path, "stability")
    if "newton" not in [str(m) for m in s.data["methods"]]:
        raise PlotError(s.path, "no 'newton' among /methods: nothing to compare with the paper's condition")
    return s


def curve_parameters(s: Scene, icurve: int) -> tuple[dict, str, float]:
    """(gamma, beta, m2) of a curve: the base run's, with the varied one (`/scene vary`) replaced."""
    par = {k: float(s.params.get(k, 0.0)) for k in ("gamma", "beta", "m2")}
    vary = str(s.groups.get("scene", {}).get("vary", "none"))
    value = float(s.data["curves/value"][icurve])
    if vary in par and math.isfinite(value):
        par[vary] = value
    return par, vary, value


def paper_dt(c: Any, gamma: float, beta: float, m2: float) -> np.ndarray:
    """Critical dt of (c^2 - m^2/4) dt^2 < 1 + (gamma/4 + beta) dt (inf when the condition always holds)."""
    c = np.asarray(c, float)
    q = c ** 2 - m2 / 4.0
    p = gamma / 4.0 + beta
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(q > 0, (p + np.sqrt(p * p + 4.0 * q)) / (2.0 * q), np.inf)


def regions(c_fine: np.ndarray, paper: np.ndarray, c: np.ndarray,
            newton: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Newton's boundary on `c_fine` (its Courant number c dt interpolated linearly in log c: the straight
    segments of the chart), and masks: condition holds but newton unstable (paper > newton), condition
    violated but newton stable (paper < newton)."""
    ok = np.isfinite(newton)
    if ok.sum() < 2:
        nb = np.full_like(c_fine, np.nan)
    else:
        nb = np.interp(np.log(c_fine), np.log(c[ok]), c[ok] * newton[ok], left=np.nan, right=np.nan) / c_fine
    return nb, paper > nb, paper < nb


@styled
def draw_stability(s: Scene):
    """The chart: one column per curve, dt (top, log-log) and the Courant number c dt (bottom) against c."""
    d = s.data
    methods = [str(m) for m in d["methods"]]
    c = np.asarray(d["c"], float)
    obs = np.asarray(d["boundary/observed"], float)
    ncurve = d["curves/value"].size
    inewton = methods.index("newton")
    c_fine = np.geomspace(c.min(), c.max(), 300)
    fig, axes = subplots(2, ncurve, figsize=(3.9 * ncurve, 6.4), squeeze=False, sharex=True,
                         gridspec_kw={"height_ratios": [1, 1.25]})
    for icurve in range(ncurve):
        par, vary, value = curve_parameters(s, icurve)
        paper_f = paper_dt(c_fine, **par)
        rk4 = np.asarray(d["boundary/rk4"][icurve], float)
        nb, bad, loose = regions(c_fine, paper_f, c, obs[icurve, inewton])
        for row in range(2):
            ax = axes[row, icurve]
            scale_f = c_fine if row else 1.0
            scale = c if row else 1.0
            ax.plot(c_fine, paper_f * scale_f, color="black", lw=1.6, label="paper's condition (critical dt)")
            ax.plot(c, rk4 * scale, color="0.5", ls="--", lw=1.2, label="RK4 linear limit")
            for im, m in enumerate(methods):
                st = STYLE.get(m, dict(marker="x"))
                ax.plot(c, obs[icurve, im] * scale, ls=":", lw=0.9, ms=5, label=f"{m} (observed)", **st)
            if row:
                ax.fill_between(c_fine, nb * c_fine, paper_f * c_fine, where=bad, color="#D55E00", alpha=0.25,
                                lw=0, label="condition holds, newton unstable")
                ax.fill_between(c_fine, paper_f * c_fine, nb * c_fine, where=loose, color="#009E73",
                                alpha=0.18, lw=0, label="condition violated, newton stable")
                ax.set_ylabel("$c\\,\\Delta t$ (Courant number)" if icurve == 0 else "")
                ax.set_xlabel("coupling $c$")
            else:
                ax.set_yscale("log")
                lo, hi = ax.get_ylim()
                ticks = [x for x in (0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0) if lo <= x <= hi]
                ax.set_yticks(ticks)
                ax.set_yticklabels([fmt(x) for x in ticks])
                ax.set_yticks([], minor=True)  # 1-2-5 labels only: the log scale's minor labels overlapped them
                ax.set_ylabel("largest stable $\\Delta t$" if icurve == 0 else "")
                name = SYMBOL.get(vary, vary)
                ax.set_title(f"${name}$ = {fmt(value)}" if vary in SYMBOL else f"curve {icurve + 1}")
            ax.set_xscale("log")
            ax.set_xticks(c)
            ax.set_xticklabels([fmt(x) for x in c])
            ax.minorticks_off()
    seen = {}
    for col in range(ncurve):  # one legend for all panels: a shading may appear in some columns only
        for h, lab in zip(*axes[1, col].get_legend_handles_labels()):
            seen.setdefault(lab, h)
    fig.legend(list(seen.values()), list(seen.keys()), loc="outside lower center", ncol=4, fontsize=7.5)
    p = s.params
    fig.suptitle(f"Stability: largest stable $\\Delta t$ vs $c$ ({p.get('potential', '')}, $A$ = "
                 f"{fmt(p.get('amplitude'))}, $T$ = {fmt(p.get('t_final'))}, $N$ = {p.get('n')}, "
                 f"$m^2$ = {fmt(p.get('m2', 0.0))}, $\\gamma$ = {fmt(p.get('gamma', 0.0))}, "
                 f"absorber $\\kappa$ = {fmt(p.get('kappa', 0.0))})"
                 + (" [quick: coarse grids]" if s.quick else "") + "\n"
                 "paper's necessary condition $(c^2 - m^2/4)\\,\\Delta t^2 < 1 + (\\alpha/4 + \\beta)\\,\\Delta t$")
    return fig


def summary(s: Scene) -> list[str]:
    """Lines of numbers: per curve and c, the paper's critical dt, each method's observed boundary, RK4's
    limit, and what the paper's condition says about newton."""
    d = s.data
    methods = [str(m) for m in d["methods"]]
    c = np.asarray(d["c"], float)
    obs = np.asarray(d["boundary/observed"], float)
    hi = np.asarray(d["boundary/observed_unstable"], float)
    inewton = methods.index("newton")
    out = [f"{'curve':>12} {'c':>4} {'paper':>7} " + " ".join(f"{m:>10}" for m in methods)
           + f" {'rk4 limit':>9}  paper's condition for newton"]
    worst = []
    for icurve in range(d["curves/value"].size):
        par, vary, value = curve_parameters(s, icurve)
        for ic, cc in enumerate(c):
            paper = float(paper_dt(cc, **par))
            stored = float(d["boundary/paper"][icurve, ic])
            if math.isfinite(stored) and abs(stored - paper) > 1e-9 * max(1.0, paper):
                raise PlotError(s.path, f"/boundary/paper[{icurve}, {ic}] = {stored:g} but the parameters give "
                                           f"{paper:g}")
            nlo, nhi = obs[icurve, inewton, ic], hi[icurve, inewton, ic]
            if paper > nhi:
                verdict = f"holds up to {paper:.4g} but newton unstable above {nhi:.4g}: not sufficient"
                worst.append((paper / nlo, vary, value, cc))
            elif paper < nlo:
                verdict = f"violated above {paper:.4g} yet newton stable up to {nlo:.4g}: not necessary"
            else:
                verdict = "matches newton within the bisection bracket"
            out.append(f"{vary + ' = ' + fmt(value):>12} {fmt(cc):>4} {paper:7.4f} "
                       + " ".join(f"{obs[icurve, im, ic]:10.4f}" for im in range(len(methods)))
                       + f" {float(d['boundary/rk4'][icurve, ic]):9.4f}  {verdict}")
    if "boundary/grid_consistent" in d and np.any(d["boundary/grid_consistent"] == 0):
        out.append("note: some bisections disagree with the grid (/boundary/grid_consistent = 0)")
    if worst:
        r, vary, value, cc = max(worst)
        out.append(f"largest overshoot of the paper's condition: {vary} = {fmt(value)}, c = {fmt(cc)}: "
                   f"it allows {r:.2f} x newton's largest stable dt")
    return out


def main(argv: list[str] | None = None) -> int:
    """The command line of `chart_stability.py`; returns the exit status (0, or 2 with one line on stderr)."""
    ap = cli.parser("chart_stability.py", __doc__, argv)
    ap.add_argument("h5", metavar="STABILITY.h5", help="file of the scene stability")
    ap.add_argument("-o", "--output", type=Path,
                    help="image to write (default postprocess/figures/stability.png of the checkout)")
    ap.add_argument("--dpi", type=cli.dpi, default=DPI, help=f"resolution of the image (default {DPI})")
    ap.add_argument("-q", "--quiet", action="store_true", help="print nothing but errors")
    args = ap.parse_args(argv)
    try:
        output = args.output or figure_dir() / "stability.png"
        image_format(output)
        s = read_stability(args.h5)
        lines = summary(s)
        path = save(draw_stability(s), output, dpi=args.dpi)
        if not args.quiet:
            print("\n".join(lines))
            print(f"wrote {path} ({path.stat().st_size / 1024:.0f} kB)", file=sys.stderr)
    except PlotError as exc:
        print(exc.line(), file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"error: {getattr(exc, 'filename', None) or args.output}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    return 0
