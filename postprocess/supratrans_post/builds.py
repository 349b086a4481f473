"""Whole-process time of supratrans built four ways: the default release build (fpm's release flags: SSE2 on
x86-64), the host build (the same plus --host-flags, default -march=native: the machine's vector units), and each of
them with HDF5, szip, zlib, LAPACK, BLAS, libgfortran and libgcc linked statically; and the naive program.

    python3 postprocess/builds.py                                  # builds what is missing, then times (minutes)
    python3 postprocess/builds.py --host-flags "-march=x86-64-v3" --runs 21
    python3 postprocess/builds.py --no-static                      # the two dynamic builds only

Each figure is a whole process (the executable on a namelist, output to a scratch folder, OMP_NUM_THREADS = 1):
CPU seconds (user + system) and wall seconds from the kernel's accounting of that child (os.wait4). The builds run
in turn (round after round, after one warm-up round), and every ratio is the median over the rounds of the ratio
within a round, so that a machine whose speed drifts still compares like with like. Two workloads: the
paper-default run (sine-Gordon, Omega = 0.9, A = 1.9, N = 200, T = 200, newton; start-up and output included, as a
user runs it), paired also against the naive program (app/naive), and a 40-amplitude sweep of that chain (A = 1.20
.. 1.98, T = 200: the computation dominates).

The builds are made with fpm through .ci/with_commit in the checkout (the one holding this package or the working
directory, or --checkout DIR from anywhere, an installed command for one; `fpm build --profile release [--flag
HOST_FLAGS]`: fpm keeps each set of flags in a build directory of its own, so the default build is untouched). The
static executables are linked by hand from fpm's own link line (fpm 0.12 cannot link one target statically without
changing the others), with the static archives the compiler finds (Debian: libhdf5-dev, libsz2/libaec-dev,
zlib1g-dev, liblapack-dev, libblas-dev), into a folder of the build directory; a fully static executable (-static)
links but crashes at start with glibc's static libgomp, so libc, libm, libmvec, libgomp and libquadmath stay shared.
A build that fails gives one line `error: ...` and exit status 2.
"""
from __future__ import annotations

import os
import shlex
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from . import cli
from .reader import PlotError

#: The paper-default run (the program's defaults are the paper's: N = 200, Omega = 0.9, T = 200, dt = 0.05).
PAPER = ("&drive amplitude = 1.9 /\n"
         "&output file = 'out.h5', overwrite = .true., quiet = .true. /\n")
#: The 40-amplitude sweep of the in-process benchmark (app/bench/benchmark.f90), one thread.
SWEEP = ("&scene kind = 'amplitude_sweep', amplitude_min = 1.2, amplitude_max = 1.98, amplitude_step = 0.02 /\n"
         "&output file = 'out.h5', overwrite = .true., quiet = .true. /\n")
#: fpm's HDF5 libraries (the `hdf5` dependency) and LAPACK/BLAS (`link` of fpm.toml) on its link line.
DYNAMIC_LIBS = ("-lhdf5", "-lhdf5hl_fortran", "-lhdf5_fortran", "-lhdf5_hl", "-llapack", "-lblas")
#: The static archives that replace them, in link order (HDF5's Fortran layer, then HDF5 and what it needs).
STATIC_ARCHIVES = ("libhdf5_fortran.a", "libhdf5.a", "libsz.a", "libaec.a", "libz.a", "liblapack.a", "libblas.a")


def fpm(root: Path, *args: str) -> str:
    """Run fpm through .ci/with_commit in the checkout; its output. PlotError when it fails."""
    try:
        proc = subprocess.run(["sh", str(root / ".ci" / "with_commit"), "fpm", *args], cwd=root, check=True,
                              capture_output=True, text=True)
    except FileNotFoundError:
        raise PlotError("fpm", "not found") from None
    except subprocess.CalledProcessError as exc:
        tail = (exc.stdout + exc.stderr).strip().splitlines()[-1:] or ["no output"]
        raise PlotError(root, f"fpm {' '.join(args)} failed: {tail[0]}") from None
    return proc.stdout


def build(root: Path, flags: str) -> tuple[Path, list[str]]:
    """Build the release profile with `flags` added (none: the default build); the executable and fpm's link line
    of it (as words)."""
    extra = ["--flag", flags] if flags else []
    out = fpm(root, "build", "--profile", "release", *extra, "--verbose")
    link = [line for line in out.splitlines()
            if line.startswith(" + ") and " -o " in line and line.rstrip().endswith("/app/supratrans")]
    if not link:
        raise PlotError(root, "fpm printed no link line of app/supratrans (with_commit relinks at every call)")
    words = shlex.split(link[-1][3:])
    return root / words[-1], words


def archive(compiler: str, name: str, folders: list[str]) -> str | None:
    """The path of a static archive: in `folders` (the link line's -L), else where the compiler finds it."""
    for folder in folders:
        if (Path(folder) / name).is_file():
            return str(Path(folder) / name)
    try:
        found = subprocess.run([compiler, f"-print-file-name={name}"], capture_output=True, text=True).stdout.strip()
    except OSError:
        return None
    return found if found and Path(found).is_file() else None


def link_static(root: Path, words: list[str], out: Path) -> Path:
    """Link fpm's objects again into `out` with the libraries of STATIC_ARCHIVES static; the executable."""
    folders = [w[2:] for w in words if w.startswith("-L")]
    paths = [archive(words[0], name, folders) for name in STATIC_ARCHIVES]
    missing = [name for name, p in zip(STATIC_ARCHIVES, paths) if p is None]
    if missing:
        raise PlotError(out, f"static archives not found: {', '.join(missing)}")
    head = [w for w in words[:words.index("-o")] if w not in DYNAMIC_LIBS]
    out.parent.mkdir(parents=True, exist_ok=True)
    cmd = [*head, *paths, "-static-libgfortran", "-static-libgcc", "-o", str(out)]
    proc = subprocess.run(cmd, cwd=root, capture_output=True, text=True)
    if proc.returncode != 0:
        raise PlotError(out, f"static link failed: {(proc.stderr.strip().splitlines() or ['?'])[-1]}")
    return out


def naive(root: Path) -> Path:
    """The naive program (app/naive), release profile."""
    out = fpm(root, "run", "--profile", "release", "--example", "naive", "--runner", "echo")
    return root / out.strip().splitlines()[-1].split()[0]


def executables(root: Path, host_flags: str, static: bool) -> dict[str, Path]:
    """Name -> executable of every build to time (built or linked here in the checkout `root`)."""
    exes = {}
    for name, flags in (("default", ""), ("host", host_flags)):
        print(f"  builds: the {name} build (fpm build --profile release{' --flag ' + repr(flags) if flags else ''}; "
              "minutes when it compiles everything)", file=sys.stderr, flush=True)
        exe, words = build(root, flags)
        exes[name] = exe
        if static:
            exes[f"{name}-static"] = link_static(root, words, exe.parent / "static" / "supratrans")
    return exes


def measure(cmd: list[str], folder: Path) -> tuple[float, float]:
    """One whole process: (CPU seconds, wall seconds). PlotError when it fails."""
    start = time.perf_counter()
    try:
        proc = subprocess.Popen(cmd, cwd=folder, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                env=dict(os.environ, OMP_NUM_THREADS="1"))
    except OSError as exc:
        raise PlotError(cmd[0], f"cannot run ({exc.strerror or exc})") from None
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    err = proc.stderr.read().decode(errors="replace")
    proc.stderr.close()
    if status != 0:
        raise PlotError(cmd[0], f"failed (wait status {status}): {(err.strip().splitlines() or ['?'])[-1]}")
    return usage.ru_utime + usage.ru_stime, wall


def rounds(commands: dict[str, list[str]], runs: int, folder: Path) -> dict[str, list[tuple[float, float]]]:
    """Every command once per round, in turn, for one warm-up round and `runs` counted ones."""
    times: dict[str, list[tuple[float, float]]] = {name: [] for name in commands}
    progress = cli.Progress("builds", (runs + 1) * len(commands), "processes")    # every few seconds, on stderr
    for r in range(runs + 1):
        for name, cmd in commands.items():
            t = measure(cmd, folder)
            if r > 0:
                times[name].append(t)
            progress.step()
    return times


def report(title: str, times: dict[str, list[tuple[float, float]]], base: str) -> list[str]:
    """The table of one workload: medians and the paired ratios to `base` (and to the naive program when timed)."""
    others = [b for b in (base, "naive") if b in times]
    head = "".join(f" {'cpu/' + b:>13s} {'wall/' + b:>13s}" for b in others)
    lines = [f"# {title}: medians of {len(times[base])} rounds; a ratio is the median over the rounds of the "
             "ratio within a round", f"{'build':16s} {'cpu_ms':>9s} {'wall_ms':>9s}{head}"]
    for name, t in times.items():
        row = f"{name:16s} {1000*statistics.median(c for c, _ in t):9.1f} {1000*statistics.median(w for _, w in t):9.1f}"
        for b in others:
            for k in (0, 1):
                row += f" {statistics.median(a[k]/r[k] for a, r in zip(t, times[b])):13.3f}"
        lines.append(row)
    return lines


def main(argv: list[str] | None = None) -> int:
    """The command line of `builds.py`; returns the exit status (0, or 2 with one line on stderr)."""
    ap = cli.parser("builds.py", __doc__, argv)
    ap.add_argument("--host-flags", default="-march=native",
                    help="compiler flags of the host build, added to fpm's release flags (default -march=native)")
    ap.add_argument("--runs", type=int, default=11, help="counted rounds of the paper-default run (default 11)")
    ap.add_argument("--sweep-runs", type=int, default=5,
                    help="counted rounds of the 40-amplitude sweep (default 5; 0: no sweep)")
    ap.add_argument("--no-static", action="store_true", help="time the dynamic builds only")
    ap.add_argument("--checkout", type=Path, metavar="DIR",
                    help="the supratrans checkout to build (default: the one holding this package, else the working "
                         "directory's)")
    args = ap.parse_args(argv)
    if not 1 <= args.runs <= 1000 or not 0 <= args.sweep_runs <= 1000:
        ap.error("--runs must be 1 .. 1000 and --sweep-runs 0 .. 1000")
    try:
        root = cli.repository(args.checkout, "--checkout DIR")
        exes = executables(root, args.host_flags, not args.no_static)
        with tempfile.TemporaryDirectory() as tmp:
            folder = Path(tmp)
            (folder / "paper.nml").write_text(PAPER)
            (folder / "sweep.nml").write_text(SWEEP)
            paper = {name: [str(exe), "paper.nml"] for name, exe in exes.items()}
            paper["naive"] = [str(naive(root))]
            print(f"host flags: {args.host_flags}")
            print("\n".join(report("paper-default run, whole process", rounds(paper, args.runs, folder),
                                   "default")))
            if args.sweep_runs:
                sweep = {name: [str(exe), "sweep.nml"] for name, exe in exes.items()}
                print("\n".join(report("40-amplitude sweep, whole process, one thread",
                                       rounds(sweep, args.sweep_runs, folder), "default")))
    except PlotError as exc:
        print(exc.line(), file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"error: {getattr(exc, 'filename', None) or 'builds'}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    return 0
