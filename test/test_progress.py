"""Progress on every long run (issue 42, part 2): a timeseries prints lines of progress on stderr (t of T, then the
fraction done, the elapsed and the remaining time) and so does the task engine (tasks done of total and what they
are called, then the same), by one rule (`supratrans_progress`, whose rule test/test_progress_clock.pf holds as a
pure function of the times) at a rate set by SUPRATRANS_PROGRESS_EVERY (default 4 s, growing with the time elapsed),
none when quiet; `--check` prints the number of tasks and runs and an estimate of the cost from the model's sizes;
`merge` says that it merged records, not that it ran them.

The interval is made tiny here (1e-6 s), so that the assertions count lines, not seconds: a line then comes whenever
a tenth of the time elapsed has passed since the last (polled every 256 steps, or after every task), so a run of
some forty polls prints several on any machine, fast or loaded, and every one but possibly the first has a
remaining time.
"""
from __future__ import annotations

import os
import re
import subprocess
import time
from pathlib import Path

#: A timeseries of some 2e6 oscillator-steps (about a second in the debug build).
LONG = "&chain n = 400, n0 = 380 /\n&numerics t_final = 500.0 /\n&output file = 'ts.h5'{quiet} /\n"
#: A duration as the lines give it: two digits in its unit ("0.3 s", "42 s", "2.5 min").
DURATION = r"([0-9]\.[0-9]|[1-9][0-9]*) (s|min|h|days)"
#: A progress line: "  t = 179.2 of 500.0 (35%), 0.3 s elapsed, about 0.6 s left".
LINE = re.compile(rf"^  t = [0-9.]+ of 500\.0 \([0-9]+%\), {DURATION} elapsed(, about {DURATION} left)?$")
#: A progress line of the task engine: "  12/40 runs (30%), 5.2 s elapsed, about 12 s left".
TASK_LINE = re.compile(rf"^  ([0-9]+)/([0-9]+) runs \(([0-9]+)%\), {DURATION} elapsed(, about {DURATION} left)?$")
#: An amplitude sweep of 21 short runs.
SWEEP = "&chain n = 40, n0 = 30 /\n&numerics t_final = 20.0 /\n&scene kind = 'amplitude_sweep', " \
        "amplitude_min = 1.0, amplitude_max = 2.0, amplitude_step = 0.05 /\n&output file = 's.h5'{quiet} /\n"


def run(exe: str, where: Path, *args: str, env: dict | None = None) -> subprocess.CompletedProcess:
    """The program run in `where` with `args` (SUPRATRANS_PROGRESS_EVERY from `env`)."""
    full = dict(os.environ)
    full.pop("SUPRATRANS_PROGRESS_EVERY", None)
    full.update(env or {})
    return subprocess.run([exe, *args], cwd=where, capture_output=True, text=True, timeout=600, env=full)


def test_a_long_timeseries_prints_progress_with_the_time_left(exe, tmp_path):
    (tmp_path / "ts.nml").write_text(LONG.format(quiet=""))
    proc = run(exe, tmp_path, "ts.nml", env={"SUPRATRANS_PROGRESS_EVERY": "1e-6"})
    assert proc.returncode == 0, proc.stderr
    lines = [line for line in proc.stderr.splitlines() if line.startswith("  t = ")]
    assert len(lines) >= 2, proc.stderr
    assert all(LINE.match(line) for line in lines), lines
    assert sum("s left" in line for line in lines) >= 2, lines
    times = [float(line.split()[2]) for line in lines]
    assert times == sorted(times) and times[-1] < 500.0


def test_quiet_and_short_runs_print_no_progress(exe, tmp_path):
    (tmp_path / "ts.nml").write_text(LONG.format(quiet=", quiet = .true."))
    proc = run(exe, tmp_path, "ts.nml", env={"SUPRATRANS_PROGRESS_EVERY": "1e-6"})
    assert proc.returncode == 0 and proc.stderr == "", proc.stderr
    # the default interval (4 s): no more lines than the run's wall time allows (none for a run of a second on an
    # idle machine; counted against the measured time, so that a slow or loaded machine cannot fail it)
    (tmp_path / "ts.nml").write_text(LONG.format(quiet=", overwrite = .true."))
    start = time.monotonic()
    proc = run(exe, tmp_path, "ts.nml")
    wall = time.monotonic() - start
    assert proc.returncode == 0, proc.stderr
    lines = [line for line in proc.stderr.splitlines() if line.startswith("  t = ")]
    assert len(lines) <= wall/4.0, (wall, proc.stderr)


def test_the_task_engine_prints_tasks_done_by_the_same_rule(exe, tmp_path):
    """The engine's lines: tasks done of total and what they are called, then the shared part; increasing, the
    last one at 100% with no time left; none when quiet. With the default interval, no more lines than the wall
    time allows besides the last."""
    (tmp_path / "s.nml").write_text(SWEEP.format(quiet=""))
    proc = run(exe, tmp_path, "s.nml", env={"SUPRATRANS_PROGRESS_EVERY": "1e-6"})
    assert proc.returncode == 0, proc.stderr
    lines = [line for line in proc.stderr.splitlines() if TASK_LINE.match(line)]
    assert lines and lines[-1].startswith("  21/21 runs (100%), ") and "left" not in lines[-1], proc.stderr
    done = [int(TASK_LINE.match(line).group(1)) for line in lines]
    assert done == sorted(set(done)), lines
    # the fraction is of the work, the tasks weighed by their costs: growing, 100% only at the end
    percent = [int(TASK_LINE.match(line).group(3)) for line in lines]
    assert percent == sorted(percent) and percent[-1] == 100 and max(percent[:-1], default=0) < 100, lines
    assert all("s left" in line for line in lines[:-1]), lines
    assert not [line for line in proc.stderr.splitlines() if "/21 runs" in line and not TASK_LINE.match(line)]
    (tmp_path / "s.nml").write_text(SWEEP.format(quiet=", overwrite = .true., quiet = .true."))
    proc = run(exe, tmp_path, "s.nml", env={"SUPRATRANS_PROGRESS_EVERY": "1e-6"})
    assert proc.returncode == 0 and proc.stderr == "", proc.stderr
    (tmp_path / "s.nml").write_text(SWEEP.format(quiet=", overwrite = .true."))
    start = time.monotonic()
    proc = run(exe, tmp_path, "s.nml")
    wall = time.monotonic() - start
    assert proc.returncode == 0, proc.stderr
    lines = [line for line in proc.stderr.splitlines() if TASK_LINE.match(line)]
    assert 1 <= len(lines) <= 1 + wall / 4.0, (wall, proc.stderr)
    assert lines[-1].startswith("  21/21 runs (100%), "), lines


def report(text: str) -> dict:
    """The `key value` lines of `--check`."""
    return dict(line.split(" ", 1) for line in text.splitlines())


def test_check_counts_the_runs_and_estimates_their_cost(exe, tmp_path):
    chain = "&chain n = 40, n0 = 30 /\n&numerics t_final = 10.0 /\n"
    cases = {
        # scene: (&scene group, tasks, task kind, runs)
        "timeseries": ("", 1, "run", 1),
        "amplitude_sweep": ("&scene kind = 'amplitude_sweep', amplitude_min = 1.0, amplitude_max = 1.5, "
                            "amplitude_step = 0.1, vary = 'gamma', values = 0.0, 0.1 /\n", 12, "runs", 12),
        "map": ("&scene kind = 'map', amplitude_min = 1.0, amplitude_max = 1.5, amplitude_step = 0.1, "
                "omega_min = 0.5, omega_max = 0.9, omega_step = 0.1 /\n", 30, "runs", 30),
        "bifurcation": ("&scene kind = 'bifurcation', omega_min = 0.5, omega_max = 0.9, omega_step = 0.1, "
                        "amplitude_min = 1.0, amplitude_max = 3.0, coarse_step = 0.5, resolution = 0.1 /\n",
                        5, "searches", 5 * 9),
        "hysteresis": ("&scene kind = 'hysteresis', omega_min = 0.9, omega_max = 0.9, amplitude_min = 1.0, "
                       "amplitude_max = 1.04, stair_height = 0.02, stair_times = 20.0, 40.0, stair_ramp = 2.0 /\n",
                       2, "stair runs", 2),
    }
    for scene, (group, tasks, kind, runs) in cases.items():
        (tmp_path / "s.nml").write_text(chain + group + "&output file = 's.h5' /\n")
        proc = run(exe, tmp_path, "--check", "s.nml")
        assert proc.returncode == 0, proc.stderr
        r = report(proc.stdout)
        assert (int(r["tasks"]), r["task_kind"], int(r["runs"])) == (tasks, kind, runs), (scene, r)
        assert float(r["work_newton_site_steps"]) > 0 and float(r["estimate_seconds"]) > 0, r
        assert r["estimate"].startswith(f"{tasks} {kind}") and "about" in r["estimate"], r
        if scene != "hysteresis":
            assert int(r["steps_per_run"]) == 200, r        # t_final/dt
            # work = runs x steps x N (Newton: 1 per oscillator-step)
            assert abs(float(r["work_newton_site_steps"]) - runs * 200 * 40) < 1e-3 * runs * 200 * 40, r
    assert not list(tmp_path.glob("*.h5"))      # --check writes nothing


#: Every namelist of input/.
INPUTS = sorted((Path(__file__).resolve().parents[1] / "input").glob("*.nml"))
#: The line for a person: "estimate 95 fold continuations (each fold: ...): about 2.4 min on 2 thread(s) (...)".
ESTIMATE = re.compile(r"^[0-9]+ [a-z ,()]+.*: about [0-9.]+ (s|min|h|days)( or less)? on [0-9]+ thread\(s\) ")


def test_check_counts_and_estimates_every_input(exe, tmp_path):
    """`--check` of every namelist of input/ prints its tasks and an estimate of their cost (continuation by
    shooting and by harmonic balance, stability and work_precision included), and writes nothing."""
    assert len(INPUTS) > 20
    for nml in INPUTS:
        proc = run(exe, tmp_path, "--check", str(nml))
        assert proc.returncode == 0, (nml.name, proc.stderr)
        r = report(proc.stdout)
        assert int(r["tasks"]) >= 1 and r["task_kind"], (nml.name, r)
        assert float(r["work_newton_site_steps"]) > 0 and float(r["estimate_seconds"]) > 0, (nml.name, r)
        assert 1 <= int(r["threads"]) <= int(r["tasks"]), (nml.name, r)
        assert ESTIMATE.match(r["estimate"]), (nml.name, r["estimate"])
        assert r["estimate"].startswith(r["tasks"] + " " + r["task_kind"]), (nml.name, r)
    assert not list(tmp_path.iterdir())      # --check writes nothing


def test_check_estimates_scenes_of_uneven_tasks(exe, tmp_path):
    """The scenes whose tasks are not runs of one length count their own work: work_precision its timed runs
    exactly (repeats x T/dt x N x the method's cost per step, dt_smallest honoured, the rk8 references 3 T /
    reference_dt), one at a time; stability its grid runs and bisections; a continuation its folds, more with
    fold_convergence and less for the fold alone."""
    chain = "&chain n = 40, n0 = 30 /\n&numerics t_final = 10.0 /\n&output file = 's.h5' /\n"

    def check(group: str) -> dict:
        (tmp_path / "s.nml").write_text(chain + group)
        proc = run(exe, tmp_path, "--check", "s.nml")
        assert proc.returncode == 0, proc.stderr
        return report(proc.stdout)

    r = check("&scene kind = 'work_precision', methods = 'newton', 'rk4', dts = 0.5, 0.25, 0.1, "
              "dt_smallest = 0.1, 0.25, repeats = 3, reference_dt = 0.05, amplitudes = 1.0, 1.5 /\n")
    # newton: dt 0.5, 0.25, 0.1 -> 20 + 40 + 100 steps; rk4 (0.6 a step): 0.5, 0.25 -> 60 steps
    timed = 3 * 40 * ((20 + 40 + 100) + 0.6 * (20 + 40))
    reference = 3 * 40 * 1.6 * 10.0 / 0.05
    assert (int(r["tasks"]), r["task_kind"], int(r["runs"]), int(r["threads"])) == (12, "timed tasks", 30, 1), r
    expected = 2 * (timed + reference)      # two amplitudes; the line prints 4 digits
    assert abs(float(r["work_newton_site_steps"]) - expected) < 1e-3 * expected, r
    r = check("&scene kind = 'stability', methods = 'newton', 'rk4', c_values = 1.0, 4.0, dts = 0.1, 0.2, 0.4, "
              "resolution = 0.01 /\n")
    assert (int(r["tasks"]), r["task_kind"]) == (2 * 2 * (1 + 3), "bisections and grid runs"), r
    grid = 2 * 40 * (100 + 50 + 25) * (1 + 0.6)     # every grid run to T, at each c
    assert int(r["runs"]) > 2 * 2 * 3 and float(r["work_newton_site_steps"]) > grid, r
    assert r["estimate"].startswith("16 bisections and grid runs (12 grid runs to T = "), r
    fold = "&scene kind = 'continuation', omega_min = 0.7, omega_max = 0.9, omega_step = 0.1{} /\n"
    base, alone, converged = (check(fold.format(extra)) for extra in
                              (", fold_convergence = .false.", ", fold_convergence = .false., floquet_every = 0",
                               ""))     # fold_convergence is on by default
    assert (int(base["tasks"]), base["task_kind"]) == (3, "fold continuations"), base
    work = {name: float(r["work_newton_site_steps"]) for name, r in
            (("base", base), ("alone", alone), ("converged", converged))}
    assert work["alone"] < work["base"] < work["converged"], work
    assert "spectra 2N x 2N" in base["estimate"] and "1 spectrum" in alone["estimate"], alone
    assert "again at dt/2 and at 2N" in converged["estimate"] and "again" not in base["estimate"], base
    hb = check(fold.format(", solver = 'harmonic_balance'"))
    more = check(fold.format(", solver = 'harmonic_balance', absorber_family = 2"))
    assert "(2K)^3" in hb["estimate"], hb
    assert float(more["work_newton_site_steps"]) > float(hb["work_newton_site_steps"]) > 0, (hb, more)


def test_merge_says_it_merged(exe, tmp_path):
    text = "&chain n = 40, n0 = 30 /\n&numerics t_final = 10.0 /\n&scene kind = 'amplitude_sweep', " \
           "amplitude_min = 1.0, amplitude_max = 1.5, amplitude_step = 0.1 /\n&output file = 's.h5' /\n"
    (tmp_path / "s.nml").write_text(text)
    for i in (1, 2):
        assert run(exe, tmp_path, "s.nml", "--slice", f"{i}/2").returncode == 0
    proc = run(exe, tmp_path, "merge", "s.part-1-of-2.h5", "s.part-2-of-2.h5")
    assert proc.returncode == 0, proc.stderr
    assert "  merged 6 runs from the parts' records (none run here)" in proc.stderr.splitlines(), proc.stderr
    assert "already done" not in proc.stderr and "nothing was run here" in proc.stderr, proc.stderr
