"""The batch scripts of input/slurm/ on a real Slurm: a one-node cluster on localhost (munged, slurmctld, slurmd
started by hand with their own configuration, no systemd), a study submitted as a job array with a dependent merge
(behind a user's --dependency, options after --), compared with the single-machine file; one array task cancelled
mid-way and resubmitted, one requeued (scontrol requeue) and one sent the SIGUSR1 that Slurm sends before a time
limit (scancel --batch --signal=USR1), each resuming from its journal (these two run at once); submissions refused
before anything is queued. Where Slurm cannot start (not root, packages missing) the tests are skipped with one line
saying why.

No test waits for a clock: each signal is sent once the slice has journaled a task (an event the test sees), to a
run that has most of its work still ahead, and every wait polls with a short interval under an overall bound. The
cluster is configured not to idle: a requeued job may start again after cred_expire + 1 s (10 + 1 here, Slurm's
default 120 + 1), and the scheduler looks at pending jobs every second (sched_interval, default 60)."""
import os
import shutil
import signal
import socket
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path

import h5py
import pytest

import compare_results
from test_slices import lpt

#: A real cluster, release builds and resumed studies: about two minutes.
pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[1]
SCRIPTS = ROOT / "input" / "slurm"

STUDY = """&chain n = 60, n0 = 45 /
&numerics t_final = {t_final} /
&scene kind = 'bifurcation', amplitude_min = 0.5, amplitude_max = 6.0, omega_min = 0.5, omega_max = 0.9,
  omega_step = 0.1, coarse_step = 0.5, resolution = 0.1, potentials = 'sine-gordon', 'klein-gordon' /
&output file = 'out/study.h5' /
"""

CONF = """ClusterName=supratrans-test
SlurmctldHost=localhost
SlurmUser=root
SlurmdUser=root
SlurmctldPort={ctld_port}
SlurmdPort={d_port}
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket={dir}/munge.socket,cred_expire=10
StateSaveLocation={dir}/state
SlurmdSpoolDir={dir}/spool
SlurmctldPidFile={dir}/slurmctld.pid
SlurmdPidFile={dir}/slurmd.pid
SlurmctldLogFile={dir}/slurmctld.log
SlurmdLogFile={dir}/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
SchedulerType=sched/builtin
SchedulerParameters=sched_interval=1
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
KillWait=10
MinJobAge=600
InactiveLimit=0
SlurmdTimeout=60
NodeName=localhost CPUs=2 RealMemory={memory_mb} State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
"""


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def node_memory_mb():
    """Most of this machine's memory (MB), the node's RealMemory: submit.sh asks for --mem, which a node without it
    (1 MB by default) cannot satisfy; more than the machine has would drain the node."""
    for line in Path("/proc/meminfo").read_text().splitlines():
        if line.startswith("MemTotal:"):
            return int(line.split()[1]) // 1024 * 9 // 10
    return 1024


def why_no_slurm():
    if os.geteuid() != 0:
        return "not root: a one-node Slurm needs root to run slurmd"
    for tool in ("munged", "slurmctld", "slurmd", "sbatch", "squeue", "scontrol", "scancel"):
        if shutil.which(tool) is None:
            return f"{tool} not installed (apt-get install slurm-wlm munge)"
    return None


class Cluster:
    """A one-node Slurm on localhost; every daemon it starts is stopped by PID in `stop`."""

    def __init__(self, folder: Path):
        self.dir = folder
        self.pids = []
        self.env = dict(os.environ, SLURM_CONF=str(folder / "slurm.conf"))

    def start(self):
        d = self.dir
        for sub in ("state", "spool"):
            (d / sub).mkdir()
        key = d / "munge.key"
        key.write_bytes(os.urandom(1024))
        key.chmod(0o400)
        (d / "slurm.conf").write_text(CONF.format(dir=d, ctld_port=free_port(), d_port=free_port(),
                                                   memory_mb=node_memory_mb()))
        subprocess.run(["munged", f"--key-file={key}", f"--socket={d}/munge.socket", f"--pid-file={d}/munged.pid",
                        f"--log-file={d}/munged.log", f"--seed-file={d}/munged.seed", "--force"],
                       check=True, capture_output=True, timeout=30)
        self.pids.append(self.pidfile("munged.pid"))
        subprocess.run(["slurmctld", "-f", str(d / "slurm.conf")], check=True, capture_output=True, env=self.env,
                       timeout=30)
        self.pids.append(self.pidfile("slurmctld.pid"))
        subprocess.run(["slurmd", "-f", str(d / "slurm.conf"), "-N", "localhost"], check=True, capture_output=True,
                       env=self.env, timeout=30)
        self.pids.append(self.pidfile("slurmd.pid"))
        deadline = time.time() + 60
        while time.time() < deadline:
            out = self.run("sinfo", "-h", "-o", "%t", check=False).stdout.strip()
            if out in ("idle", "mix", "alloc"):
                return
            time.sleep(0.5)
        raise RuntimeError(f"the node did not come up (sinfo: {out!r}); see {d}/slurmctld.log")

    def pidfile(self, name):
        path = self.dir / name
        deadline = time.time() + 20
        while time.time() < deadline:
            if path.exists() and path.read_text().strip():
                return int(path.read_text().split()[0])
            time.sleep(0.1)
        raise RuntimeError(f"{name} not written")

    def stop(self):
        for pid in reversed(self.pids):
            try:
                os.kill(pid, signal.SIGTERM)
            except ProcessLookupError:
                continue
        deadline = time.time() + 20
        for pid in self.pids:
            while time.time() < deadline:
                try:
                    os.kill(pid, 0)
                except ProcessLookupError:
                    break
                time.sleep(0.1)
            else:
                try:
                    os.kill(pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass

    def run(self, *cmd, cwd=None, check=True, env=None):
        proc = subprocess.run(list(cmd), cwd=cwd, env=env or self.env, capture_output=True, text=True, timeout=60)
        if check:
            assert proc.returncode == 0, f"{cmd}: {proc.stderr}"
        return proc

    def state(self, job):
        out = self.run("scontrol", "-o", "show", "job", str(job), check=False).stdout
        states = [w.split("=", 1)[1] for w in out.split() if w.startswith("JobState=")]
        return states

    def wait(self, job, timeout=300):
        """Wait until every task of `job` has ended (polled every 0.2 s, at most `timeout` s: a bound, not a
        moment anything is expected at); return their states."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            states = self.state(job)
            if states and all(s in ENDED for s in states):
                return states
            time.sleep(0.2)
        raise AssertionError(f"job {job} did not end in {timeout} s: {self.state(job)}")

    def wait_for_journal(self, job, journal, tasks, timeout=300):
        """Wait until `journal` holds `tasks` journaled tasks (polled every 0.05 s, at most `timeout` s); fails
        when the job `job` ends first."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline and journal_lines(journal) < tasks:
            states = self.state(job)
            assert not (states and all(s in ENDED for s in states)), f"job {job} ended ({states}) before its journal"
            time.sleep(0.05)
        assert journal_lines(journal) >= tasks, f"job {job}: no task journaled in {timeout} s: {self.state(job)}"


#: The states of a job that has ended.
ENDED = ("COMPLETED", "FAILED", "CANCELLED", "TIMEOUT", "NODE_FAIL", "OUT_OF_MEMORY")


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    reason = why_no_slurm()
    if reason:
        pytest.skip(f"Slurm cannot start here: {reason}")
    c = Cluster(tmp_path_factory.mktemp("slurm"))
    try:
        c.start()
    except (subprocess.SubprocessError, RuntimeError, OSError) as exc:
        c.stop()
        pytest.skip(f"Slurm cannot start here: {exc}")
    yield c
    c.stop()


@pytest.fixture(scope="module")
def release_exe(release_exe):
    """The release executable of conftest.py (built through .ci/with_commit) as a string: it goes into the
    environment of the jobs."""
    return str(release_exe)


def single_machine(exe, folder, text):
    (folder / "study.nml").write_text(text)
    subprocess.run([exe, "study.nml"], cwd=folder, check=True, capture_output=True, timeout=300)
    (folder / "out" / "study.h5").rename(folder / "whole.h5")


def submit(cluster, folder, *args, env):
    proc = subprocess.run(["bash", str(SCRIPTS / "submit.sh"), *args], cwd=folder, env=env, capture_output=True,
                          text=True, timeout=600)
    return proc


def field(cluster, job, name):
    out = cluster.run("scontrol", "-o", "show", "job", str(job), check=False).stdout
    return [w.split("=", 1)[1] for w in out.split() if w.startswith(name + "=")]


def test_array_and_merge_equal_the_single_machine_file(cluster, release_exe, tmp_path):
    single_machine(release_exe, tmp_path, STUDY.format(t_final="40.0"))
    env = dict(cluster.env, SUPRATRANS=release_exe)
    # a user's own dependency (a job that holds the study back) and NAMELIST N -- opts without THROTTLE; the
    # slices dealt by the costs measured in the single-machine file (--costs, copied at submission)
    hold = cluster.run("sbatch", "--parsable", "--hold", "--wrap", "true", cwd=tmp_path).stdout.strip().split(";")[0]
    proc = submit(cluster, tmp_path, "study.nml", "3", "--costs", "whole.h5", "--", "--cpus-per-task=1",
                  f"--dependency=afterok:{hold}", env=env)
    assert proc.returncode == 0, proc.stderr
    words = proc.stdout.split()
    array, merge = words[2], words[-1]
    # the namelist edited after the submission changes nothing: the tasks read the study's copy
    (tmp_path / "study.nml").write_text(STUDY.format(t_final="45.0"))
    assert field(cluster, array, "JobName")[0] == "supratrans-study"
    assert f"afterok:{hold}" in field(cluster, array, "Dependency")[0]
    merge_dep = field(cluster, merge, "Dependency")[0]
    assert f"afterok:{array}" in merge_dep and f"afterok:{hold}" in merge_dep, merge_dep
    assert all(s == "PENDING" for s in cluster.state(array))
    cluster.run("scontrol", "release", hold)
    assert cluster.wait(hold) == ["COMPLETED"]
    assert all(s == "COMPLETED" for s in cluster.wait(array)), list((tmp_path / "out").rglob("*.out"))
    assert cluster.wait(merge) == ["COMPLETED"], (tmp_path / "out" / "study.slurm" / "merge.out").read_text()
    diffs, compared, _ = compare_results.compare(tmp_path / "whole.h5", tmp_path / "out" / "study.h5")
    assert compared > 5 and not diffs, diffs
    assert len(list((tmp_path / "out").glob("study.part-*-of-3.h5"))) == 3
    with h5py.File(tmp_path / "whole.h5") as f:
        owner = lpt(list(f["cost/cpu_time"][()].ravel()), 3)
    for i in (1, 2, 3):
        with h5py.File(tmp_path / "out" / f"study.part-{i}-of-3.h5") as f:
            assert list(f["part/task"][()]) == [t + 1 for t in range(len(owner)) if owner[t] == i]
    with h5py.File(tmp_path / "out" / "study.h5") as f:
        parts = f["provenance/parts"][()].decode().splitlines()      # where, when and how long each slice ran
        assert [p.split("\t")[0] for p in parts] == ["1", "2", "3"]
        assert abs(f["cost"].attrs["scene_wall_time_s"] - sum(float(p.split("\t")[4]) for p in parts)) < 1e-9
    logs = sorted((tmp_path / "out" / "study.slurm").glob("slice-*.out"))
    assert len(logs) == 3 and all("slice" in p.read_text() for p in logs)


def test_refused_at_submission(cluster, release_exe, tmp_path):
    """An existing output without overwrite, a missing executable, a namelist that does not pass --check: one line
    each, nothing queued."""
    text = STUDY.format(t_final="40.0")
    (tmp_path / "study.nml").write_text(text)
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "study.h5").write_bytes(b"an earlier result")
    env = dict(cluster.env, SUPRATRANS=release_exe)
    before = cluster.run("squeue", "-h", "-o", "%i").stdout.split()
    proc = submit(cluster, tmp_path, "study.nml", "2", env=env)
    assert proc.returncode == 2 and "exists" in proc.stderr, proc.stderr     # (--check says so)
    assert "overwrite" in proc.stderr
    (tmp_path / "out" / "study.h5").unlink()
    proc = submit(cluster, tmp_path, "study.nml", "2", env=dict(env, SUPRATRANS=str(tmp_path / "no-such-exe")))
    assert proc.returncode == 2 and "no-such-exe" in proc.stderr, proc.stderr
    (tmp_path / "study.nml").write_text(text.replace("n = 60", "n = -60"))
    proc = submit(cluster, tmp_path, "study.nml", "2", env=env)
    assert proc.returncode == 2 and "--check" in proc.stderr, proc.stderr
    assert cluster.run("squeue", "-h", "-o", "%i").stdout.split() == before
    assert not (tmp_path / "out" / "study.h5").exists()


#: A study of 10 long searches (unscreened, T = 6000: about 7 s of one quiet core in the release build, 0.7 s a
#: search; screened, a slice of it ends in about 0.1 s). A signal sent once a slice has journaled its first search
#: finds most of the slice's searches still ahead of it.
LONG = STUDY.format(t_final="6000.0").replace("resolution = 0.1,", "resolution = 0.1, screen_method = 'none',")


@pytest.fixture(scope="module")
def long_reference(release_exe, tmp_path_factory):
    """The single-machine file of LONG, made once for the tests that stop a slice of it."""
    folder = tmp_path_factory.mktemp("long")
    single_machine(release_exe, folder, LONG)
    return folder / "whole.h5"


def test_cancelled_task_resubmitted_resumes_from_its_journal(cluster, release_exe, long_reference, tmp_path):
    assert "screen_method = 'none'" in LONG
    (tmp_path / "study.nml").write_text(LONG)
    env = dict(cluster.env, SUPRATRANS=release_exe)
    array_script = str(SCRIPTS / "supratrans-array.sbatch")
    job = cluster.run("sbatch", "--parsable", "--array=1-2", "--cpus-per-task=1", array_script, "study.nml", "2",
                      cwd=tmp_path, env=env).stdout.strip().split(";")[0]
    journal = tmp_path / "out" / "study.part-2-of-2.h5.journal"
    cluster.wait_for_journal(f"{job}_2", journal, 1)
    cluster.run("scancel", f"{job}_2")
    states = cluster.wait(job)
    assert "CANCELLED" in states or "FAILED" in states, states
    lines = journal.read_text().splitlines()[1:]
    tasks_before = [int(x.split()[0]) for x in lines]
    assert tasks_before and len(tasks_before) == len(set(tasks_before))
    assert not (tmp_path / "out" / "study.part-2-of-2.h5").exists()
    again = cluster.run("sbatch", "--parsable", "--array=2", "--cpus-per-task=1", array_script, "study.nml", "2",
                        cwd=tmp_path, env=env).stdout.strip().split(";")[0]
    assert cluster.wait(again) == ["COMPLETED"]
    log = (tmp_path / f"supratrans-{again}_2.out").read_text()
    assert f"{len(tasks_before)} already done" in log, log       # the journal's runs were not done again
    finish_and_compare(cluster, tmp_path, env, long_reference, 2)


def journal_lines(path):
    return path.read_text().count("\n") - 1 if path.exists() else 0


def finish_and_compare(cluster, folder, env, reference, slices):
    merge = cluster.run("sbatch", "--parsable", str(SCRIPTS / "supratrans-merge.sbatch"), "study.nml", str(slices),
                        cwd=folder, env=env).stdout.strip().split(";")[0]
    assert cluster.wait(merge) == ["COMPLETED"]
    diffs, compared, _ = compare_results.compare(reference, folder / "out" / "study.h5")
    assert compared > 5 and not diffs, diffs


def resumed_counts(log):
    """The `N already done` of each run of a slice in its log, in order."""
    return [int(line.split(" already done")[0].split(",")[-1]) for line in log.splitlines() if "already done" in line]


def submit_one_slice(cluster, folder, env):
    """LONG as an array of one slice (the script's own --signal and --requeue, no time limit to wait for); the job
    id (the slice may not have started yet)."""
    (folder / "study.nml").write_text(LONG)
    return cluster.run("sbatch", "--parsable", "--array=1", "--cpus-per-task=1",
                       str(SCRIPTS / "supratrans-array.sbatch"), "study.nml", "1", cwd=folder,
                       env=env).stdout.strip().split(";")[0]


@dataclass
class Stopped:
    """A one-slice job of LONG stopped mid-way: its folder, job id, the searches journaled when it was stopped, and
    the states of its tasks once it ended."""
    folder: Path
    job: str
    done_before: int
    states: list

    def log(self):
        return (self.folder / f"supratrans-{self.job}_1.out").read_text()


@pytest.fixture(scope="module")
def stopped(cluster, release_exe, tmp_path_factory):
    """Two one-slice jobs of LONG at once, one a CPU each: `requeue`, requeued by scontrol requeue once its slice has
    journaled a search (what a preempting scheduler does), and `usr1`, sent at that event the SIGUSR1 that Slurm
    sends the batch shell before a time limit (the script's --signal=B:USR1@120, here scancel --batch
    --signal=USR1 rather than a limit to wait for). Together, their waits for a requeued job to be eligible again
    (cred_expire + 1 s) overlap."""
    env = dict(cluster.env, SUPRATRANS=release_exe)
    folders = {name: tmp_path_factory.mktemp(name) for name in ("requeue", "usr1")}
    jobs = {name: submit_one_slice(cluster, folder, env) for name, folder in folders.items()}
    signals = {"requeue": ("scontrol", "requeue"), "usr1": ("scancel", "--batch", "--signal=USR1")}
    journals = {name: folder / "out" / "study.part-1-of-1.h5.journal" for name, folder in folders.items()}
    done_before = {}
    deadline = time.monotonic() + 300       # a bound, not a moment anything is expected at
    while len(done_before) < len(jobs):     # each signalled as soon as its own slice has journaled a search
        for name, job in jobs.items():
            if name not in done_before and journal_lines(journals[name]) >= 1:
                cluster.run(*signals[name], f"{job}_1")
                done_before[name] = journal_lines(journals[name])
            elif name not in done_before:
                states = cluster.state(job)
                assert not (states and all(s in ENDED for s in states)), f"job {job} ended ({states}), no journal"
        assert time.monotonic() < deadline, f"no search journaled in 300 s: {[cluster.state(j) for j in jobs.values()]}"
        time.sleep(0.05)
    return {name: Stopped(folders[name], job, done_before[name], cluster.wait(job)) for name, job in jobs.items()}


def test_requeued_task_resumes_from_its_journal(cluster, release_exe, long_reference, stopped):
    """scontrol requeue of a running slice: the rerun of the same job resumes from what the first run journaled,
    and its log is appended to the first run's."""
    run = stopped["requeue"]
    log = run.log()
    assert run.states == ["COMPLETED"], log
    assert log.count("supratrans-array: slice 1/1") == 2, log        # both runs in one log
    assert "requeued to resume" not in log, log                      # Slurm requeued it, not the script
    resumed = resumed_counts(log)
    assert len(resumed) == 2 and resumed[0] == 0 and resumed[1] >= max(run.done_before - 1, 1), log
    finish_and_compare(cluster, run.folder, dict(cluster.env, SUPRATRANS=release_exe), long_reference, 1)


def test_sigusr1_before_the_time_limit_stops_requeues_and_resumes(cluster, release_exe, long_reference, stopped):
    """The SIGUSR1 before a time limit: a clean stop, the task requeues itself, the rerun resumes from the journal;
    the merged file is the single machine's."""
    run = stopped["usr1"]
    log = run.log()
    assert run.states == ["COMPLETED"], log
    assert log.count("requeued to resume") == 1, log
    assert int(field(cluster, f"{run.job}_1", "Restarts")[0]) == 1
    resumed = resumed_counts(log)
    assert len(resumed) == 2 and resumed[0] == 0 and resumed[1] >= 1, log
    finish_and_compare(cluster, run.folder, dict(cluster.env, SUPRATRANS=release_exe), long_reference, 1)
