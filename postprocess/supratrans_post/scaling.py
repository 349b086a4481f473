"""Time and memory of supratrans against the chain length N, the final time T and the number of runs.

    python3 postprocess/scaling.py                                   # release build; prints the table only
    python3 postprocess/scaling.py -o postprocess/figures/scaling.png   # and draws the chart there
    python3 postprocess/scaling.py --exe build/.../supratrans -o scaling.png   # this executable, no fpm
    python3 postprocess/scaling.py --site-cost postprocess/data/site_cost.csv -o postprocess/figures/site_cost.png

Each point is one whole process (the release executable on a namelist of its own, output to a scratch folder): wall
time and peak resident memory from the kernel's accounting of that child (os.wait4). The paper-default run
(sine-Gordon, Omega = 0.9, A = 1.9, newton, dt = 0.05) is varied one parameter at a time: N = 200 .. 10^6 at T = 20
(N0 = 3N/4, one probe), T = 50 .. 800 at N = 200, and amplitude sweeps of 1 .. 100 runs at N = 200, T = 200.
It takes minutes. Nothing is written but the chart, and only where -o says.

With --site-cost nothing is run: the chart of the cost per site-step against N is drawn from the CSV file the
benchmark writes (`fpm run --example benchmark --profile release -- 7 scaling`: Newton steps alone, one thread,
processor time; columns n, ns_per_site_step, iterations_per_step, bytes_per_site_step, gb_per_s,
triad_gb_per_s), with the bandwidth those bytes take against the machine's triad bandwidth, and its rows printed.

Without --exe the executable is built with `fpm build --profile release` in the supratrans checkout (the one
holding this package, else the working directory or one above it); outside a checkout it is the `supratrans`
installed on PATH (README: `fpm install`). A run that fails, or no executable, gives one line `error: ...` and exit
status 2.
"""
from __future__ import annotations

import csv
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from . import cli, style
from .reader import PlotError

#: The points: (what is varied, its values); the other parameters as in `run_text`.
POINTS = (("N", (200, 1000, 10_000, 100_000, 1_000_000)), ("T", (50, 100, 200, 400, 800)), ("runs", (1, 10, 100)))
#: Axis label of each panel.
LABELS = {"N": "oscillators N (T = 20)", "T": "final time T (N = 200)", "runs": "runs of a sweep (N = 200, T = 200)"}


def executable() -> str:
    """The release executable, built by fpm in the checkout; outside one, the `supratrans` installed on PATH.
    PlotError when there is neither or the build fails."""
    root = cli.checkout()
    if root is None:
        return cli.installed("give the executable with --exe")
    try:
        subprocess.run(["fpm", "build", "--profile", "release"], cwd=root, check=True, capture_output=True)
        out = subprocess.run(["fpm", "run", "--profile", "release", "--runner", "echo"], cwd=root, check=True,
                             capture_output=True, text=True)
    except FileNotFoundError:
        raise PlotError("fpm", "not found (install it, or give the executable with --exe)") from None
    except subprocess.CalledProcessError as exc:
        raise PlotError(root, f"fpm failed (status {exc.returncode}): {' '.join(exc.cmd)}") from None
    return str(root / out.stdout.strip().splitlines()[-1].split()[0])


def measure(exe: str, text: str, folder: Path) -> tuple[float, float]:
    """Run one namelist; return (wall seconds, peak MiB). PlotError when the program fails."""
    nml = folder / "case.nml"
    nml.write_text(text)
    start = time.perf_counter()
    try:
        proc = subprocess.Popen([exe, str(nml)], cwd=folder, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                env=dict(os.environ, OMP_NUM_THREADS="1"))
    except OSError as exc:
        raise PlotError(exe, f"cannot run ({exc.strerror or exc})") from None
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    err = proc.stderr.read().decode(errors="replace")
    proc.stderr.close()
    if status != 0:
        last = (err.strip().splitlines() or ["no message"])[-1]
        raise PlotError(exe, f"failed (wait status {status}) on the namelist {' '.join(text.split())[:120]}: {last}")
    return wall, usage.ru_maxrss / 1024.0


def run_text(n: int, t_final: float, runs: int = 1) -> str:
    """The namelist of one point: N oscillators, final time T, an amplitude sweep of `runs` runs when > 1."""
    scene = ""
    if runs > 1:
        scene = (f"&scene kind = 'amplitude_sweep', amplitude_min = 1.0, amplitude_max = {1.0 + 0.01 * (runs - 1):.2f},"
                 " amplitude_step = 0.01 /\n")
    return (f"&chain n = {n}, n0 = {3 * n // 4} /\n&drive amplitude = 1.9, omega = 0.9 /\n"
            f"&numerics t_final = {t_final} /\n&record probes = {min(60, n)} /\n{scene}"
            "&output file = 'out.h5', overwrite = .true., quiet = .true. /\n")


def measure_all(exe: str) -> list[tuple[str, int, float, float]]:
    """(varied, value, wall s, peak MiB) of every point of POINTS, in a scratch folder removed afterwards."""
    rows = []
    # progress on stderr every few seconds (minutes in all): each point weighted by its oscillator-steps (dt = 0.05)
    # at 60 ns, over a start-up of 20 ms
    steps = {"N": lambda v: v * 400, "T": lambda v: 200 * v / 0.05, "runs": lambda v: 200 * 4000 * v}
    progress = cli.Progress("scaling", [0.02 + 6e-8 * steps[kind](v) for kind, values in POINTS for v in values],
                            "points")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for kind, values in POINTS:
            for v in values:
                text = {"N": lambda: run_text(v, 20.0), "T": lambda: run_text(200, float(v)),
                        "runs": lambda: run_text(200, 200.0, v)}[kind]()
                rows.append((kind, v, *measure(exe, text, folder)))
                progress.step()
    return rows


def table(rows: list[tuple[str, int, float, float]]) -> list[str]:
    """The rows as a Markdown table."""
    return ["| varied | value | wall s | peak MiB |", "| --- | --- | --- | --- |",
            *(f"| {kind} | {value} | {wall:.3f} | {mib:.1f} |" for kind, value, wall, mib in rows)]


@style.styled
def draw(rows: list[tuple[str, int, float, float]]):
    """The chart: wall time and peak memory against N, T and the number of runs, log-log."""
    fig, axes = style.subplots(1, 3, figsize=(12, 3.6))
    for ax, (kind, _) in zip(axes, POINTS):
        pts = [(v, w, m) for k, v, w, m in rows if k == kind]
        x = [p[0] for p in pts]
        ax.loglog(x, [p[1] for p in pts], "o-", label="wall time (s)")
        ax.loglog(x, [p[2] for p in pts], "s--", label="peak memory (MiB)")
        ax.set_xlabel(LABELS[kind])
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend()
    fig.suptitle("supratrans: one process per point, one thread (newton, dt = 0.05)")
    return fig


#: The columns of the benchmark's site-cost CSV (app/bench/bench_scaling.f90), in order.
SITE_COST_COLUMNS = ("n", "ns_per_site_step", "iterations_per_step", "bytes_per_site_step", "gb_per_s",
                     "triad_gb_per_s")


def read_site_cost(path: Path) -> list[dict[str, float]]:
    """The rows of the benchmark's site-cost CSV, sorted by N; PlotError when the file is missing, its header is not
    SITE_COST_COLUMNS, a value is not a positive finite number, or it has no row."""
    try:
        with open(path, newline="") as f:
            table = list(csv.reader(f))
    except OSError as exc:
        raise PlotError(path, f"cannot read ({exc.strerror or exc})") from None
    if not table or tuple(c.strip() for c in table[0]) != SITE_COST_COLUMNS:
        raise PlotError(path, f"not a site-cost table (header must be {','.join(SITE_COST_COLUMNS)})")
    rows = []
    for line, cells in enumerate(table[1:], start=2):
        if not cells:
            continue
        try:
            values = [float(c) for c in cells]
        except ValueError:
            raise PlotError(path, f"line {line}: not a number in {','.join(cells)}") from None
        if len(values) != len(SITE_COST_COLUMNS) or not all(0.0 < v < float("inf") for v in values):
            raise PlotError(path, f"line {line}: expected {len(SITE_COST_COLUMNS)} positive finite numbers")
        rows.append(dict(zip(SITE_COST_COLUMNS, values)))
    if not rows:
        raise PlotError(path, "no rows")
    return sorted(rows, key=lambda r: r["n"])


def site_cost_table(rows: list[dict[str, float]]) -> list[str]:
    """The rows as a Markdown table, with each cost relative to the smallest N's."""
    first = rows[0]["ns_per_site_step"]
    return ["| N | ns per site-step | relative to the smallest N | Newton iterations per step | bytes per site-step |"
            " GB/s | of the triad's |", "| --- | --- | --- | --- | --- | --- | --- |",
            *(f"| {int(r['n'])} | {r['ns_per_site_step']:.2f} | {r['ns_per_site_step'] / first:.3f} | "
              f"{r['iterations_per_step']:.3f} | {r['bytes_per_site_step']:.0f} | {r['gb_per_s']:.2f} | "
              f"{r['gb_per_s'] / r['triad_gb_per_s']:.2f} |" for r in rows)]


@style.styled
def draw_site_cost(rows: list[dict[str, float]]):
    """The chart: ns per site-step against N (log N), the 1.2 times line of the smallest N's cost; beside it the
    bandwidth the step's bytes take against the machine's triad bandwidth."""
    fig, (ax, bw) = style.subplots(1, 2, figsize=(10, 3.6))
    n = [r["n"] for r in rows]
    cost = [r["ns_per_site_step"] for r in rows]
    ax.semilogx(n, cost, "o-", label="Newton step (one thread)")
    ax.axhline(1.2 * cost[0], color="0.5", ls="--", lw=1, label=f"1.2 x the cost at N = {int(n[0])}")
    ax.set_ylim(0.0, 1.5 * max(cost))
    ax.set_xlabel("oscillators N")
    ax.set_ylabel("ns per site-step")
    ax.legend()
    bw.semilogx(n, [r["gb_per_s"] for r in rows], "o-", label="the step's bytes / its time")
    bw.semilogx(n, [r["triad_gb_per_s"] for r in rows], "s--", label="triad (measured in the same run)")
    bw.set_ylim(0.0, 1.2 * max(max(r["gb_per_s"], r["triad_gb_per_s"]) for r in rows))
    bw.set_xlabel("oscillators N")
    bw.set_ylabel("GB/s")
    bw.legend()
    for a in (ax, bw):
        a.grid(True, which="both", alpha=0.3)
    fig.suptitle("supratrans: cost per site-step against N (benchmark, processor time)")
    return fig


def main(argv: list[str] | None = None) -> int:
    """The command line of `scaling.py`; returns the exit status (0, or 2 with one line on stderr)."""
    ap = cli.parser("scaling.py", __doc__, argv)
    ap.add_argument("-o", "--output", type=Path, metavar="IMAGE",
                    help="draw the chart into this image (default: none, the table only)")
    ap.add_argument("--exe", help="the supratrans executable to time (default: fpm's release build)")
    ap.add_argument("--dpi", type=cli.dpi, default=110, help="resolution of the image (default 110)")
    ap.add_argument("--site-cost", type=Path, metavar="CSV",
                    help="run nothing: the cost per site-step against N from the benchmark's CSV")
    args = ap.parse_args(argv)
    try:
        if args.output:
            style.image_format(args.output)
        if args.site_cost:
            site = read_site_cost(args.site_cost)
            print("\n".join(site_cost_table(site)))
            if args.output:
                path = style.save(draw_site_cost(site), args.output, dpi=args.dpi)
                print(f"wrote {path}", file=sys.stderr)
            return 0
        rows = measure_all(args.exe or executable())
        print("\n".join(table(rows)))
        if args.output:
            path = style.save(draw(rows), args.output, dpi=args.dpi)
            print(f"wrote {path}", file=sys.stderr)
    except PlotError as exc:
        print(exc.line(), file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"error: {getattr(exc, 'filename', None) or args.output}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    return 0
