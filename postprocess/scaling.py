#!/usr/bin/env python3
"""Time and memory of supratrans against the chain length N, the final time T and the number of runs.

    python3 postprocess/scaling.py            # release build; prints the table, draws postprocess/figures/scaling.png

Each point is one whole process (the release executable on a namelist of its own, output to a scratch folder): wall
time and peak resident memory from the kernel's accounting of that child (os.wait4). The paper-default run
(sine-Gordon, Omega = 0.9, A = 1.9, newton, dt = 0.05) is varied one parameter at a time: N = 200 .. 10^6 at T = 20
(N0 = 3N/4, one probe), T = 50 .. 800 at N = 200, and amplitude sweeps of 1 .. 100 runs at N = 200, T = 200.
"""
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def executable():
    subprocess.run(["fpm", "build", "--profile", "release"], cwd=ROOT, check=True, capture_output=True)
    out = subprocess.run(["fpm", "run", "--profile", "release", "--runner", "echo"], cwd=ROOT, check=True,
                         capture_output=True, text=True)
    return str(ROOT / out.stdout.strip().splitlines()[-1].split()[0])


def measure(exe, text, folder):
    """Run one namelist; return (wall seconds, peak MiB)."""
    nml = folder / "case.nml"
    nml.write_text(text)
    start = time.perf_counter()
    proc = subprocess.Popen([exe, str(nml)], cwd=folder, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            env=dict(os.environ, OMP_NUM_THREADS="1"))
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    err = proc.stderr.read().decode()
    proc.stderr.close()
    if status != 0:
        raise RuntimeError(f"supratrans failed on\n{text}\n{err}")
    return wall, usage.ru_maxrss / 1024.0


def run_text(n, t_final, runs=1):
    scene = ""
    if runs > 1:
        scene = (f"&scene kind = 'amplitude_sweep', amplitude_min = 1.0, amplitude_max = {1.0 + 0.01 * (runs - 1):.2f},"
                 " amplitude_step = 0.01 /\n")
    return (f"&chain n = {n}, n0 = {3 * n // 4} /\n&drive amplitude = 1.9, omega = 0.9 /\n"
            f"&numerics t_final = {t_final} /\n&record probes = {min(60, n)} /\n{scene}"
            "&output file = 'out.h5', overwrite = .true., quiet = .true. /\n")


def main():
    exe = executable()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for n in (200, 1000, 10_000, 100_000, 1_000_000):
            rows.append(("N", n, *measure(exe, run_text(n, 20.0), folder)))
        for t in (50, 100, 200, 400, 800):
            rows.append(("T", t, *measure(exe, run_text(200, float(t)), folder)))
        for runs in (1, 10, 100):
            rows.append(("runs", runs, *measure(exe, run_text(200, 200.0, runs), folder)))
    print("| varied | value | wall s | peak MiB |")
    print("| --- | --- | --- | --- |")
    for kind, value, wall, mib in rows:
        print(f"| {kind} | {value} | {wall:.3f} | {mib:.1f} |")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(12, 3.6))
    for ax, kind, label in zip(axes, ("N", "T", "runs"), ("oscillators N (T = 20)", "final time T (N = 200)",
                                                            "runs of a sweep (N = 200, T = 200)")):
        pts = [(v, w, m) for k, v, w, m in rows if k == kind]
        x = [p[0] for p in pts]
        ax.loglog(x, [p[1] for p in pts], "o-", label="wall time (s)")
        ax.loglog(x, [p[2] for p in pts], "s--", label="peak memory (MiB)")
        ax.set_xlabel(label)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend()
    fig.suptitle("supratrans: one process per point, one thread (newton, dt = 0.05)")
    fig.tight_layout()
    out = Path(__file__).resolve().parent / "figures" / "scaling.png"
    fig.savefig(out, dpi=110)
    print(f"wrote {out}", file=sys.stderr)


if __name__ == "__main__":
    main()
