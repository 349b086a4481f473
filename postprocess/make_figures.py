#!/usr/bin/env python3
"""Run every scene of input/ and draw every figure of the paper into one folder.

    python3 postprocess/make_figures.py                  # run input/*.nml, draw into postprocess/figures/
    python3 postprocess/make_figures.py --quick          # coarser grids, out/quick/, for a fast check
    python3 postprocess/make_figures.py --no-run         # only draw, from the files already in out/
    python3 postprocess/make_figures.py --only fig2 bif1 # some figures (names: the input files' stems)

Each namelist of a scene drawn here (timeseries, amplitude_sweep, map, bifurcation, and the speed/accuracy
scenes stability and work_precision; others are listed and skipped) is run with `fpm run --profile release -- input/X.nml`, in the paper's order (Fig. 1, 2, 3,
3-and-a-half, 4, 11, Bif1-3, then any other input), one line of progress each:

    [5/13] input/fig2.nml ... 45 s

(on a terminal the line shows the program's own progress while it runs; its whole output goes to
out/logs/X.log). A scene that fails is reported and the others go on. A sweep interrupted (Ctrl-C) resumes
from its journal when run again (Ctrl-C or `kill` stops the running scene too); meanwhile `--no-run` draws
its partial snapshot, marked as such.
Then every figure is drawn: Fig. 1 from the four fig1_* runs, one figure per other file, named after its
input file (fig2.png, ..., bif3.png), with the numbers each figure shows printed below it. A `stability` file
is drawn by chart_stability.py; a `work_precision` file by work_precision.py, which first times the SciPy peer
in the same process (with --no-run it reuses the peer points saved next to the file, if there are any).
Exit status 0 when every scene ran and every figure was drawn, 1 otherwise.
"""
import argparse
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import supratrans_plot as sp  # noqa: E402

ROOT = HERE.parent
#: Order of the figures (the paper's), by input file stem or its prefix.
ORDER = ["fig1", "fig2", "fig3", "fig3half", "fig4", "fig11", "bif1", "bif2", "bif3"]
#: Scenes drawn by the charts of the speed/accuracy study (their own scripts), besides sp.SCENES.
CHARTS = ("stability", "work_precision")
#: `--quick`: factor applied to the steps of the scene grids (amplitude, frequency, threshold resolution).
QUICK = {"amplitude_step": 5.0, "omega_step": 2.0, "resolution": 5.0, "coarse_step": 2.0}


# ------------------------------------------------------------------------------------------------ namelists


def _strip_comments(text):
    """Namelist text without its `!` comments (outside quotes)."""
    out = []
    for line in text.splitlines():
        quote = None
        for i, ch in enumerate(line):
            if quote:
                if ch == quote:
                    quote = None
            elif ch in "'\"":
                quote = ch
            elif ch == "!":
                line = line[:i]
                break
        out.append(line)
    return "\n".join(out)


def _groups(text):
    """{group name: body text} of a namelist file: `&name ... /`, the `/` outside quotes, comments removed."""
    text = _strip_comments(text)
    groups, i, n = {}, 0, len(text)
    while i < n:
        if text[i] != "&":
            i += 1
            continue
        m = re.match(r"&(\w+)", text[i:])
        if not m:
            i += 1
            continue
        j, quote = i + m.end(), None
        while j < n:
            ch = text[j]
            if quote:
                quote = None if ch == quote else quote
            elif ch in "'\"":
                quote = ch
            elif ch == "/":
                break
            j += 1
        groups[m.group(1).lower()] = text[i + m.end():j]
        i = j + 1
    return groups


def _key(body, key):
    """Value of `key` in a group body as text (quotes removed), None when absent."""
    m = re.search(rf"(?<![\w%])\s*{key}\s*=\s*('([^']*)'|\"([^\"]*)\"|[^,\s/]+)", body or "", flags=re.I)
    if not m:
        return None
    return m.group(2) if m.group(2) is not None else m.group(3) if m.group(3) is not None else m.group(1)


class Job:
    """One namelist of input/: its scene, its output file, the figure it belongs to."""

    def __init__(self, nml):
        self.nml = Path(nml)
        text = self.nml.read_text()
        g = _groups(text)
        self.kind = (_key(g.get("scene"), "kind") or "timeseries").lower()
        out = _key(g.get("output"), "file")
        self.output = (ROOT / out) if out else None
        self.stem = self.nml.stem
        self.figure = "fig1" if self.stem.startswith("fig1_") else self.stem
        self.text = text

    def sort_key(self):
        return (ORDER.index(self.figure) if self.figure in ORDER else len(ORDER), self.figure, self.stem)

    def rel(self, p):
        try:
            return str(Path(p).relative_to(ROOT))
        except ValueError:
            return str(p)


def quick_copy(job, folder):
    """A copy of the job's namelist with coarser scene grids (QUICK) and its output under `folder`."""
    text = _strip_comments(job.text)

    def scale(m):
        key, value = m.group(1), m.group(2)
        factor = QUICK[key.lower()]
        return f"{key} = {float(value.replace('d', 'e').replace('D', 'e')) * factor:.6g}"

    pattern = r"(?i)\b(" + "|".join(QUICK) + r")\s*=\s*([-+0-9.eEdD]+)"
    scene = re.search(r"&scene.*?(?<![\w.])/", text, flags=re.S | re.I)
    if scene:
        text = text[: scene.start()] + re.sub(pattern, scale, scene.group(0)) + text[scene.end():]
    out = folder / (job.output.name if job.output else job.stem + ".h5")
    text = re.sub(r"(?i)(\bfile\s*=\s*)('[^']*'|\"[^\"]*\")", lambda m: f"{m.group(1)}'{out}'", text)
    if not re.search(r"(?i)\boverwrite\s*=", text):
        text = re.sub(r"(?i)(&output)", r"\1 overwrite = .true.,", text)
    copy = folder / "input" / job.nml.name
    copy.parent.mkdir(parents=True, exist_ok=True)
    copy.write_text(text)
    q = Job(copy)
    q.stem, q.figure = job.stem, job.figure
    return q


# ------------------------------------------------------------------------------------------------ running


def run(cmd, log, label, tty):
    """Run `cmd` in the repository, its output into `log`; on a terminal, show its last line after `label`."""
    log.parent.mkdir(parents=True, exist_ok=True)
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
        except KeyboardInterrupt:
            proc.terminate()
            proc.wait()
            raise
        return proc.wait()


def _interrupt(signum, frame):
    raise KeyboardInterrupt


def tail(path, n=3):
    try:
        lines = [x for x in Path(path).read_text().splitlines() if x.strip()]
    except OSError:
        return []
    return lines[-n:]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n\n".join(__doc__.split("\n\n")[1:]))
    ap.add_argument("--outdir", type=Path, help="folder of the images (default postprocess/figures/, "
                                                "with --quick out/quick/figures/)")
    ap.add_argument("--quick", action="store_true", help="coarser scene grids (steps x 2..5), outputs in out/quick/")
    ap.add_argument("--no-run", action="store_true", help="do not run the program: draw from the files there are")
    ap.add_argument("--only", nargs="+", metavar="NAME", help="only these figures (fig1, fig2, ..., bif3)")
    ap.add_argument("--input", type=Path, default=ROOT / "input", help="folder of the namelists (default input/)")
    ap.add_argument("--logs", type=Path, help="folder of the program's output, one log per namelist "
                                              "(default out/logs/, with --quick out/quick/logs/)")
    ap.add_argument("--dpi", type=int, default=sp.DPI, help=f"resolution of the images (default {sp.DPI})")
    args = ap.parse_args(argv)
    args.input = args.input.resolve()
    if args.outdir:
        args.outdir = args.outdir.resolve()
    if args.logs:
        args.logs = args.logs.resolve()
    os.chdir(ROOT)  # the namelists' output paths are relative to the repository, where fpm runs them
    signal.signal(signal.SIGTERM, _interrupt)  # `kill`: stop the running scene too, as Ctrl-C does

    jobs = sorted((Job(p) for p in sorted(args.input.glob("*.nml"))), key=Job.sort_key)
    if args.only:
        unknown = sorted(set(args.only) - {j.figure for j in jobs} - {j.stem for j in jobs})
        if unknown:
            print(f"error: {args.input}: no namelist for {', '.join(unknown)}", file=sys.stderr)
            return 2
        jobs = [j for j in jobs if j.figure in args.only or j.stem in args.only]
    if not jobs:
        print(f"error: {args.input}: no namelist (*.nml) to run", file=sys.stderr)
        return 2
    for j in jobs:
        if j.output is None:
            print(f"note: {j.rel(j.nml)}: no '&output file': skipped")
        elif j.kind not in sp.SCENES and j.kind not in CHARTS:
            print(f"note: {j.rel(j.nml)}: scene '{j.kind}' is not one of the figures drawn here: skipped")
    jobs = [j for j in jobs if j.output is not None and (j.kind in sp.SCENES or j.kind in CHARTS)]
    if not jobs:
        print(f"error: {args.input}: no namelist of a scene drawn here ({', '.join(sp.SCENES)})", file=sys.stderr)
        return 2
    if args.quick:
        folder = ROOT / "out" / "quick"
        jobs = [quick_copy(j, folder) for j in jobs]
    outdir = args.outdir or (ROOT / "out" / "quick" / "figures" if args.quick else HERE / "figures")
    logs = args.logs or ROOT / "out" / ("quick/logs" if args.quick else "logs")
    tty = sys.stdout.isatty()
    failures = 0

    if not args.no_run and shutil.which("fpm") is None:
        print("error: fpm: not found (install it with `bash .ci/install`, or draw existing files with --no-run)",
              file=sys.stderr)
        return 2
    if not args.no_run:
        t0 = time.monotonic()
        label = "[build] fpm build --profile release ..."
        print(label, end="" if tty else "\n", flush=True)
        status = run(["fpm", "build", "--profile", "release"], logs / "build.log", label, tty)
        if status != 0:
            print(f"\r{label} failed (status {status}); see {logs / 'build.log'}\033[K" if tty else
                  f"build failed (status {status}); see {logs / 'build.log'}")
            for line in tail(logs / "build.log", 5):
                print("    " + line)
            return 1
        if tty:
            print(f"\r{label} {time.monotonic() - t0:.0f} s\033[K")
        for i, job in enumerate(jobs, 1):
            nml = job.rel(job.nml)
            label = f"[{i}/{len(jobs)}] {nml} ..."
            print(label, end="" if tty else "", flush=True)
            t = time.monotonic()
            log = logs / (job.stem + ".log")
            try:
                status = run(["fpm", "run", "--profile", "release", "--", nml], log, label, tty)
            except KeyboardInterrupt:
                print(f"\r{label} interrupted\033[K" if tty else " interrupted")
                print("interrupted: a sweep resumes from its journal when run again; "
                      "`make_figures.py --no-run` draws what there is (partial snapshots marked as such)")
                return 130
            dt = time.monotonic() - t
            result = f"{dt:.0f} s" if status == 0 else f"FAILED (status {status}, {dt:.0f} s): see {job.rel(log)}"
            print(f"\r{label} {result}\033[K" if tty else f" {result}", flush=True)
            if status != 0:
                failures += 1
                for line in tail(log):
                    print("    " + line)

    # ---------------------------------------------------------------------------------------------- draw
    print(f"drawing into {outdir}")
    figures = {}
    for job in jobs:
        figures.setdefault(job.figure, []).append(job)
    for name, group in figures.items():
        target = outdir / f"{name}.png"
        if group[0].kind in CHARTS:
            failures += draw_chart(group[0], outdir, args)
            continue
        try:
            expect = sp.FIGURES[name][1] if name in sp.FIGURES else None
            scenes = [sp.open_scene(j.rel(j.output), expect=expect) for j in group]
            if name == "fig1" or all(s.scene == "timeseries" for s in scenes):
                fig = sp.draw_timeseries(scenes)
            elif len(scenes) == 1:
                fig = sp.draw(scenes[0])
            else:
                raise sp.PlotError(group[0].nml, "several namelists for one figure")
            sp.save(fig, target, dpi=args.dpi)
        except sp.PlotError as exc:
            failures += 1
            print(f"  {name}: not drawn: {exc.line()}")
            continue
        size = target.stat().st_size / 1024
        marks = ", ".join(s.partial_note() for s in scenes if s.partial)
        print(f"  {name}: {target.relative_to(ROOT) if target.is_relative_to(ROOT) else target} "
              f"({size:.0f} kB){'  [' + marks + ']' if marks else ''}")
        for s in scenes:
            for line in sp.summary(s)[1 if s.scene != "timeseries" else 0:]:
                print("    " + line.strip())
    print(f"{failures} problem(s); see above" if failures else f"all {len(figures)} figure(s) drawn")
    return 1 if failures else 0


def draw_chart(job, outdir, args):
    """Draw a speed/accuracy chart with its own script; return the number of problems (0 or 1)."""
    path = job.rel(job.output)
    try:
        if job.kind == "stability":
            import chart_stability as cs
            s = cs.read_stability(path)
            target = outdir / f"{job.figure}.png"
            sp.save(cs.draw_stability(s), target, dpi=args.dpi)
            print(f"  {job.figure}: {target.relative_to(ROOT) if target.is_relative_to(ROOT) else target}")
            for line in cs.summary(s):
                print("    " + line.strip())
            return 0
        import work_precision as wpc
        argv = ["--h5", str(path), "--outdir", str(outdir), "--dpi", str(args.dpi), "--quiet"]
        peer = sp.output_path(path, "_peer.json")
        if args.no_run and Path(peer).is_file():
            argv += ["--peer", str(peer)]
        print(f"  {job.figure}: timing the SciPy peer and drawing work_precision*.png")
        return 0 if wpc.main(argv) == 0 else 1
    except sp.PlotError as exc:
        print(f"  {job.figure}: not drawn: {exc.line()}")
        return 1


if __name__ == "__main__":
    sys.exit(main())
