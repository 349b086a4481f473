"""Resources and signals (issue 22, items 8, 9, 11 and `--check` on a read-only file system): memory limits of a
cgroup and of `ulimit -v` are refused before the work in one line, an absurd OMP_NUM_THREADS is bounded with a line
saying so, the timeseries scene stops at a signal and honours the work limit like every other scene, and `merge`
stops cleanly at a signal (status 5, nothing left)."""
import os
import resource
import signal
import subprocess
import time
from pathlib import Path

import pytest

TS = """&chain n = {n}, n0 = 30 /
&record probes = 5 /
&numerics t_final = {t_final} /
&output file = 'out/s.h5', quiet = .true. /
"""
SWEEP = """&chain n = 40, n0 = 30 /
&numerics t_final = 10.0 /
&scene kind = 'amplitude_sweep', amplitude_min = 1.0, amplitude_max = 1.6, amplitude_step = 0.2 /
&output file = '{out}', quiet = .true. /
"""
STOPS = [signal.SIGTERM, signal.SIGINT, signal.SIGUSR1]


def run(exe, *args, cwd, env=None, timeout=300, preexec_fn=None):
    full = dict(os.environ, **(env or {}))
    return subprocess.run([exe, *map(str, args)], cwd=cwd, capture_output=True, text=True, timeout=timeout, env=full,
                          preexec_fn=preexec_fn)


def one_line(proc, status, *words):
    """The run ended with `status` and one line on stderr holding every word (no backtrace)."""
    assert proc.returncode == status, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    for word in words:
        assert word in lines[0], lines[0]
    return lines[0]


def namelist(tmp_path, text, name="s.nml"):
    (tmp_path / "out").mkdir(exist_ok=True)
    path = tmp_path / name
    path.write_text(text)
    return path


def with_pending(sig):
    """preexec_fn: the child starts with `sig` blocked and already pending (the mask is inherited across exec), so
    that it arrives the moment the program installs its handler: "a signal early in the run", deterministically."""
    def pending():
        signal.pthread_sigmask(signal.SIG_BLOCK, [sig])
        os.kill(os.getpid(), sig)
    return pending


def leftovers(directory, keep=()):
    return sorted(p.name for p in Path(directory).iterdir() if p.name not in keep)


# ---------------------------------------------------------------------------------- 9. timeseries: signals, work

@pytest.mark.parametrize("sig", STOPS, ids=[s.name for s in STOPS])
def test_timeseries_stops_at_a_signal_and_writes_nothing(exe, tmp_path, sig):
    """A stop signal that arrives as the run starts ends it at once: status 5, one line, no output, no temporary
    (but the mid-run checkpoint it resumes from, issue 23: the lock file is removed as the run ends). Today's code ignored it and ran to
    the end (exit 0)."""
    namelist(tmp_path, TS.format(n=40, t_final=20000.0))
    proc = run(exe, "s.nml", cwd=tmp_path, preexec_fn=with_pending(sig), timeout=120)
    line = one_line(proc, 5, "out/s.h5", "timeseries stopped by signal " + str(int(sig)), "checkpoint written")
    assert "t = 0" in line
    assert leftovers(tmp_path / "out") == ["s.h5.checkpoint"]


def test_timeseries_stops_at_sigterm_sent_while_it_runs(exe, tmp_path):
    """SIGTERM sent to a running timeseries (once its handler is in place) stops it before T."""
    namelist(tmp_path, TS.format(n=40, t_final=1.0e5))
    proc = subprocess.Popen([exe, "s.nml"], cwd=tmp_path, stderr=subprocess.PIPE, text=True)
    try:
        wait_for_handler(proc.pid, signal.SIGTERM)
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 5, err
    assert len(err.strip().splitlines()) == 1 and "timeseries stopped by signal 15" in err, err
    assert leftovers(tmp_path / "out") == ["s.h5.checkpoint"]


def wait_for_handler(pid, sig, timeout=60.0):
    """Wait until process `pid` catches `sig` (its bit in SigCgt of /proc/PID/status)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            fields = dict(line.split(":", 1) for line in Path(f"/proc/{pid}/status").read_text().splitlines()
                          if ":" in line)
        except FileNotFoundError:
            return
        if int(fields["SigCgt"].strip(), 16) >> (int(sig) - 1) & 1:
            return
        time.sleep(0.01)
    pytest.fail("the program never installed its signal handler")


def test_timeseries_beyond_the_work_limit_is_refused(exe, tmp_path):
    """5e13 oscillator-steps, the limit of every scene, holds for a timeseries too: refused before the work, status
    2, one line naming the limit (10^8 steps x 10^6 oscillators; records sparse so that memory is not the issue)."""
    namelist(tmp_path, """&chain n = 1000000, n0 = 30 /
&record probes = 5, probe_every = 1000000, ledger_every = 1000000 /
&numerics t_final = 1.0e6, dt = 0.01 /
&output file = 'out/s.h5', quiet = .true. /
""")
    proc = run(exe, "s.nml", cwd=tmp_path, timeout=60)
    one_line(proc, 2, "oscillator-steps", "5.0e13", "limit")
    assert leftovers(tmp_path / "out") == []
    assert run(exe, "--check", "s.nml", cwd=tmp_path).returncode == 2


# -------------------------------------------------------------------------------- 11. merge stops cleanly

def make_parts(exe, tmp_path, n=2):
    namelist(tmp_path, SWEEP.format(out="parts/p.h5"), name="p.nml")
    for i in range(1, n + 1):
        proc = run(exe, "p.nml", "--slice", f"{i}/{n}", cwd=tmp_path)
        assert proc.returncode == 0, proc.stderr
    return sorted((tmp_path / "parts").glob("p.part-*.h5"))


@pytest.mark.parametrize("partial", [False, True], ids=["merge", "merge --partial"])
@pytest.mark.parametrize("sig", STOPS, ids=[s.name for s in STOPS])
def test_merge_stopped_early_by_a_signal_leaves_nothing(exe, tmp_path, sig, partial):
    """A signal early in `merge` (it arrives the moment the program can catch it): status 5, one line, nothing
    written (no output, journal, snapshot or temporary; the parts unchanged). Today's code ignored it until the
    scene ran, and was killed (143) before that."""
    parts = make_parts(exe, tmp_path)
    before = {p: p.read_bytes() for p in parts}
    names = leftovers(tmp_path / "parts")
    args = ["merge", *(["--partial"] if partial else []), *parts]
    proc = run(exe, *args, cwd=tmp_path, preexec_fn=with_pending(sig), timeout=120)
    one_line(proc, 5, "merge: stopped by signal " + str(int(sig)), "nothing written")
    assert leftovers(tmp_path / "parts") == names          # no p.h5, journal, snapshot, lock or temporary
    assert {p: p.read_bytes() for p in parts} == before
    proc = run(exe, *args, cwd=tmp_path, timeout=120)    # the same command then merges
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "parts" / ("p.h5.partial.h5" if partial else "p.h5")).is_file()


def test_merge_signalled_at_any_moment_ends_whole_or_cleanly(exe, tmp_path):
    """SIGTERM at a spread of moments once `merge` catches it: either the merge finished (0, the output whole and
    nothing else beside it, not even the lock) or it stopped (5, one line, nothing left); never 143."""
    parts = make_parts(exe, tmp_path)
    names = leftovers(tmp_path / "parts")
    for delay in [0.0, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1]:
        for extra in ["p.h5", "p.h5.lock"]:
            (tmp_path / "parts" / extra).unlink(missing_ok=True)
        proc = subprocess.Popen([exe, "merge", *parts], cwd=tmp_path, stderr=subprocess.PIPE, text=True)
        wait_for_handler(proc.pid, signal.SIGTERM)
        time.sleep(delay)
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=120)
        assert proc.returncode in (0, 5), (delay, proc.returncode, err)
        if proc.returncode == 5:
            assert len(err.strip().splitlines()) == 1, err
            assert leftovers(tmp_path / "parts") == names
        else:
            assert leftovers(tmp_path / "parts") == sorted(names + ["p.h5"])


# ------------------------------------------------------------------ --check on a read-only file system

@pytest.fixture
def read_only_mount(tmp_path):
    mount = tmp_path / "ro"
    mount.mkdir()
    if os.geteuid() != 0 or subprocess.run(["mount", "-t", "tmpfs", "-o", "ro,size=64k", "tmpfs", str(mount)],
                                           capture_output=True).returncode != 0:
        pytest.skip("cannot mount a read-only tmpfs here (needs root)")
    yield mount
    subprocess.run(["umount", "-l", str(mount)], capture_output=True)


@pytest.mark.parametrize("out", ["ro/s.h5", "ro/new/deeper/s.h5"])
def test_check_says_which_directory_cannot_be_written(exe, tmp_path, read_only_mount, out):
    """`--check` asks access(2) W_OK of the nearest existing directory of the output: on a read-only file system it
    ends with the run's status 4 and one line naming the directory and the reason. It used to say ok."""
    namelist(tmp_path, TS.format(n=40, t_final=2.0).replace("out/s.h5", out))
    proc = run(exe, "--check", "s.nml", cwd=tmp_path, timeout=60)
    one_line(proc, 4, "'ro'", "Read-only file system", "W_OK")
    assert run(exe, "s.nml", cwd=tmp_path, timeout=60).returncode == 4      # the run agrees


def test_check_says_ok_on_a_writable_directory_and_creates_nothing(exe, tmp_path):
    namelist(tmp_path, TS.format(n=40, t_final=2.0).replace("out/s.h5", "out/new/s.h5"))
    proc = run(exe, "--check", "s.nml", cwd=tmp_path, timeout=60)
    assert proc.returncode == 0, proc.stderr
    assert leftovers(tmp_path / "out") == []


# ------------------------------------------------------------------------------ 8. memory and threads

def fake_cgroups(root, lines, files):
    """A fake tree for SUPRATRANS_TEST_CGROUP_ROOT: `lines` of proc/self/cgroup, `files` {path under sys/fs/cgroup:
    text}."""
    (root / "proc" / "self").mkdir(parents=True)
    (root / "proc" / "self" / "cgroup").write_text("".join(line + "\n" for line in lines))
    for name, text in files.items():
        path = root / "sys" / "fs" / "cgroup" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text + "\n")
    return {"SUPRATRANS_TEST_CGROUP_ROOT": str(root)}


# a chain of 10^5 oscillators needs about 16 MB; the cgroups below allow 10 MB somewhere up the hierarchy
CGROUPS = {
    "v2, limit on the job above the step": (["0::/job_7/step_0/task_0"],
                                            {"job_7/memory.max": "10000000", "job_7/step_0/memory.max": "max",
                                             "job_7/step_0/task_0/memory.max": "max", "memory.max": "max"},
                                            "job_7/memory.max"),
    "v2, limit on the process's own cgroup": (["0::/user.slice/a.scope"],
                                              {"user.slice/a.scope/memory.max": "10000000"},
                                              "a.scope/memory.max"),
    "v1 memory controller": (["12:pids:/x", "4:memory:/slurm/uid_0/job_7", "3:cpu,cpuacct:/x", "0::/"],
                             {"memory/slurm/uid_0/job_7/memory.limit_in_bytes": "10000000",
                              "memory/memory.limit_in_bytes": "9223372036854771712"},
                             "job_7/memory.limit_in_bytes"),
    "v1 inside a container (path not mounted: the mount's root)": (
        ["4:memory:/process_api/abc"], {"memory/memory.limit_in_bytes": "10000000"}, "memory/memory.limit_in_bytes"),
}


@pytest.mark.parametrize("case", sorted(CGROUPS))
def test_cgroup_memory_limit_is_refused_before_the_work(exe, tmp_path, case):
    """A cgroup limit below what the run needs (Slurm's --mem: the job was OOM-killed, exit 137, silently) is
    refused before the work: status 2, one line naming the cgroup file; nothing written."""
    lines, files, named = CGROUPS[case]
    env = fake_cgroups(tmp_path / "root", lines, files)
    namelist(tmp_path, TS.format(n=100000, t_final=0.1))
    proc = run(exe, "s.nml", cwd=tmp_path, env=env, timeout=120)
    one_line(proc, 2, "needs about 0.016 GB", "0.01 GB available", "cgroup", named)
    assert leftovers(tmp_path / "out") == []
    assert run(exe, "--check", "s.nml", cwd=tmp_path, env=env).returncode == 2


def test_cgroup_without_a_limit_runs(exe, tmp_path):
    env = fake_cgroups(tmp_path / "root", ["0::/job_7/step_0"],
                       {"job_7/memory.max": "max", "job_7/step_0/memory.max": "max"})
    namelist(tmp_path, TS.format(n=100000, t_final=0.1))
    proc = run(exe, "s.nml", cwd=tmp_path, env=env, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "out" / "s.h5").is_file()


def address_space_limit(kib):
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (kib*1024, kib*1024))
    return limit


def starts_under(exe, tmp_path, kib):
    """Whether the program starts at all under RLIMIT_AS = kib KiB (`--version`): below some limit the loader cannot
    map the libraries, or a library's start-up fails or hangs (OpenBLAS, openmp flavour) before main: not ours."""
    try:
        return run(exe, "--version", cwd=tmp_path, timeout=8, preexec_fn=address_space_limit(kib)).returncode == 0
    except subprocess.TimeoutExpired:
        return False


STARTS = {}


def smallest_start(exe, tmp_path):
    """The smallest address-space limit (KiB, within 2 MiB) under which the program starts (bisection, once)."""
    if exe not in STARTS:
        STARTS[exe] = bisect_start(exe, tmp_path)
    return STARTS[exe]


def bisect_start(exe, tmp_path):
    low, high = 0, 4 << 20
    if not starts_under(exe, tmp_path, high):
        pytest.skip("the program does not start under a 4 GiB address-space limit here")
    while high - low > 2048:
        mid = (low + high)//2
        low, high = (low, mid) if starts_under(exe, tmp_path, mid) else (mid, high)
    return high


@pytest.mark.slow
def test_address_space_limit_ends_in_one_line_never_a_backtrace(exe, tmp_path):
    """Under `ulimit -v` (RLIMIT_AS) a little above what the program maps to run, a run of 10^5 oscillators (about
    16 MB more) used to die allocating with a backtrace (or a SIGSEGV): the check compared the need with the whole
    limit. Now it runs (0) or is refused in one line (2) before the work: the check counts what is mapped already."""
    base = smallest_start(exe, tmp_path)
    namelist(tmp_path, TS.format(n=100000, t_final=0.1))
    seen = set()
    for kib in range(base, base + 60001, 2500):
        if not starts_under(exe, tmp_path, kib):
            continue
        proc = run(exe, "s.nml", cwd=tmp_path, timeout=120, preexec_fn=address_space_limit(kib))
        assert proc.returncode in (0, 2), (kib - base, proc.returncode, proc.stderr)
        assert "Backtrace" not in proc.stderr and "Error allocating" not in proc.stderr, proc.stderr
        if proc.returncode == 2:
            one_line(proc, 2, "ulimit -v", "GB available")
            assert leftovers(tmp_path / "out") == []
        else:
            assert proc.stderr == "", proc.stderr
            (tmp_path / "out" / "s.h5").unlink()
        (tmp_path / "out" / "s.h5.lock").unlink(missing_ok=True)
        seen.add(proc.returncode)
    assert seen == {0, 2}, (base, seen)            # both sides of the limit were seen


def test_absurd_thread_count_is_bounded_with_one_line(exe, tmp_path):
    """OMP_NUM_THREADS=100000 used to crash the program (SIGSEGV creating threads): it runs with at most 4 threads
    a processor it may use (sched_getaffinity) and says so in one line."""
    namelist(tmp_path, SWEEP.format(out="out/s.h5"))
    cpus = len(os.sched_getaffinity(0))
    proc = run(exe, "s.nml", cwd=tmp_path, env={"OMP_NUM_THREADS": "100000"}, timeout=300)
    assert proc.returncode == 0, proc.stderr
    line = one_line(proc, 0, "100000 OpenMP threads", f"running {4*cpus}")
    assert line.startswith("supratrans: ")
    assert (tmp_path / "out" / "s.h5").is_file()


@pytest.mark.slow
@pytest.mark.parametrize("scene", ["timeseries", "amplitude_sweep"])
def test_allocation_failure_ends_in_one_line(exe, tmp_path, scene):
    """When memory runs out at an allocation all the same (the check before the work skipped by the test-only
    SUPRATRANS_TEST_NO_MEMORY_CHECK, as when its estimate is short), the run ends with one line naming what could
    not be allocated, status 2, never a backtrace; a scene journals no task of a run that could not allocate."""
    base = smallest_start(exe, tmp_path)
    text = TS.format(n=1000000, t_final=0.1)
    if scene == "amplitude_sweep":
        text = SWEEP.format(out="out/s.h5").replace("n = 40,", "n = 1000000,").replace("t_final = 10.0", "t_final = 0.1")
    namelist(tmp_path, text)
    env = {"SUPRATRANS_TEST_NO_MEMORY_CHECK": "1", "OMP_NUM_THREADS": "1"}
    proc = run(exe, "s.nml", cwd=tmp_path, env=env, timeout=120, preexec_fn=address_space_limit(base + 20000))
    line = one_line(proc, 2, "allocate", "out of memory")
    assert "Backtrace" not in proc.stderr and "Error allocating" not in proc.stderr
    if scene == "timeseries":
        assert "cannot allocate" in line and "oscillators" in line, line
    else:
        assert "after 0 of 4 runs" in line and "it resumes" in line, line
    assert not (tmp_path / "out" / "s.h5").exists()
    journal = tmp_path / "out" / "s.h5.journal"
    if journal.exists():
        assert journal.read_text().count("\n") == 1        # the header only: no task recorded
