"""Run every scene of input/ and draw every figure of the paper into one folder.

    python3 postprocess/make_figures.py                  # run input/*.nml, draw into postprocess/figures/
    python3 postprocess/make_figures.py --quick          # coarser grids, out/quick/, for a fast check
    python3 postprocess/make_figures.py --no-run         # only draw, from the files already in out/
    python3 postprocess/make_figures.py --only fig2 bif1 # some figures (names: the input files' stems)

Each namelist of a scene drawn here (timeseries, amplitude_sweep, map, bifurcation, and the speed/accuracy
scenes stability and work_precision; others are listed and skipped) is run with
`fpm run --profile release -- input/X.nml`, in the paper's order (Fig. 1, 2, 3, 3-and-a-half, 4, 11, Bif1-3, then
any other input), one line of progress each:

    [5/13] input/fig2.nml ... 45 s

(on a terminal the line shows the program's own progress while it runs; its whole output goes to
out/logs/X.log). A scene that fails is reported and the others go on. A sweep interrupted (Ctrl-C) resumes
from its journal when run again (Ctrl-C or `kill` stops the running scene too); meanwhile `--no-run` draws
its partial snapshot, marked as such.
Then every figure is drawn: Fig. 1 from the four fig1_* runs, one figure per other file, named after its
input file (fig2.png, ..., bif3.png), with the numbers each figure shows printed below it. Charts of several
files: fold_sg.png and fold_bif1.png lay the fold line over their scan (SCAN_OF), fold_hb_sg.png the fold line
by harmonic balance over the same scan and beside fold_sg's fold line when its file is there (run now or
before: SHOOTING_OF); ramp090.png the scans of input/ramp090_t*.nml against their ramp time next to the fold of
fold_sg_090 (PREFIXES, COMPANIONS); threshold_sg.png the fold line, the scan, the hysteresis window and A_s of the
undamped sine-Gordon chain (COMBINED). `--only ramp090`, `--only threshold_sg` or `--only fold_hb_sg` runs the
files they need too. A `stability` file is drawn by chart_stability.py; a `work_precision` file by
work_precision.py, which first times the SciPy peer in the same process (with --no-run it reuses the peer points
saved next to the file, if there are any).
With --quick the namelists are copied (read and written with f90nml) to out/quick/input/, the steps of their
scene grids scaled (amplitude_step x 5, omega_step x 2, x 10 for a fold line, resolution x 5, coarse_step x 2,
stair_height x 5; a continuation by harmonic balance from Omega = 0.15 up, at least three frequencies and the first
three c_values: namelist.QUICK_HB), their output in out/quick/ (overwritten), their figures' titles marked
"quick". Every figure is drawn at 200 dpi (style.DPI) unless --dpi says, each PNG with a vector PDF of the same
name beside it.
Outside a checkout (an installed `supratrans-figures`) the namelists' output paths are relative to the working
directory, the figures go where --outdir says (asked for in one line), and the namelists run with the `supratrans`
installed on PATH (README: `fpm install`), or not at all with --no-run. When the output is not a terminal the
program's own progress lines (elapsed, time left: every few seconds at most) are printed below the scene's line,
and fpm's build lines below the build's (one every 4 s at most).
Exit status 0 when every scene ran and every figure was drawn, 1 otherwise, 2 with one line on stderr when
nothing could be done.
"""
from __future__ import annotations

import argparse
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

from . import cli, figures, namelist, style
from .charts import stability as chart_stability
from .charts import work_precision as chart_work_precision
from .reader import PlotError, open_scene, output_path

#: The repository: the namelists' output paths are relative to it, and fpm runs there (the checkout holding this
#: package, else the one the command is started in; see cli.checkout).
ROOT = cli.checkout() or Path.cwd()
#: fpm through .ci/with_commit, so that the program built (and rebuilt by `fpm run`) records the repository's
#: commit in /provenance fixed at build (fpm cannot run git itself; plain fpm reads it at run time instead).
FPM = ["sh", str(ROOT / ".ci" / "with_commit"), "fpm"]
#: Order of the figures (the paper's), by input file stem or its prefix.
ORDER = ["fig1", "fig2", "fig3", "fig3half", "fig4", "fig11", "bif1", "bif2", "bif3"]
#: Scenes drawn by the charts of the speed/accuracy study, besides the figures' scenes.
CHARTS = ("stability", "work_precision")
#: Fold lines drawn over the scan thresholds of a bifurcation diagram: {continuation input: bifurcation input}.
SCAN_OF = {"fold_sg": "bif_undamped_sg", "fold_bif1": "bif1", "fold_hb_sg": "bif_undamped_sg"}
#: Fold lines by harmonic balance drawn beside the shooting scene's fold line of the same chain when its file is
#: there (run now, or before: with --only it is not run, the shooting fold line costing 100 times the harmonic
#: balance's, 23 min at --quick): {harmonic-balance input: shooting input}.
SHOOTING_OF = {"fold_hb_sg": "fold_sg"}
#: Fold lines by harmonic balance drawn beside the curves of a bifurcation diagram that share their chain (the
#: undamped sine-Gordon curve of each), from their file when it is there (run now or before, as SHOOTING_OF):
#: {bifurcation input: harmonic-balance input}.
FOLD_OF = {"bif1": "fold_hb_sg", "bif2": "fold_hb_sg", "bif3": "fold_hb_sg", "bif_undamped_sg": "fold_hb_sg"}
#: Figures made of several namelists by their stems' prefix: {prefix: figure} (Fig. 1's four runs; the scans at
#: Omega = 0.9 for each ramp time, input/ramp090_t*.nml).
PREFIXES = {"fig1_": "fig1", "ramp090_": "ramp090"}
#: Files a figure needs besides its own namelists: {figure: (input stems)}. `--only FIGURE` runs them too. The
#: ramp chart lays the fold of input/fold_sg_090.nml over its scans; the chart `threshold_sg` has no namelist of its
#: own: the fold line, the scan and the hysteresis window of the undamped sine-Gordon chain, with A_s.
COMPANIONS = {"ramp090": ("fold_sg_090",), "threshold_sg": ("fold_sg", "bif_undamped_sg", "hysteresis"),
              "fold_hb_sg": ("bif_undamped_sg",)}
#: Charts drawn from other figures' files only: {chart: (fold line, scan, hysteresis) input stems}.
COMBINED = {"threshold_sg": ("fold_sg", "bif_undamped_sg", "hysteresis")}
#: A line of fpm's build progress: `[ 45%] Compiling...`.
BUILD_LINE = re.compile(r"^\[ *[0-9]+%\]")
#: Resolution of figures that need another than the house style's style.DPI (200), unless --dpi says: none now.
FIGURE_DPI: dict[str, int] = {}


# ------------------------------------------------------------------------------------------------ namelists


class Job:
    """One namelist of input/: its scene, its output file, the figure it belongs to."""

    def __init__(self, nml: Path) -> None:
        self.nml = Path(nml)
        parsed = namelist.read(self.nml)
        self.kind = namelist.scene_kind(parsed)
        out = namelist.output_file(parsed)
        self.output = (ROOT / out) if out else None
        self.stem = self.nml.stem
        self.figure = next((f for p, f in PREFIXES.items() if self.stem.startswith(p)), self.stem)

    def sort_key(self) -> tuple:
        """The paper's order (ORDER), then by name."""
        return (ORDER.index(self.figure) if self.figure in ORDER else len(ORDER), self.figure, self.stem)

    def rel(self, p: Path) -> str:
        """A path relative to the repository when it is inside it."""
        try:
            return str(Path(p).relative_to(ROOT))
        except ValueError:
            return str(p)


def quick_copy(job: Job, folder: Path) -> Job:
    """A copy of the job's namelist with coarser scene grids (namelist.QUICK) and its output under `folder`."""
    out = folder / (job.output.name if job.output else job.stem + ".h5")
    copy = namelist.quick_copy(job.nml, folder / "input" / job.nml.name, out)
    q = Job(copy)
    q.stem, q.figure = job.stem, job.figure
    return q


# ------------------------------------------------------------------------------------------------ running


def run(cmd: list[str], log: Path, label: str, tty: bool, relayed: list[str] | None = None) -> int:
    """Run `cmd` in the repository, its output into `log`; on a terminal, show its last line after `label`;
    otherwise print the program's own progress lines (those with the time elapsed, which it prints every few
    seconds at most) and fpm's build lines (`[ 45%] ...`, at most one every cli.PROGRESS_EVERY seconds or
    SUPRATRANS_PROGRESS_EVERY) on lines of their own, and append them to `relayed`."""
    log.parent.mkdir(parents=True, exist_ok=True)
    every = cli.progress_every()
    last = time.monotonic()
    with open(log, "w") as fh:
        proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                bufsize=1)
        try:
            for line in proc.stdout:
                fh.write(line)
                fh.flush()
                if tty and line.strip():
                    width = max(10, os.get_terminal_size().columns - len(label) - 2) if sys.stdout.isatty() else 60
                    print(f"\r{label} {line.strip()[:width]}\033[K", end="", flush=True)
                elif not tty and ("elapsed" in line or (BUILD_LINE.match(line)
                                                        and time.monotonic() - last >= every)):
                    last = time.monotonic()
                    print(("" if relayed else "\n") + "    " + line.strip(), flush=True)
                    if relayed is not None:
                        relayed.append(line)
        except KeyboardInterrupt:
            proc.terminate()
            proc.wait()
            raise
        return proc.wait()


def _interrupt(signum: int, frame: object) -> None:
    """SIGTERM as Ctrl-C: the running scene is stopped too."""
    raise KeyboardInterrupt


def tail(path: Path, n: int = 3) -> list[str]:
    """The last `n` non-blank lines of a log ([] when it cannot be read)."""
    try:
        lines = [x for x in Path(path).read_text().splitlines() if x.strip()]
    except OSError:
        return []
    return lines[-n:]


def _parser(argv: list[str] | None = None) -> argparse.ArgumentParser:
    """The options of make_figures.py (usage and epilog from the module documentation)."""
    ap = cli.parser("make_figures.py", __doc__, argv)
    ap.add_argument("--outdir", type=Path, help="folder of the images (default postprocess/figures/, "
                                                "with --quick out/quick/figures/)")
    ap.add_argument("--quick", action="store_true", help="coarser scene grids (steps x 2..5), outputs in out/quick/")
    ap.add_argument("--no-run", action="store_true", help="do not run the program: draw from the files there are")
    ap.add_argument("--only", nargs="+", metavar="NAME", help="only these figures (fig1, fig2, ..., bif3)")
    ap.add_argument("--input", type=Path, default=ROOT / "input", help="folder of the namelists (default input/)")
    ap.add_argument("--logs", type=Path, help="folder of the program's output, one log per namelist "
                                              "(default out/logs/, with --quick out/quick/logs/)")
    ap.add_argument("--dpi", type=cli.dpi, help=f"resolution of the images (default {style.DPI})")
    return ap


def _jobs(args: argparse.Namespace) -> tuple[list[Job], int]:
    """The jobs to run and draw, in the paper's order, and the number of namelists that could not be read;
    notes for those skipped. SystemExit(2) when there is nothing to do."""
    jobs, unreadable = [], 0
    for p in sorted(args.input.glob("*.nml")):
        try:
            jobs.append(Job(p))
        except PlotError as exc:
            print(exc.line())
            unreadable += 1
    jobs.sort(key=Job.sort_key)
    if args.only:
        unknown = sorted(set(args.only) - {j.figure for j in jobs} - {j.stem for j in jobs} - set(COMBINED))
        if unknown:
            print(f"error: {args.input}: no namelist for {', '.join(unknown)}", file=sys.stderr)
            raise SystemExit(2)
        wanted = set(args.only).union(*(COMPANIONS.get(name, ()) for name in args.only))
        jobs = [j for j in jobs if j.figure in wanted or j.stem in wanted]
    if not jobs:
        why = f" ({unreadable} unreadable)" if unreadable else ""
        print(f"error: {args.input}: no namelist (*.nml) to run{why}", file=sys.stderr)
        raise SystemExit(2)
    for j in jobs:
        if j.output is None:
            print(f"note: {j.rel(j.nml)}: no '&output file': skipped")
        elif j.kind not in figures.SCENES and j.kind not in CHARTS:
            print(f"note: {j.rel(j.nml)}: scene '{j.kind}' is not one of the figures drawn here: skipped")
    jobs = [j for j in jobs if j.output is not None and (j.kind in figures.SCENES or j.kind in CHARTS)]
    if not jobs:
        print(f"error: {args.input}: no namelist of a scene drawn here ({', '.join(figures.SCENES)})",
              file=sys.stderr)
        raise SystemExit(2)
    if args.quick:
        jobs = [quick_copy(j, ROOT / "out" / "quick") for j in jobs]
    return jobs, unreadable


def program() -> list[str]:
    """The command that runs a namelist: in a checkout fpm's release build through .ci/with_commit (FPM), else
    the `supratrans` installed on PATH (README: `fpm install`; PlotError when there is none)."""
    if cli.checkout() is None:
        return [cli.installed("draw existing files with --no-run")]
    return [*FPM, "run", "--profile", "release", "--"]


def _build(logs: Path, tty: bool) -> bool:
    """Build the program (release profile), one line of progress; whether it built."""
    t0 = time.monotonic()
    label = "[build] fpm build --profile release ..."
    print(label, end="" if tty else "\n", flush=True)
    relayed = [label]       # its line is ended already: fpm's lines follow it directly
    status = run([*FPM, "build", "--profile", "release"], logs / "build.log", label, tty, relayed)
    if status != 0:
        print(f"\r{label} failed (status {status}); see {logs / 'build.log'}\033[K" if tty else
              f"build failed (status {status}); see {logs / 'build.log'}")
        for line in tail(logs / "build.log", 5):
            print("    " + line)
        return False
    if tty:
        print(f"\r{label} {time.monotonic() - t0:.0f} s\033[K")
    return True


def _run_all(jobs: list[Job], logs: Path, tty: bool) -> int:
    """Run every job with the release build, one line of progress each; returns the number of failures.
    KeyboardInterrupt when interrupted."""
    failures = 0
    for i, job in enumerate(jobs, 1):
        nml = job.rel(job.nml)
        label = f"[{i}/{len(jobs)}] {nml} ..."
        print(label, end="", flush=True)
        t = time.monotonic()
        log = logs / (job.stem + ".log")
        relayed: list[str] = []
        try:
            status = run([*program(), nml], log, label, tty, relayed)
        except KeyboardInterrupt:
            print(f"\r{label} interrupted\033[K" if tty else " interrupted")
            raise
        dt = time.monotonic() - t
        result = f"{dt:.0f} s" if status == 0 else f"FAILED (status {status}, {dt:.0f} s): see {job.rel(log)}"
        print(f"\r{label} {result}\033[K" if tty else (f"{label} {result}" if relayed else f" {result}"), flush=True)
        if status != 0:
            failures += 1
            for line in tail(log):
                print("    " + line)
    return failures


def _draw_all(jobs: list[Job], outdir: Path, args: argparse.Namespace) -> tuple[int, int]:
    """Draw every figure and chart of the jobs into `outdir`, with their numbers; returns (figures, problems)."""
    print(f"drawing into {outdir}")
    groups: dict[str, list[Job]] = {}
    for job in jobs:
        groups.setdefault(job.figure, []).append(job)
    failures = 0
    for name, group in groups.items():
        target = outdir / f"{name}.png"
        if group[0].kind in CHARTS:
            failures += draw_chart(group[0], outdir, args)
            continue
        try:
            expect = figures.FIGURES[name][1] if name in figures.FIGURES else None
            scenes = [open_scene(j.rel(j.output), expect=expect) for j in group]
            if name == "fig1" or all(s.scene == "timeseries" for s in scenes):
                fig = figures.draw_timeseries(scenes)
            elif name == "ramp090":
                fold = _companion(groups, "fold_sg_090", "continuation")
                fig = figures.draw_ramp(scenes, fold)
            elif len(scenes) == 1 and name in SCAN_OF and SCAN_OF[name] in groups:
                scan = groups[SCAN_OF[name]][0]
                fig = figures.draw_continuation(scenes[0], open_scene(scan.rel(scan.output), expect="bifurcation"),
                                                _shooting(groups, name, args))
            elif len(scenes) == 1 and scenes[0].scene == "bifurcation" and name in FOLD_OF:
                fig = figures.draw_bifurcation(scenes[0], _beside(groups, name, args, FOLD_OF))
            elif len(scenes) == 1:
                fig = figures.draw(scenes[0])
            else:
                raise PlotError(group[0].nml, "several namelists for one figure")
            style.save(fig, target, dpi=_dpi(args, name))
        except PlotError as exc:
            failures += 1
            print(f"  {name}: not drawn: {exc.line()}")
            continue
        size = target.stat().st_size / 1024
        marks = ", ".join(s.partial_note() for s in scenes if s.partial)
        print(f"  {name}: {_shown(target)} ({size:.0f} kB){'  [' + marks + ']' if marks else ''}")
        if name == "ramp090":
            for line in figures.summary_ramp(scenes, fold):
                print("    " + line.strip())
            continue
        for s in scenes:
            for line in figures.summary(s)[1 if s.scene != "timeseries" else 0:]:
                print("    " + line.strip())
    drawn = len(groups)
    for name, parts in COMBINED.items():
        if not all(p in groups for p in parts) or (args.only and name not in args.only):
            continue
        drawn += 1
        failures += _draw_combined(name, [groups[p][0] for p in parts], outdir, args)
    return drawn, failures


def _dpi(args: argparse.Namespace, name: str) -> int:
    """The resolution of the figure `name`: --dpi when given, else FIGURE_DPI's or style.DPI."""
    return args.dpi or FIGURE_DPI.get(name, style.DPI)


def _shooting(groups: dict, name: str, args: argparse.Namespace):
    """The Scene of the shooting fold line drawn beside the fold line by harmonic balance `name` (SHOOTING_OF)."""
    return _beside(groups, name, args, SHOOTING_OF)


def _beside(groups: dict, name: str, args: argparse.Namespace, table: dict):
    """The Scene of the fold line drawn beside the figure `name` (`table`: SHOOTING_OF, FOLD_OF): the file of its
    job, or, when it is not among the jobs, the file its namelist in the input folder writes (under out/quick/
    with --quick) if it is there. None when there is no such namelist or file, or the file cannot be read (a note
    says so: the figure is drawn without it)."""
    stem = table.get(name)
    if stem is None:
        return None
    try:
        if stem in groups:
            return _companion(groups, stem, "continuation")
        nml = args.input / f"{stem}.nml"
        if not nml.is_file():
            return None
        job = Job(nml)
        if job.output is None:
            return None
        path = ROOT / "out" / "quick" / job.output.name if args.quick else job.output
        return open_scene(job.rel(path), expect="continuation")
    except PlotError as exc:
        print(f"  {name}: drawn without the fold line of {stem}: {exc.line()}")
        return None


def _companion(groups: dict, stem: str, scene: str):
    """The Scene of the companion file `stem` when its namelist is among the jobs, else None."""
    if stem not in groups:
        return None
    job = groups[stem][0]
    return open_scene(job.rel(job.output), expect=scene)


def _draw_combined(name: str, parts: list[Job], outdir: Path, args: argparse.Namespace) -> int:
    """Draw the chart `name` of COMBINED from the files of its parts (fold line, scan, hysteresis); returns the
    number of problems (0 or 1)."""
    target = outdir / f"{name}.png"
    try:
        fold, scan, hyst = (open_scene(j.rel(j.output), expect=k)
                            for j, k in zip(parts, ("continuation", "bifurcation", "hysteresis")))
        style.save(figures.draw_thresholds(fold, scan, hyst), target, dpi=_dpi(args, name))
    except PlotError as exc:
        print(f"  {name}: not drawn: {exc.line()}")
        return 1
    print(f"  {name}: {_shown(target)} ({target.stat().st_size / 1024:.0f} kB)")
    for line in figures.summary_thresholds(fold, scan, hyst):
        print("    " + line.strip())
    return 0


def _shown(path: Path) -> Path:
    """A path as printed: relative to the repository when inside it."""
    return path.relative_to(ROOT) if path.is_relative_to(ROOT) else path


def main(argv: list[str] | None = None) -> int:
    """The command line of `make_figures.py`; returns the exit status (0 all done, 1 something failed, 2 nothing
    to do, 130 interrupted)."""
    args = _parser(argv).parse_args(argv)
    inside = cli.checkout() is not None
    try:
        # outside a checkout: the figures go where --outdir says, the namelists run with the installed program
        if not (args.outdir or args.quick):
            style.figure_dir()
        if not inside and not args.no_run:
            program()
    except PlotError as exc:
        print(exc.line(), file=sys.stderr)
        return 2
    args.input = args.input.resolve()
    if args.outdir:
        args.outdir = args.outdir.resolve()
    if args.logs:
        args.logs = args.logs.resolve()
    os.chdir(ROOT)  # the namelists' output paths are relative to the repository, where fpm runs them
    style.vector_copies(True)  # every PNG with its vector PDF beside it (the house style)
    signal.signal(signal.SIGTERM, _interrupt)  # `kill`: stop the running scene too, as Ctrl-C does
    try:
        jobs, failures = _jobs(args)
    except SystemExit as exc:
        return int(exc.code)
    outdir = args.outdir or (ROOT / "out" / "quick" / "figures" if args.quick else style.figure_dir())
    logs = args.logs or ROOT / "out" / ("quick/logs" if args.quick else "logs")
    if not args.no_run:
        if inside and shutil.which("fpm") is None:
            print("error: fpm: not found (install it with `bash .ci/install`, or draw existing files with --no-run)",
                  file=sys.stderr)
            return 2
        tty = sys.stdout.isatty()
        if inside and not _build(logs, tty):
            return 1
        try:
            failures += _run_all(jobs, logs, tty)
        except KeyboardInterrupt:
            print("interrupted: a sweep resumes from its journal when run again; "
                  "`make_figures.py --no-run` draws what there is (partial snapshots marked as such)")
            return 130
    drawn, problems = _draw_all(jobs, outdir, args)
    failures += problems
    print(f"{failures} problem(s); see above" if failures else f"all {drawn} figure(s) drawn")
    return 1 if failures else 0


def draw_chart(job: Job, outdir: Path, args: argparse.Namespace) -> int:
    """Draw a speed/accuracy chart (`charts`); return the number of problems (0 or 1)."""
    path = job.rel(job.output)
    try:
        if job.kind == "stability":
            s = chart_stability.read_stability(path)
            target = outdir / f"{job.figure}.png"
            style.save(chart_stability.draw_stability(s), target, dpi=_dpi(args, job.figure))
            print(f"  {job.figure}: {_shown(target)}")
            for line in chart_stability.summary(s):
                print("    " + line.strip())
            return 0
        argv = ["--h5", str(path), "--outdir", str(outdir), "--dpi", str(_dpi(args, job.figure)), "--quiet"]
        peer = output_path(path, "_peer.json")
        if args.no_run and Path(peer).is_file():
            argv += ["--peer", str(peer)]
        print(f"  {job.figure}: timing the SciPy peer and drawing work_precision*.png")
        return 0 if chart_work_precision.main(argv) == 0 else 1
    except PlotError as exc:
        print(f"  {job.figure}: not drawn: {exc.line()}")
        return 1
