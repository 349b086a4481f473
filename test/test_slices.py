"""Slices, merge, whole journal records, the output lock and a clean stop on SIGTERM, as a user drives them."""
import fcntl
import os
import random
import signal
import subprocess
import time
from pathlib import Path

import h5py
import pytest

import compare_results

BIF = """&chain n = 60, n0 = 45 /
&numerics t_final = 40.0 /
&scene kind = 'bifurcation', amplitude_min = 0.5, amplitude_max = 6.0, omega_min = 0.5, omega_max = 0.9,
  omega_step = 0.1, coarse_step = 0.5, resolution = 0.1, potentials = 'sine-gordon', 'klein-gordon' /
&output file = 'out/study.h5', quiet = .true. /
"""
SWEEP = """&chain n = 60, n0 = 45 /
&numerics t_final = 30.0 /
&scene kind = 'amplitude_sweep', amplitude_min = 1.0, amplitude_max = 2.4, amplitude_step = 0.2,
  vary = 'gamma', values = 0.0, 0.02 /
&output file = 'out/study.h5', quiet = .true. /
"""
WORKPREC = """&chain n = 40, n0 = 30 /
&numerics t_final = 20.0 /
&scene kind = 'work_precision', methods = 'newton', 'rk4', dts = 0.1, 0.05, repeats = 1, reference_dt = 0.05 /
&output file = 'out/study.h5', quiet = .true. /
"""


def sh(exe, *args, cwd, check=True):
    proc = subprocess.run([exe, *map(str, args)], cwd=cwd, capture_output=True, text=True, timeout=300)
    if check:
        assert proc.returncode == 0, proc.stderr
    return proc


def identical(a, b):
    diffs, compared, _ = compare_results.compare(a, b)
    assert compared > 5 and not diffs, diffs


@pytest.mark.parametrize("text,n", [(BIF, 3), (SWEEP, 4), (WORKPREC, 2)], ids=["bifurcation", "sweep", "work_precision"])
def test_slices_merged_equal_the_single_machine_file(exe, tmp_path, text, n):
    (tmp_path / "study.nml").write_text(text)
    sh(exe, "study.nml", cwd=tmp_path)
    (tmp_path / "out" / "study.h5").rename(tmp_path / "whole.h5")
    for i in range(1, n + 1):
        sh(exe, "study.nml", "--slice", f"{i}/{n}", cwd=tmp_path)
    parts = sorted((tmp_path / "out").glob("study.part-*.h5"))
    assert len(parts) == n
    assert not list((tmp_path / "out").glob("*.journal"))
    sh(exe, "merge", *parts, cwd=tmp_path)
    identical(tmp_path / "whole.h5", tmp_path / "out" / "study.h5")
    if "work_precision" not in text:
        return
    with h5py.File(tmp_path / "out" / "study.h5") as f:
        assert f.attrs["scene"] == b"work_precision"


def test_slices_interleave_the_tasks(exe, tmp_path):
    (tmp_path / "study.nml").write_text(BIF)
    sh(exe, "study.nml", "--slice", "2/3", cwd=tmp_path)
    with h5py.File(tmp_path / "out" / "study.part-2-of-3.h5") as f:
        assert list(f["part/task"][()]) == [2, 5, 8]
        assert f["part"].attrs["tasks_total"] == 10


def test_slices_are_dealt_by_cost(exe, tmp_path):
    """Largest-first by estimated cost: the frequencies outside the gap of the massless curve (Omega >= 1, no
    search, next to no cost) go to the slice with less work; the merged file is still the single machine's."""
    text = BIF.replace("omega_max = 0.9", "omega_max = 1.2").replace(
        "potentials = 'sine-gordon', 'klein-gordon'", "vary = 'm2', values = 0.0, 0.5")
    (tmp_path / "study.nml").write_text(text)
    sh(exe, "study.nml", cwd=tmp_path)
    (tmp_path / "out" / "study.h5").rename(tmp_path / "whole.h5")
    tasks = {}
    for i in (1, 2):
        sh(exe, "study.nml", "--slice", f"{i}/2", cwd=tmp_path)
        with h5py.File(tmp_path / "out" / f"study.part-{i}-of-2.h5") as f:
            tasks[i] = list(f["part/task"][()])
    outside = [6, 7, 8]                     # Omega = 1.0, 1.1, 1.2 of the curve m2 = 0 (gap edge 1)
    inside = [t for t in range(1, 17) if t not in outside]
    # the 13 searches round-robin (7 and 6), the three outside to the slice of 6
    assert [t for t in tasks[1] if t in inside] == inside[0::2]
    assert [t for t in tasks[2] if t in inside] == inside[1::2]
    assert [t for t in tasks[2] if t in outside] == outside and sorted(tasks[1] + tasks[2]) == list(range(1, 17))
    sh(exe, "merge", "--slices", "2", "study.nml", cwd=tmp_path)
    identical(tmp_path / "whole.h5", tmp_path / "out" / "study.h5")


def lpt(costs, n):
    """The largest-first deal of supratrans_tasks::slice_owners, in Python: costs rounded to 9 digits of the
    largest, decreasing (ties: lower task), each to the least loaded slice (ties: lower slice); 1-based slices."""
    top = max(costs)
    key = [int(round(1e9 * c / top)) for c in costs]
    load = [0] * n
    owner = [0] * len(costs)
    for t in sorted(range(len(costs)), key=lambda t: (-key[t], t)):
        s = min(range(n), key=lambda s: (load[s], s))
        owner[t] = s + 1
        load[s] += key[t]
    return owner


@pytest.mark.slow
def test_slices_dealt_by_measured_costs(exe, tmp_path):
    """--costs EARLIER.h5: the slices are dealt largest-first by the searches' processor times measured in an earlier
    output of the same study; the merged file is still the single machine's. An output of another study, or a file
    without costs, is refused in one line before any work."""
    (tmp_path / "study.nml").write_text(BIF)
    sh(exe, "study.nml", cwd=tmp_path)
    (tmp_path / "out" / "study.h5").rename(tmp_path / "whole.h5")
    with h5py.File(tmp_path / "whole.h5") as f:
        wall = list(f["cost/cpu_time"][()].ravel())       # (curve, omega): task order
    owner = lpt(wall, 3)
    for i in (1, 2, 3):
        sh(exe, "study.nml", "--slice", f"{i}/3", "--costs", "whole.h5", cwd=tmp_path)
        with h5py.File(tmp_path / "out" / f"study.part-{i}-of-3.h5") as f:
            assert list(f["part/task"][()]) == [t + 1 for t in range(len(wall)) if owner[t] == i]
    sh(exe, "merge", "--slices", "3", "study.nml", cwd=tmp_path)
    identical(tmp_path / "whole.h5", tmp_path / "out" / "study.h5")
    # refused: another study's output, a file that is not one, --costs without --slice
    (tmp_path / "other.nml").write_text(BIF.replace("omega_max = 0.9", "omega_max = 0.8").replace("study.h5",
                                                                                                  "other.h5"))
    sh(exe, "other.nml", cwd=tmp_path)
    (tmp_path / "sweep.nml").write_text(SWEEP.replace("study.h5", "sweep.h5"))
    sh(exe, "sweep.nml", cwd=tmp_path)
    (tmp_path / "out" / "study.h5").unlink()
    for part in (tmp_path / "out").glob("study.part-*"):
        part.unlink()
    for costs, words in (("out/other.h5", "another study"), ("out/sweep.h5", "not of this bifurcation study"),
                         ("study.nml", "--costs study.nml")):
        proc = sh(exe, "study.nml", "--slice", "1/3", "--costs", costs, cwd=tmp_path, check=False)
        lines = proc.stderr.strip().splitlines()
        assert proc.returncode == 2 and len(lines) == 1 and words in lines[0], proc.stderr
    proc = sh(exe, "study.nml", "--costs", "whole.h5", cwd=tmp_path, check=False)
    assert proc.returncode == 2 and "--costs applies with --slice" in proc.stderr, proc.stderr


def test_a_finished_slice_run_again_does_nothing(exe, tmp_path):
    (tmp_path / "study.nml").write_text(BIF)
    sh(exe, "study.nml", "--slice", "1/2", cwd=tmp_path)
    part = tmp_path / "out" / "study.part-1-of-2.h5"
    before = part.stat().st_mtime_ns
    proc = sh(exe, "study.nml", "--slice", "1/2", cwd=tmp_path)
    assert part.stat().st_mtime_ns == before, proc.stderr


@pytest.fixture()
def parts(exe, tmp_path):
    (tmp_path / "study.nml").write_text(BIF)
    for i in (1, 2, 3):
        sh(exe, "study.nml", "--slice", f"{i}/3", cwd=tmp_path)
    return tmp_path


def refused(exe, cwd, *args, words):
    proc = sh(exe, "merge", *args, cwd=cwd, check=False)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    for w in words:
        assert w in lines[0], lines[0]
    assert not (cwd / "out" / "study.h5").exists()


def test_merge_refuses_a_missing_slice(exe, parts):
    refused(exe, parts, "out/study.part-1-of-3.h5", "out/study.part-3-of-3.h5",
            words=["slice 2 of 3 is missing", "--slice 2/3"])


def test_check_tells_a_submission_script_the_output_and_memory(exe, tmp_path):
    """--check of one file prints what input/slurm/submit.sh needs, one `key value` a line."""
    (tmp_path / "study.nml").write_text(BIF)
    proc = sh(exe, "--check", "study.nml", cwd=tmp_path)
    report = dict(line.split(" ", 1) for line in proc.stdout.splitlines())
    assert report["output"] == "out/study.h5" and report["overwrite"] == "0" and report["scene"] == "bifurcation"
    assert 60 * 100 < int(report["memory_per_thread_bytes"]) < 10**8          # some 160 bytes a site of N = 60
    # the checkpoint's buffers (on by default) are part of it: twice the run's state
    assert int(report["checkpoint_bytes"]) > 0
    (tmp_path / "off.nml").write_text(BIF.replace("quiet = .true.", "quiet = .true., checkpoint_every = 0"))
    off = dict(line.split(" ", 1) for line in sh(exe, "--check", "off.nml", cwd=tmp_path).stdout.splitlines())
    assert off["checkpoint_bytes"] == "0"
    assert int(report["memory_per_thread_bytes"]) == int(off["memory_per_thread_bytes"]) + int(
        report["checkpoint_bytes"]) == 3 * int(off["memory_per_thread_bytes"])


def test_merge_slices_names_every_missing_part(exe, parts):
    (parts / "out" / "study.part-1-of-3.h5").unlink()
    (parts / "out" / "study.part-3-of-3.h5").unlink()
    proc = sh(exe, "merge", "--slices", "3", "study.nml", cwd=parts, check=False)
    assert proc.returncode == 2, proc.stderr
    line, = proc.stderr.strip().splitlines()
    assert "2 of 3 parts" in line and "slice(s) 1, 3 " in line and "--slice I/3" in line, line
    # --partial --slices N: a snapshot of what the parts there hold
    proc = sh(exe, "merge", "--partial", "--slices", "3", "study.nml", cwd=parts)
    with h5py.File(parts / "out" / "study.h5.partial.h5") as f:
        assert f.attrs["complete"] == 0
    assert not (parts / "out" / "study.h5").exists()


def test_merge_refuses_a_slice_given_twice(exe, parts):
    (parts / "copy.part-1-of-3.h5").write_bytes((parts / "out" / "study.part-1-of-3.h5").read_bytes())
    refused(exe, parts, "out/study.part-1-of-3.h5", "copy.part-1-of-3.h5", "out/study.part-2-of-3.h5",
            "out/study.part-3-of-3.h5", words=["given twice", "copy.part-1-of-3.h5"])


def test_merge_refuses_parts_of_another_input(exe, parts):
    (parts / "other.nml").write_text(BIF.replace("t_final = 40.0", "t_final = 30.0").replace("study", "other"))
    sh(exe, "other.nml", "--slice", "2/3", cwd=parts)
    refused(exe, parts, "out/study.part-1-of-3.h5", "out/other.part-2-of-3.h5", "out/study.part-3-of-3.h5",
            words=["out/other.part-2-of-3.h5", "another input"])


def test_merge_refuses_what_is_not_a_part(exe, parts):
    (parts / "junk.h5").write_text("not hdf5")
    refused(exe, parts, "junk.h5", words=["junk.h5", "not an HDF5 file"])


def test_merge_refuses_an_interrupted_slice(exe, parts):
    (parts / "out" / "study.part-2-of-3.h5").unlink()
    proc = subprocess.run([exe, "study.nml", "--slice", "2/3"], cwd=parts, capture_output=True, text=True,
                          env=dict(os.environ, SUPRATRANS_STOP_AFTER="1"))
    assert proc.returncode == 5, proc.stderr
    assert (parts / "out" / "study.part-2-of-3.h5.journal").exists()
    refused(exe, parts, "out/study.part-1-of-3.h5", "out/study.part-2-of-3.h5.partial.h5", "out/study.part-3-of-3.h5",
            words=["interrupted", "partial snapshot"])


def test_partial_merge_draws_what_is_there(exe, parts):
    sh(exe, "merge", "--partial", "out/study.part-1-of-3.h5", "out/study.part-3-of-3.h5", cwd=parts)
    with h5py.File(parts / "out" / "study.h5.partial.h5") as f:
        assert f.attrs["complete"] == 0
        status = f["status"][()].ravel()
    assert sorted(set(status.tolist()) & {-1}) == [-1]
    assert (status == -1).sum() == 3        # slice 2 of 3 holds tasks 2, 5, 8
    assert not (parts / "out" / "study.h5").exists()


TINY = """&chain n = 20, n0 = 15 /
&numerics t_final = 5.0 /
&scene kind = 'amplitude_sweep', amplitude_min = 1.0, amplitude_max = 1.7, amplitude_step = 0.1 /
&output file = 'out/study.h5', quiet = .true. /
"""


def stopped_journal(exe, tmp_path, text, after):
    """Run a scene that stops (as on SIGTERM) after `after` tasks; return the reference file and the journal."""
    (tmp_path / "study.nml").write_text(text)
    sh(exe, "study.nml", cwd=tmp_path)
    reference = tmp_path / "reference.h5"
    (tmp_path / "out" / "study.h5").rename(reference)
    proc = subprocess.run([exe, "study.nml"], cwd=tmp_path, capture_output=True, text=True,
                          env=dict(os.environ, SUPRATRANS_STOP_AFTER=str(after), OMP_NUM_THREADS="1"))
    assert proc.returncode == 5, proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1 and "resume" in proc.stderr, proc.stderr
    assert (tmp_path / "out" / "study.h5.partial.h5").exists()
    return reference, tmp_path / "out" / "study.h5.journal"


def torn_offsets(full: bytes, start: int, sampled: int = 24, seed: int = 40) -> list[int]:
    """Where to cut a journal inside its lines after byte `start`: the boundaries of each line (its first bytes, the
    CRC-32 at its end, the line whole but for its newline, the newline), the ends of its first and last three fields
    (a line one or more fields short), plus `sampled` offsets drawn with a fixed seed from the rest, so that every run
    of the suite cuts at the same places."""
    cuts = set()
    line_start = start
    while line_start < len(full):
        end = full.index(b"\n", line_start)           # the newline of this line
        fields = [i for i in range(line_start + 1, end) if full[i] == 32 and full[i - 1] != 32]
        cuts |= {line_start, line_start + 1, line_start + 2, end - 9, end - 8, end - 1, end}
        cuts |= set(fields[:3] + fields[-3:])
        line_start = end + 1
    cuts = {c for c in cuts if start <= c < len(full)}
    rest = sorted(set(range(start, len(full))) - cuts)
    return sorted(cuts | set(random.Random(seed).sample(rest, min(sampled, len(rest)))))


@pytest.mark.slow
def test_journal_torn_inside_its_last_two_lines(exe, tmp_path):
    """A journal cut inside its last two lines (as a kill leaves it) resumes to the same file: cut at the boundaries
    of its lines and fields and at 24 offsets sampled with a fixed seed (about 50 of 1100 offsets: cutting at every
    one took 1100 runs of the program)."""
    reference, journal = stopped_journal(exe, tmp_path, TINY, 6)
    full = journal.read_bytes()
    lines = full.splitlines(keepends=True)
    assert len(lines) == 7
    start = len(b"".join(lines[:-2]))
    assert len(full) - start > 500
    cuts = torn_offsets(full, start)
    assert cuts[0] == start and cuts[-1] == len(full) - 1 and len(full) - 2 in cuts
    for cut in cuts:
        journal.write_bytes(full[:cut])
        sh(exe, "study.nml", cwd=tmp_path)
        identical(reference, tmp_path / "out" / "study.h5")
        (tmp_path / "out" / "study.h5").unlink()


def test_altered_journal_line_is_recomputed(exe, tmp_path):
    reference, journal = stopped_journal(exe, tmp_path, TINY, 4)
    lines = journal.read_text().splitlines(keepends=True)
    fields = lines[2].split(" ")
    fields[1] = "1.00000000000000000E+100"
    lines[2] = " ".join(fields)
    journal.write_text("".join(lines))
    proc = subprocess.run([exe, "study.nml"], cwd=tmp_path, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    identical(reference, tmp_path / "out" / "study.h5")


#: BIF unscreened at T = 200: about 0.3 s of CPU a search (3 s for its 10), so that a signal sent once it has
#: journaled its first finds nine still ahead (screened, the whole study takes 0.6 s).
BIF_LONG = BIF.replace("t_final = 40.0", "t_final = 200.0").replace("resolution = 0.1,",
                                                                        "resolution = 0.1, screen_method = 'none',")


def wait_for_journal(proc, journal, lines, timeout=120):
    """Wait (polling every 0.01 s, at most `timeout` s) until `journal` has `lines` lines; fails when `proc` ends
    first."""
    deadline = time.monotonic() + timeout
    while not journal.exists() or journal.read_text().count("\n") < lines:
        assert proc.poll() is None, f"the run ended before its journal had {lines} lines: {proc.stderr.read()}"
        assert time.monotonic() < deadline, f"{journal}: not {lines} lines in {timeout} s"
        time.sleep(0.01)


@pytest.mark.slow
def test_sigterm_stops_cleanly_and_the_same_command_resumes(exe, tmp_path):
    (tmp_path / "study.nml").write_text(BIF_LONG)
    assert "screen_method = 'none'" in BIF_LONG
    proc = subprocess.Popen([exe, "study.nml"], cwd=tmp_path, stderr=subprocess.PIPE, text=True,
                            env=dict(os.environ, OMP_NUM_THREADS="1"))
    journal = tmp_path / "out" / "study.h5.journal"
    wait_for_journal(proc, journal, 2)          # its header and one search
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 5, err
    done = journal.read_text().count("\n") - 1
    assert 1 <= done < 10
    sh(exe, "study.nml", cwd=tmp_path)
    assert (tmp_path / "out" / "study.h5").exists() and not journal.exists()


def test_empty_journal_is_no_journal(exe, tmp_path):
    (tmp_path / "study.nml").write_text(SWEEP)
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "study.h5.journal").write_text("")
    sh(exe, "study.nml", cwd=tmp_path)
    assert (tmp_path / "out" / "study.h5").exists()


def test_second_instance_on_one_output_is_refused(exe, tmp_path):
    # the first instance: a study of hours (T = 10^5 unscreened) that holds the lock until the test stops it
    (tmp_path / "first.nml").write_text(BIF_LONG.replace("t_final = 200.0", "t_final = 100000.0"))
    (tmp_path / "study.nml").write_text(BIF)
    first = subprocess.Popen([exe, "first.nml"], cwd=tmp_path, stderr=subprocess.PIPE, text=True)
    try:
        wait_for_journal(first, tmp_path / "out" / "study.h5.journal", 1)     # it holds the lock and has begun
        second = sh(exe, "study.nml", cwd=tmp_path, check=False)
    finally:
        first.send_signal(signal.SIGTERM)
        _, err = first.communicate(timeout=120)
    assert first.returncode == 5, err
    assert second.returncode == 4, second.stderr
    lines = second.stderr.strip().splitlines()
    assert len(lines) == 1 and "another supratrans" in lines[0], second.stderr
    lock = tmp_path / "out" / "study.h5.lock"
    # the first has ended: the lock is free (its journal and snapshot, of another input, removed)
    for left in (tmp_path / "out").glob("study.h5.*"):
        if left != lock:
            left.unlink()
    third = sh(exe, "study.nml", cwd=tmp_path, check=False)
    assert third.returncode == 0, third.stderr
    assert not lock.exists()          # removed by the instance that held it, as it ended (see test_trust.py)


def test_a_lock_held_by_another_process_is_never_removed(exe, tmp_path):
    """A lock file that another process holds (flock) refuses the run and stays, the same file; an empty lock file
    left by an older version (not held) is taken and removed at the end; every run leaves no lock file."""
    (tmp_path / "study.nml").write_text(SWEEP)
    (tmp_path / "out").mkdir()
    lock = tmp_path / "out" / "study.h5.lock"
    fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        held = sh(exe, "study.nml", cwd=tmp_path, check=False)
        assert held.returncode == 4 and "another supratrans" in held.stderr, held.stderr
        assert lock.exists() and os.stat(lock).st_ino == os.fstat(fd).st_ino
    finally:
        os.close(fd)
    assert lock.exists()                                 # released, not held: left as an older version leaves it
    done = sh(exe, "study.nml", cwd=tmp_path, check=False)
    assert done.returncode == 0, done.stderr
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["study.h5"]


@pytest.fixture()
def small_disk(tmp_path):
    """A 64 KiB tmpfs (root only), unmounted afterwards."""
    mount = tmp_path / "disk"
    mount.mkdir()
    if os.geteuid() != 0 or subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(mount)],
                                           capture_output=True).returncode != 0:
        pytest.skip("cannot mount a small tmpfs here (needs root)")
    yield mount
    subprocess.run(["umount", "-l", str(mount)], capture_output=True)


@pytest.mark.slow
def test_full_disk_is_one_line_and_the_journal_resumes(exe, tmp_path, small_disk):
    text = """&chain n = 40, n0 = 30 /
&numerics t_final = 10.0 /
&scene kind = 'amplitude_sweep', amplitude_min = 1.0, amplitude_max = 3.0, amplitude_step = 0.01,
  vary = 'gamma', values = 0.0, 0.01, 0.02 /
&output file = 'disk/s.h5', quiet = .true. /
"""
    (tmp_path / "study.nml").write_text(text)
    proc = subprocess.run([exe, "study.nml"], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 4, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "disk full" in lines[0], proc.stderr
    assert sorted(p.name for p in small_disk.iterdir()) == ["s.h5.journal"]   # no temporary, no lock left
    kept = small_disk.joinpath("s.h5.journal").read_text().count("\n") - 1
    assert kept > 50
    subprocess.run(["mount", "-o", "remount,size=10m", str(small_disk)], check=True)
    proc = subprocess.run([exe, "study.nml"], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    (tmp_path / "ref.nml").write_text(text.replace("disk/s.h5", "ref.h5"))
    subprocess.run([exe, "ref.nml"], cwd=tmp_path, check=True, capture_output=True, timeout=300)
    identical(tmp_path / "ref.h5", small_disk / "s.h5")


def test_unwritable_output_directory_is_refused_before_any_work(exe, tmp_path):
    """A read-only file system (root ignores permission bits): one line, exit 4, before anything runs."""
    mount = tmp_path / "ro"
    mount.mkdir()
    if os.geteuid() != 0 or subprocess.run(["mount", "-t", "tmpfs", "-o", "ro,size=64k", "tmpfs", str(mount)],
                                           capture_output=True).returncode != 0:
        pytest.skip("cannot mount a read-only tmpfs here (needs root)")
    try:
        # a study of hours (T = 10^5 unscreened): had it run before looking at the directory, it would not end
        # within the bound of 60 s
        text = BIF_LONG.replace("t_final = 200.0", "t_final = 100000.0").replace("out/study.h5", "ro/study.h5")
        (tmp_path / "study.nml").write_text(text)
        proc = subprocess.run([exe, "study.nml"], cwd=tmp_path, capture_output=True, text=True, timeout=60)
        assert proc.returncode == 4, proc.stderr
        lines = proc.stderr.strip().splitlines()
        assert len(lines) == 1 and "cannot write in its directory" in lines[0], proc.stderr
    finally:
        subprocess.run(["umount", "-l", str(mount)], capture_output=True)
