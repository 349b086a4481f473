"""Time and memory of supratrans against the chain length N, the final time T and the number of runs.

    python3 postprocess/scaling.py                                   # release build; prints the table only
    python3 postprocess/scaling.py -o postprocess/figures/scaling.png   # and draws the chart there
    python3 postprocess/scaling.py --exe build/.../supratrans -o scaling.png   # this executable, no fpm

Each point is one whole process (the release executable on a namelist of its own, output to a scratch folder): wall
time and peak resident memory from the kernel's accounting of that child (os.wait4). The paper-default run
(sine-Gordon, Omega = 0.9, A = 1.9, newton, dt = 0.05) is varied one parameter at a time: N = 200 .. 10^6 at T = 20
(N0 = 3N/4, one probe), T = 50 .. 800 at N = 200, and amplitude sweeps of 1 .. 100 runs at N = 200, T = 200.
It takes minutes. Nothing is written but the chart, and only where -o says.

Without --exe the executable is built with `fpm build --profile release` in the supratrans checkout (the one
holding this package, else the working directory or one above it). A run that fails, or no checkout, gives one
line `error: ...` and exit status 2.
"""
from __future__ import annotations

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
    """The release executable, built by fpm in the checkout; PlotError when there is none or the build fails."""
    root = cli.repository()
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
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for kind, values in POINTS:
            for v in values:
                text = {"N": lambda: run_text(v, 20.0), "T": lambda: run_text(200, float(v)),
                        "runs": lambda: run_text(200, 200.0, v)}[kind]()
                rows.append((kind, v, *measure(exe, text, folder)))
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


def main(argv: list[str] | None = None) -> int:
    """The command line of `scaling.py`; returns the exit status (0, or 2 with one line on stderr)."""
    ap = cli.parser("scaling.py", __doc__, argv)
    ap.add_argument("-o", "--output", type=Path, metavar="IMAGE",
                    help="draw the chart into this image (default: none, the table only)")
    ap.add_argument("--exe", help="the supratrans executable to time (default: fpm's release build)")
    ap.add_argument("--dpi", type=cli.dpi, default=110, help="resolution of the image (default 110)")
    args = ap.parse_args(argv)
    try:
        if args.output:
            style.image_format(args.output)
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
