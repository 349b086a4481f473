"""Speed against accuracy, ours against SciPy's: run the scene `work_precision`, then the SciPy peer on the same
problem in the same process, draw the work-precision charts and print the equal-error table.

    python3 postprocess/work_precision.py                           # fpm run ... input/work_precision.nml, then all
    python3 postprocess/work_precision.py --h5 out/work_precision.h5    # an existing file: peer, charts, table
    python3 postprocess/work_precision.py --h5 out/work_precision.h5 --peer out/work_precision_peer.json
                                                                    # charts and table only, nothing run

Steps: (a) `fpm run --profile release -- input/work_precision.nml` in the repository (outside one the `supratrans`
installed on PATH, the paths relative to the working directory; or `--h5`), its progress lines passed on; (b) right
after, `peer_scipy.py`'s DOP853 and RK45 at tolerances 1e-3 .. 1e-12 for every amplitude of the file; (c) the
peer's points written as JSON next to the file (`out/work_precision_peer.json`, with the table); (d) the charts
`postprocess/figures/work_precision.png` (error of the injected energy vs wall time, log-log, one line per
method, one panel per amplitude) and `work_precision_dt.png` (error vs dt, fitted orders in the legend; the
peer against its mean step T/steps); (e) the table: for each error level 1e-2 .. 1e-8, the fastest of our
methods, SciPy's best and their ratio.

Time at an error level, for one method: its runs in order of work (dt decreasing, tolerance decreasing), each
credited with the worst error of itself and every costlier run (no credit for a lucky cancellation at one
dt), log time interpolated linearly in log error between the two runs that bracket the level; the cheapest
run's time when it already reaches the level (no extrapolation); not reached when no run does.
The Fortran times are the scene's medians (one thread, `repeats` runs), the peer's the medians of its
`repeats` solves, measured back to back; the verdict uses the medians, the ratio of the shortest times is
printed beside it as a measure of the machine's noise.

A file that cannot be used gives the one line `error: <file>: <what is wrong>` and exit status 2.
"""
from __future__ import annotations

import math
import subprocess
import sys
import time
from pathlib import Path
from typing import Any, Callable

import numpy as np

from .. import cli, namelist, peer as ps
from ..reader import PlotError, Scene, output_path
from ..style import DPI, figure_dir, fmt, save, styled, subplots

#: fpm through .ci/with_commit: the program records the repository's commit in /provenance.
def _fpm() -> list[str]:
    return ["sh", str(cli.repository() / ".ci" / "with_commit"), "fpm"]

#: Error levels of the table.
LEVELS = [10.0 ** -k for k in range(2, 9)]
#: The goal of issue 5: one of our methods at least this many times faster than SciPy's best at every level.
GOAL = 5.0
#: Styles: ours solid with filled markers, SciPy's dashed with open markers.
STYLE = {"newton": dict(color="black", marker="o"), "linearized": dict(color="tab:blue", marker="s"),
         "rk4": dict(color="tab:green", marker="^"), "rk8": dict(color="tab:red", marker="D"),
         "avf4": dict(color="tab:cyan", marker="v"), "avf8": dict(color="tab:olive", marker="P"),
         "DOP853": dict(color="tab:purple", marker="o", ls="--", mfc="none"),
         "RK45": dict(color="tab:orange", marker="s", ls="--", mfc="none"),
         "RK23": dict(color="tab:brown", marker="^", ls="--", mfc="none")}


# ------------------------------------------------------------------------------------------------ lines


def our_lines(w: Scene, ia: int) -> dict[str, dict]:
    """{method: dict(dt, time, error, error_u)} of the Fortran runs at amplitude index `ia` that ran and are
    ok, in order of work (dt decreasing)."""
    d = w.data
    out = {}
    for im, name in enumerate(d["methods"]):
        dt = np.asarray(d["dt"][im], float)
        ok = (d["status"][ia, im] == 0) & np.isfinite(dt) & np.isfinite(d["wall_time"][ia, im]) \
            & np.isfinite(d["error_energy"][ia, im])
        order = np.argsort(-dt[ok])
        tmin = d.get("wall_time_min", d["wall_time"])
        out[str(name)] = {"dt": dt[ok][order], "time": d["wall_time"][ia, im][ok][order],
                          "time_min": tmin[ia, im][ok][order],
                          "error": d["error_energy"][ia, im][ok][order], "error_u": d["error_u"][ia, im][ok][order]}
    return out


def peer_lines(peer: dict, amplitude: float) -> dict[str, dict]:
    """{method: dict(tol, time, error, mean_dt, error_u)} of the peer's ok points at `amplitude`, in order of work
    (tolerance decreasing)."""
    out = {}
    for p in peer["points"]:
        if p.get("status") != "ok" or not math.isclose(p["amplitude"], amplitude, rel_tol=1e-12):
            continue
        m = out.setdefault(p["method"], {"tol": [], "time": [], "time_min": [], "error": [], "mean_dt": [],
                                         "error_u": []})
        m["tol"].append(p["tol"])
        m["time"].append(p["wall_time"])
        m["time_min"].append(p.get("wall_time_min", p["wall_time"]))
        m["error"].append(p["error_energy"])
        m["mean_dt"].append(p["mean_dt"])
        m["error_u"].append(p.get("error_u", math.nan))
    for m in out.values():
        order = np.argsort(-np.asarray(m["tol"]))
        for k in list(m):
            m[k] = np.asarray(m[k], float)[order]
    return out


def time_at_error(times: Any, errors: Any, level: float) -> tuple[float, str]:
    """Wall time a method needs for `level`, from its runs in order of work (see the module documentation):
    (time, how) with how 'interpolated', 'cheapest run' or 'not reached' (time NaN)."""
    t = np.asarray(times, float)
    e = np.asarray(errors, float)
    keep = np.isfinite(t) & np.isfinite(e) & (t > 0)
    t, e = t[keep], e[keep]
    if t.size == 0:
        return math.nan, "not reached"
    env = np.maximum.accumulate(e[::-1])[::-1]  # worst error of this run and every costlier one
    env = np.maximum(env, 1e-300)
    hit = np.nonzero(env <= level)[0]
    if hit.size == 0:
        return math.nan, "not reached"
    i = int(hit[0])
    if i == 0:
        return float(t[0]), "cheapest run"
    x0, x1 = math.log(env[i - 1]), math.log(env[i])
    y0, y1 = math.log(t[i - 1]), math.log(t[i])
    if x1 == x0:
        return float(t[i]), "interpolated"
    y = y0 + (math.log(level) - x0) * (y1 - y0) / (x1 - x0)
    return float(math.exp(y)), "interpolated"


def equal_error_table(w: Scene, peer: dict, levels: list[float] = LEVELS) -> list[dict]:
    """Rows (one per amplitude and level): the fastest of our methods and its time, SciPy's best and its time,
    ratio SciPy / ours (from the medians: the verdict), every method's time; and the same ratio from the
    shortest times (`ratio_min`: the spread of a noisy machine)."""
    rows = []
    for ia, a in enumerate(np.asarray(w.data["amplitude"], float)):
        ours, theirs = our_lines(w, ia), peer_lines(peer, a)
        for level in levels:
            row = {"amplitude": float(a), "level": level, "times": {}}
            for key, suffix in (("time", ""), ("time_min", "_min")):
                for group, lines in (("ours", ours), ("scipy", theirs)):
                    best, best_t = None, math.inf
                    for name, ln in lines.items():
                        t, how = time_at_error(ln[key], ln["error"], level)
                        if not suffix:
                            row["times"][name] = t
                        if math.isfinite(t) and t < best_t:
                            best, best_t = name, t
                    row[group + suffix] = best
                    row[group + "_time" + suffix] = best_t if best else math.nan
            for suffix in ("", "_min"):
                row["ratio" + suffix] = (row["scipy_time" + suffix] / row["ours_time" + suffix]
                                         if row["ours" + suffix] and row["scipy" + suffix] else math.nan)
            row["goal_met"] = bool(row["ratio"] >= GOAL) if math.isfinite(row["ratio"]) else None
            rows.append(row)
    return rows


def format_table(rows: list[dict]) -> list[str]:
    """The table as text lines."""
    lines = [f"{'A':>5} {'error':>7}  {'fastest of ours':>22}  {'SciPy best':>20}  {'ratio':>6}  goal (>= {GOAL:g}x)"
             "  [ratio of the shortest times]"]

    def cell(name, t):
        return f"{name} {t * 1e3:8.2f} ms" if name and math.isfinite(t) else "not reached"

    def num(x):
        return f"{x:6.1f}" if math.isfinite(x) else "   n/a"

    for r in rows:
        goal = {True: "met", False: "NOT met", None: "n/a"}[r["goal_met"]]
        lines.append(f"{r['amplitude']:5g} {r['level']:7.0e}  {cell(r['ours'], r['ours_time']):>22}  "
                     f"{cell(r['scipy'], r['scipy_time']):>20}  {num(r['ratio'])}  {goal:<8}  "
                     f"[{num(r.get('ratio_min', math.nan)).strip()}]")
    return lines


def fitted_order(dt: Any, err: Any, floor: float, ceiling: float = 1e-2, points: int = 4) -> float:
    """Least-squares slope of log error vs log dt over the smallest steps: errors at or below `floor` skipped,
    the first above `ceiling` ends the range, at most `points` used (the rule of the Fortran scene)."""
    dt, err = np.asarray(dt, float), np.asarray(err, float)
    ok = np.isfinite(dt) & np.isfinite(err)
    xs, ys = [], []
    for i in np.argsort(dt[ok]):
        d, e = dt[ok][i], err[ok][i]
        if not e > floor:
            continue
        if e > ceiling:
            break
        xs.append(math.log(d))
        ys.append(math.log(e))
        if len(xs) == points:
            break
    if len(xs) < 2 or np.ptp(xs) == 0:
        return math.nan
    return float(np.polyfit(xs, ys, 1)[0])


# ------------------------------------------------------------------------------------------------ charts


def _panel_title(w: Scene, ia: int) -> str:
    """Title of the panel of amplitude `ia`: 'A = 1.9 (above A_s)'."""
    a = float(w.data["amplitude"][ia])
    p = w.params
    side = ""
    if "threshold_As" in p:
        side = " (below $A_s$)" if a < float(p["threshold_As"]) else " (above $A_s$)"
    return f"$A$ = {a:g}{side}"


def _suptitle(w: Scene, what: str) -> str:
    """Title of a chart: what it shows and the problem's parameters."""
    p = w.params
    return (f"{what}: {p['potential']}, $c$ = {fmt(p['c'])}, $\\Omega$ = {fmt(p['omega'])}, "
            f"$N$ = {p['n']}, $T$ = {fmt(p['t_final'])}, $\\gamma$ = {fmt(p['gamma'])}, "
            f"$\\beta$ = {fmt(p['beta'])}")


@styled
def draw_work_precision(w: Scene, peer: dict, rows: list[dict] | None = None):
    """Error of the injected energy vs wall time, log-log, one line per method, one panel per amplitude; the
    time SciPy's best needs divided by the goal (5) as a grey line: our points left of it meet the goal."""
    amps = np.asarray(w.data["amplitude"], float)
    rows = rows if rows is not None else equal_error_table(w, peer)
    fig, axes = subplots(1, len(amps), figsize=(5.2 * len(amps), 4.2), squeeze=False, sharey=True)
    floor = w.data.get("reference/error_energy")
    for ia, a in enumerate(amps):
        ax = axes[0, ia]
        lines = {**our_lines(w, ia), **(peer_lines(peer, a) if peer else {})}
        for name, ln in lines.items():
            st = dict(STYLE.get(name, {}))
            ls = st.pop("ls", "-")
            label = name if "tol" not in ln else f"SciPy {name}"
            ax.plot(ln["time"], np.maximum(ln["error"], 1e-16), ls=ls, ms=4, label=label, **st)
            if "tol" in ln and name == "DOP853":
                for tol, t, e in zip(ln["tol"], ln["time"], ln["error"]):
                    if round(math.log10(tol)) in (-3, -6, -9, -12):
                        ax.annotate(f"tol {tol:.0e}", (t, max(e, 1e-16)), textcoords="offset points",
                                    xytext=(4, 3), fontsize=6.5, color=STYLE["DOP853"]["color"])
        mine = [r for r in rows if r["amplitude"] == a and math.isfinite(r["scipy_time"])]
        if mine:
            ax.plot([r["scipy_time"] / GOAL for r in mine], [r["level"] for r in mine], color="0.55", ls=":",
                    lw=2.0, label=f"SciPy's best / {GOAL:g}")
        if floor is not None and np.isfinite(floor[ia]):
            ax.axhline(floor[ia], color="0.7", lw=0.8, ls="-.")
            ax.text(0.99, floor[ia], "reference's error estimate", transform=ax.get_yaxis_transform(), ha="right",
                    va="bottom", fontsize=6.5, color="0.45")
        ax.axhspan(min(LEVELS), max(LEVELS), color="0.93", zorder=-5, lw=0)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall time per run [s] (median)")
        ax.set_title(_panel_title(w, ia))
        if ia == 0:
            ax.set_ylabel("relative error of the injected energy")
        ax.legend(loc="lower left", fontsize=7, ncol=2)
    fig.suptitle(_suptitle(w, "Work-precision") + "\nshaded: the error levels of the goal (1e-2 .. 1e-8)")
    return fig


@styled
def draw_dt(w: Scene, peer: dict):
    """Error of the injected energy vs time step, log-log, the fitted orders in the legend; the SciPy peer
    against its mean step T/steps (its order: the same fit)."""
    d = w.data
    amps = np.asarray(d["amplitude"], float)
    fig, axes = subplots(1, len(amps), figsize=(5.2 * len(amps), 4.2), squeeze=False, sharey=True)
    floor = d.get("reference/error_energy")
    for ia, a in enumerate(amps):
        ax = axes[0, ia]
        fl = max(float(floor[ia]) if floor is not None else 0.0, 1e-13)
        for im, (name, ln) in enumerate(our_lines(w, ia).items()):
            st = dict(STYLE.get(name, {}))
            st.pop("ls", None)
            order = float(d["order_energy"][ia, im])
            ax.plot(ln["dt"], np.maximum(ln["error"], 1e-16), ls="-", ms=4,
                    label=f"{name}: order {order:.2f}" if math.isfinite(order) else name, **st)
        for name, ln in (peer_lines(peer, a) if peer else {}).items():
            st = dict(STYLE.get(name, {}))
            ls = st.pop("ls", "--")
            order = fitted_order(ln["mean_dt"], ln["error"], fl)
            ax.plot(ln["mean_dt"], np.maximum(ln["error"], 1e-16), ls=ls, ms=4,
                    label=f"SciPy {name} (mean step): order {order:.2f}" if math.isfinite(order)
                    else f"SciPy {name} (mean step)", **st)
        ax.axhline(fl, color="0.7", lw=0.8, ls="-.")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("time step dt (SciPy: T / accepted steps)")
        ax.set_title(_panel_title(w, ia))
        if ia == 0:
            ax.set_ylabel("relative error of the injected energy")
        ax.legend(loc="lower right", fontsize=7)
    fig.suptitle(_suptitle(w, "Error vs time step") + "\norders: least-squares slope over the (at most 4) "
                 "smallest steps with errors between the reference floor and 1e-2")
    return fig


# ------------------------------------------------------------------------------------------------ running


def base() -> Path:
    """Where the namelists' paths are relative to: the checkout, else (an installed command) the working
    directory."""
    return cli.checkout() or Path.cwd()


def output_of(nml: Path) -> Path:
    """The `&output file` of a namelist (relative to the repository, or outside one to the working directory)."""
    root = base()
    out = namelist.output_file(namelist.read(nml if nml.is_absolute() else root / nml))
    if out is None:
        raise PlotError(nml, "no '&output file'")
    return root / out


def run_scene(nml: Path, log: Callable) -> Path:
    """Run the scene with fpm in the repository, or outside one with the `supratrans` installed on PATH; the path
    of its file."""
    out = output_of(nml)
    t0 = time.monotonic()
    if cli.checkout() is None:
        cmd = [cli.installed("give the scene's file with --h5"), str(nml)]
    else:
        cmd = [*_fpm(), "run", "--profile", "release", "--", str(nml)]
    log(f"running: {' '.join(cmd[-5:] if len(cmd) > 2 else cmd)}")
    # the scene takes about a minute: the program's own progress lines (every few seconds at most, with the time
    # left) go on to stderr as it prints them; its last line names a failure
    proc = subprocess.Popen(cmd, cwd=base(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    lines = []
    for line in proc.stderr:
        lines.append(line)
        if "elapsed" in line:
            print(line.rstrip(), file=sys.stderr, flush=True)
    status = proc.wait()
    if status != 0:
        tail = ("".join(lines).strip() or "no output").splitlines()[-1]
        raise PlotError(nml, f"{Path(cmd[0]).name} run failed (status {status}): {tail}")
    log(f"  done in {time.monotonic() - t0:.0f} s: {out}")
    return out


def main(argv: list[str] | None = None) -> int:
    """The command line of `work_precision.py`; returns the exit status (0, 1 when the peer's model check fails,
    2 with one line on stderr)."""
    ap = cli.parser("work_precision.py", __doc__, argv)
    ap.add_argument("--nml", type=Path, default=Path("input/work_precision.nml"),
                    help="namelist of the scene (default input/work_precision.nml)")
    ap.add_argument("--h5", type=Path, help="use this work_precision file instead of running the scene")
    ap.add_argument("--peer", type=Path, help="use these peer points (JSON) instead of running the peer")
    ap.add_argument("--peer-out", type=Path, help="where to write the peer's points (default: "
                                                  "<file>_peer.json next to the file)")
    ap.add_argument("--methods", nargs="+", default=ps.DEFAULT_METHODS, choices=["DOP853", "RK45", "RK23"])
    ap.add_argument("--tols", nargs="+", type=float, default=ps.DEFAULT_TOLS, metavar="TOL")
    ap.add_argument("--repeats", type=int, default=5, help="timed solves per peer point (median; default 5)")
    ap.add_argument("--outdir", type=Path, help="folder of the charts (default postprocess/figures/ of the checkout)")
    ap.add_argument("--dpi", type=cli.dpi, default=DPI, help=f"resolution of the images (default {DPI})")
    ap.add_argument("-q", "--quiet", action="store_true", help="print only the table")
    args = ap.parse_args(argv)

    def log(*a):
        if not args.quiet:
            print(*a, file=sys.stderr, flush=True)

    try:
        outdir = args.outdir or figure_dir()
        h5 = args.h5
        if h5 is None:
            root = base()
            nml = args.nml if args.nml.is_absolute() else (root / args.nml)
            if not nml.is_file():
                raise PlotError(args.nml, "no such file")
            h5 = run_scene(nml.relative_to(root) if nml.is_relative_to(root) else nml, log)
        w = ps.read_work_precision(h5)
        if args.peer:
            peer = ps.read_points(args.peer)
        else:
            log("SciPy peer (same process, right after):")
            peer = ps.run_peer(w, methods=args.methods, tols=args.tols, repeats=args.repeats, log=log)
        rows = equal_error_table(w, peer)
        peer["equal_error_table"] = rows
        peer["goal"] = {"factor": GOAL, "met_everywhere": all(r["goal_met"] for r in rows)}
        if not args.peer:
            out = args.peer_out or output_path(w.path, "_peer.json")
            ps.write_points(peer, out)
            log(f"wrote {out}")
        for fig, name in ((draw_work_precision(w, peer, rows), "work_precision.png"),
                          (draw_dt(w, peer), "work_precision_dt.png")):
            path = save(fig, outdir / name, dpi=args.dpi)
            log(f"wrote {path} ({path.stat().st_size / 1024:.0f} kB)")
        check = peer.get("check", [])
        for c in check:
            print(f"model check A = {c['amplitude']:g}: SciPy DOP853 at tol {ps.CHECK_TOL:g} vs reference: "
                  f"relative difference {c['relative_error']:.1e} ({'ok' if c['passed'] else 'MISMATCH'})")
        print("\n".join(format_table(rows)))
        missed = [r for r in rows if r["goal_met"] is not True]
        if missed:
            print(f"goal ({GOAL:g}x at every level) NOT met at: " + "; ".join(
                f"A = {r['amplitude']:g}, {r['level']:.0e} ({r['ratio']:.1f}x)" for r in missed))
        else:
            print(f"goal ({GOAL:g}x at every level 1e-2 .. 1e-8): met")
        return 0 if all(c["passed"] for c in check) else 1
    except PlotError as exc:
        print(exc.line(), file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"error: {getattr(exc, 'filename', None) or args.outdir}: {exc.strerror or exc}", file=sys.stderr)
        return 2
