"""Mid-run checkpoints (issue 23): a long timeseries, a threshold search, a hysteresis stair run and the runs of an
amplitude sweep and of a map, killed mid-run (SIGTERM: the program checkpoints at once and exits 5; SIGKILL after a
periodic checkpoint), resume from their checkpoint and end with every result dataset bit for bit that of an
uninterrupted run, for every method. A damaged or foreign checkpoint is ignored with one line, never used; with
checkpoint_every = 0 nothing is written.

No signal races the run's end or a clock: each is sent after an event the test sees (the program's first line, from
which its stop signals are caught; a periodic checkpoint written, every CHECKPOINT_EVERY s of wall time), to a run
that has most of its work still ahead of it then, and the test requires the stop (exit 5) it asked for."""
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
from compare_results import compare  # noqa: E402

METHODS = ["newton", "linearized", "rk4", "rk8"]

TIMESERIES = """! {tag}
&chain n = 200, n0 = 150 /
&drive amplitude = 1.79 /
&record probes = 1, 60, 100, probe_every = 3, ledger_every = 7 /
&numerics method = '{method}', dt = 0.05, t_final = {t_final} /
&output file = 'out/{name}.h5', overwrite = .true., checkpoint_every = {every} /
"""

SEARCH = """! {tag}
&chain n = 60, n0 = 45 /
&numerics method = '{method}', dt = 0.05, t_final = 200.0 /
&scene kind = 'bifurcation', amplitude_min = 0.5, amplitude_max = 6.0, omega_min = 0.7, omega_max = 0.9,
  omega_step = 0.1, coarse_step = 0.5, resolution = 0.05, screen_method = 'none' /
&output file = 'out/{name}.h5', overwrite = .true., checkpoint_every = {every} /
"""

# one long stair run per task (two stair lengths): each task checkpoints inside its run
HYSTERESIS = """! {tag}
&chain n = 60, n0 = 45 /
&drive ramp_time = 20.0 /
&numerics method = '{method}', dt = 0.05 /
&scene kind = 'hysteresis', omega_min = 0.9, omega_max = 0.9, omega_step = 0.05, amplitude_min = 1.0,
  amplitude_max = 2.0, stair_height = 0.1, stair_times = 60.0, 90.0, stair_ramp = 10.0 /
&output file = 'out/{name}.h5', overwrite = .true., checkpoint_every = {every} /
"""

SWEEP = """! {tag}
&chain n = 60, n0 = 45 /
&drive omega = 0.9, ramp_time = 20.0 /
&numerics method = '{method}', dt = 0.05, t_final = 1500.0 /
&scene kind = 'amplitude_sweep', amplitude_min = 1.0, amplitude_max = 2.0, amplitude_step = 0.5 /
&output file = 'out/{name}.h5', overwrite = .true., checkpoint_every = {every} /
"""

MAP = """! {tag}
&chain n = 60, n0 = 45 /
&drive ramp_time = 20.0 /
&numerics method = '{method}', dt = 0.05, t_final = 1000.0 /
&scene kind = 'map', omega_min = 0.8, omega_max = 0.9, omega_step = 0.1, amplitude_min = 1.5, amplitude_max = 2.0,
  amplitude_step = 0.5 /
&output file = 'out/{name}.h5', overwrite = .true., checkpoint_every = {every} /
"""

TEMPLATES = {"timeseries": TIMESERIES, "search": SEARCH, "hysteresis": HYSTERESIS, "sweep": SWEEP, "map": MAP}


#: The periodic checkpoints (s of wall time) of the runs that are stopped: the first is written early in every run
#: (each takes 0.3-1.5 s of CPU in the debug build), so that a signal sent when it appears finds most of the run ahead.
CHECKPOINT_EVERY = 0.05

#: Length of the timeseries that are stopped (about 1 s of CPU in the debug build; the other scenes have their own
#: lengths in their templates).
KILLED_T = 1200.0


def write(tmp_path, scene, method, name, every=CHECKPOINT_EVERY, tag="", t_final=KILLED_T):
    (tmp_path / "out").mkdir(exist_ok=True)
    path = tmp_path / f"{name}.nml"
    path.write_text(TEMPLATES[scene].format(method=method, name=name, every=every, tag=tag, t_final=t_final))
    return path


def checkpoints(tmp_path, name):
    return sorted((tmp_path / "out").glob(f"{name}.h5.checkpoint*"))


def run(exe, nml, cwd, threads=2):
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    return subprocess.run([exe, str(nml)], cwd=cwd, capture_output=True, text=True, timeout=600, env=env)


def start(exe, nml, cwd, threads=2):
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    return subprocess.Popen([exe, str(nml)], cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=env)


def started(proc):
    """Wait for the program's first line (its stop signals are caught from then on); the line."""
    return proc.stderr.readline()


def written(tmp_path, name):
    """Each checkpoint file of the run `name` with the time it was last written."""
    times = {}
    for path in checkpoints(tmp_path, name):
        try:
            times[path] = path.stat().st_mtime_ns
        except FileNotFoundError:       # replaced while listed
            pass
    return times


def wait_for_checkpoint(proc, tmp_path, name, timeout=120):
    """Wait (polling every 0.01 s, at most `timeout` s) until the running `proc` writes a checkpoint of `name` (a
    file that was not there or has been written again since the call); fails when the run ends first."""
    before = written(tmp_path, name)
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        assert proc.poll() is None, f"the run ended before writing a checkpoint: {proc.stderr.read()}"
        now = written(tmp_path, name)
        if any(before.get(path) != t for path, t in now.items()):
            return
        time.sleep(0.01)
    raise AssertionError(f"no checkpoint of {name} in {timeout} s")


def same_results(reference, result):
    diffs, compared, added = compare(reference, result)
    assert compared > 10 and not diffs and not added, (diffs, added)


@pytest.fixture(scope="module")
def references(exe, tmp_path_factory):
    """Uninterrupted runs, checkpoints off, one per (scene, method), made when first asked for."""
    made = {}
    root = tmp_path_factory.mktemp("reference")

    def get(scene, method, t_final=KILLED_T):
        if (scene, method, t_final) not in made:
            name = f"{scene}_{method}_{t_final:g}"
            nml = write(root, scene, method, name, every=0, t_final=t_final)
            proc = run(exe, nml, root)
            assert proc.returncode == 0, proc.stderr
            assert not checkpoints(root, name)
            made[scene, method, t_final] = root / "out" / f"{name}.h5"
        return made[scene, method, t_final]

    return get


def kill_and_resume(exe, tmp_path, scene, method):
    """Run with periodic checkpoints; stop it with SIGTERM once it has written its first checkpoint (it checkpoints
    again and exits 5), start it again and SIGKILL it once the resumed run has written a checkpoint of its own, then
    let it finish; the output, which must come from a run that resumed."""
    name = f"{scene}_{method}"
    nml = write(tmp_path, scene, method, name)
    for sig in (signal.SIGTERM, signal.SIGKILL):
        proc = start(exe, nml, tmp_path)
        first = started(proc)
        wait_for_checkpoint(proc, tmp_path, name)
        proc.send_signal(sig)
        _, err = proc.communicate(timeout=600)
        err = first + err
        if sig == signal.SIGTERM:
            # stopped there: the checkpoint written at the signal, and the one line says so
            assert proc.returncode == 5, err
            assert checkpoints(tmp_path, name), err
            assert "checkpoint written" in err or "stopped by signal 15" in err, err
        else:
            assert proc.returncode == -signal.SIGKILL, err
    assert checkpoints(tmp_path, name)
    proc = run(exe, nml, tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert "resumed" in proc.stderr, proc.stderr    # from the checkpoint the killed run left (not from t = 0)
    assert not checkpoints(tmp_path, name), "a finished run leaves no checkpoint"
    return tmp_path / "out" / f"{name}.h5", proc.stderr


def kills(scenes, methods, fast):
    """The (scene, method) cases of a kill test, each `slow` but the one of the fast tier."""
    return [pytest.param(scene, method, id=f"{scene}-{method}",
                         marks=() if (scene, method) == fast else pytest.mark.slow)
            for scene in scenes for method in methods]


@pytest.mark.parametrize("scene,method", kills(["timeseries", "search"], METHODS, fast=("timeseries", "newton")))
def test_killed_run_resumes_bit_identical(exe, tmp_path, references, scene, method):
    result, _ = kill_and_resume(exe, tmp_path, scene, method)
    same_results(references(scene, method), result)


@pytest.mark.parametrize("scene,method", kills(["hysteresis", "sweep", "map"], ["newton", "rk4"], fast=None))
def test_killed_scene_run_resumes_bit_identical(exe, tmp_path, references, scene, method):
    """The one run of a task of a hysteresis, sweep or map scene checkpoints inside itself: killed (SIGTERM, then
    SIGKILL after a checkpoint) it resumes from its step, and the result datasets are bit for bit those of an
    uninterrupted run."""
    result, _ = kill_and_resume(exe, tmp_path, scene, method)
    same_results(references(scene, method), result)


def test_stair_run_stopped_mid_run_resumes(exe, tmp_path, references):
    """A SIGTERM once a stair run has checkpointed stops it there (exit 5, its checkpoint kept, nothing journaled
    for it); the rerun resumes it from its step (not from t = 0) and ends bit-identical."""
    nml = write(tmp_path, "hysteresis", "newton", "hy")
    proc = start(exe, nml, tmp_path, threads=1)
    started(proc)
    wait_for_checkpoint(proc, tmp_path, "hy")
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=600)
    assert proc.returncode == 5, err
    assert checkpoints(tmp_path, "hy"), err
    journal = tmp_path / "out" / "hy.h5.journal"
    assert not journal.exists() or journal.read_text().count("\n") <= 1, journal.read_text()   # its header alone
    again = run(exe, nml, tmp_path, threads=1)
    assert again.returncode == 0, again.stderr
    assert "resumed" in again.stderr, again.stderr
    assert not checkpoints(tmp_path, "hy")
    same_results(references("hysteresis", "newton"), tmp_path / "out" / "hy.h5")


def stopped_timeseries(exe, tmp_path, sig=signal.SIGTERM):
    """Start the timeseries `ts` with periodic checkpoints and stop it with `sig` once it has
    written its first: it writes its checkpoint at the signal and exits 5; its stderr."""
    nml = write(tmp_path, "timeseries", "newton", "ts")
    proc = start(exe, nml, tmp_path)
    started(proc)
    wait_for_checkpoint(proc, tmp_path, "ts")
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=600)
    assert proc.returncode == 5, err
    return nml, err


@pytest.mark.parametrize("sig", [signal.SIGTERM, pytest.param(signal.SIGUSR1, marks=pytest.mark.slow)],
                         ids=["SIGTERM", "SIGUSR1"])
def test_timeseries_resumes_from_its_checkpoint(exe, tmp_path, references, sig):
    """A SIGTERM (or Slurm's SIGUSR1) in the middle of a long timeseries writes its checkpoint; the rerun says it
    resumed (it does not start again from t = 0) and ends bit-identical."""
    nml, err = stopped_timeseries(exe, tmp_path, sig)
    assert "checkpoint written" in err
    [ckpt] = checkpoints(tmp_path, "ts")
    assert ckpt.read_bytes().startswith(b"supratrans-checkpoint 1\n")
    again = run(exe, nml, tmp_path)
    assert again.returncode == 0, again.stderr
    assert "resumed from its checkpoint" in again.stderr
    same_results(references("timeseries", "newton"), tmp_path / "out" / "ts.h5")


@pytest.mark.parametrize("damage", ["flipped byte", pytest.param("cut short", marks=pytest.mark.slow),
                                    pytest.param("other input", marks=pytest.mark.slow)])
def test_damaged_or_foreign_checkpoint_is_ignored(exe, tmp_path, references, damage):
    """A checkpoint that fails its checksum, is cut short, or belongs to another input is ignored with one line and
    the run starts afresh (and ends with the uninterrupted result)."""
    nml, _ = stopped_timeseries(exe, tmp_path)
    [ckpt] = checkpoints(tmp_path, "ts")
    data = bytearray(ckpt.read_bytes())
    if damage == "flipped byte":
        data[len(data) // 2] ^= 0x10
        ckpt.write_bytes(bytes(data))
    elif damage == "cut short":
        ckpt.write_bytes(bytes(data[: len(data) - 100]))
    else:
        write(tmp_path, "timeseries", "newton", "ts", tag="an edited namelist is another input")
    again = run(exe, nml, tmp_path)
    assert again.returncode == 0, again.stderr
    lines = [line for line in again.stderr.splitlines() if "checkpoint" in line]
    assert len(lines) == 1 and "ignored" in lines[0], again.stderr
    assert "resumed" not in again.stderr
    same_results(references("timeseries", "newton"), tmp_path / "out" / "ts.h5")


def test_no_checkpoint_when_off(exe, tmp_path):
    """checkpoint_every = 0: a SIGTERM stops the timeseries as before (nothing written, exit 5, no checkpoint)."""
    # signalled as soon as its stop signals are caught (its first line), with all its 20000 time units ahead
    nml = write(tmp_path, "timeseries", "rk4", "ts", every=0, t_final=20000.0)
    proc = start(exe, nml, tmp_path)
    started(proc)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=600)
    assert proc.returncode == 5, err
    assert "nothing written" in err
    assert not checkpoints(tmp_path, "ts")
    assert not (tmp_path / "out" / "ts.h5").exists()


def test_slice_stopped_by_sigusr1_resumes_and_merges(exe, tmp_path, references):
    """Slurm's `--signal=B:USR1`: a slice of a search study stopped by SIGUSR1 once its searches have checkpointed
    writes their checkpoints and exits 5; run again it resumes them, and the merged file is the single machine's."""
    nml = write(tmp_path, "search", "rk4", "search_rk4")
    env = dict(os.environ, OMP_NUM_THREADS="2")
    proc = subprocess.Popen([exe, str(nml), "--slice", "1/2"], cwd=tmp_path, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env)
    first = started(proc)
    wait_for_checkpoint(proc, tmp_path, "search_rk4.part-1-of-2")
    proc.send_signal(signal.SIGUSR1)
    _, err = proc.communicate(timeout=600)
    assert proc.returncode == 5, first + err
    assert checkpoints(tmp_path, "search_rk4.part-1-of-2") and "stopped by signal 10" in err, err
    for part in ("1/2", "2/2"):
        again = subprocess.run([exe, str(nml), "--slice", part], cwd=tmp_path, capture_output=True, text=True,
                               timeout=600, env=env)
        assert again.returncode == 0, again.stderr
        if part == "1/2":
            assert "resumed" in again.stderr, again.stderr
    parts = sorted(str(p) for p in (tmp_path / "out").glob("search_rk4.part-*-of-2.h5"))
    merged = subprocess.run([exe, "merge", *parts], cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert merged.returncode == 0, merged.stderr
    assert not list((tmp_path / "out").glob("*.checkpoint*"))
    same_results(references("search", "rk4"), tmp_path / "out" / "search_rk4.h5")
