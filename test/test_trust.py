"""Trust on a shared machine (issue 22, files and links): no file the program did not create is ever written, a link
planted under a predictable name is never followed, the output's lock is taken before anything of the output is
touched and is never deleted, a file system without locks is named as such, and names that cannot work are refused
before the work. Every symbolic-link test plants the link and checks that its target is byte-for-byte unchanged."""
import fcntl
import os
import shutil
import signal
import stat
import subprocess
import time
from pathlib import Path

import pytest

TS = """&chain n = 40, n0 = 30 /
&record probes = 5 /
&numerics t_final = 2.0 /
&output file = '{out}', quiet = .true.{extra} /
"""
SWEEP = """&chain n = 40, n0 = 30 /
&numerics t_final = 10.0 /
&scene kind = 'amplitude_sweep', amplitude_min = 1.0, amplitude_max = 1.6, amplitude_step = 0.2 /
&output file = '{out}', quiet = .true.{extra} /
"""
LONG = """&chain n = 60, n0 = 45 /
&numerics t_final = 200.0 /
&scene kind = 'bifurcation', amplitude_min = 0.5, amplitude_max = 6.0, omega_min = 0.5, omega_max = 0.9,
  omega_step = 0.1, coarse_step = 0.5, resolution = 0.1, potentials = 'sine-gordon', 'klein-gordon' /
&output file = 'out/s.h5', quiet = .true. /
"""
VICTIM = b"\\documentclass{article} thesis of another user\n\x00\x01binary tail\xff"


def run(exe, *args, cwd, env=None, timeout=300):
    full = dict(os.environ, **(env or {}))
    return subprocess.run([exe, *map(str, args)], cwd=cwd, capture_output=True, text=True, timeout=timeout, env=full)


def one_line(proc, status, *words):
    """The run ended with `status` and one line on stderr holding every word."""
    assert proc.returncode == status, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    for word in words:
        assert word in lines[0], lines[0]
    return lines[0]


@pytest.fixture
def victim(tmp_path):
    """Another user's file, outside the output directory."""
    path = tmp_path / "home" / "thesis.tex"
    path.parent.mkdir()
    path.write_bytes(VICTIM)
    return path


def nml(tmp_path, template=TS, out="out/s.h5", extra="", name="s.nml"):
    (tmp_path / "out").mkdir(exist_ok=True)
    path = tmp_path / name
    path.write_text(template.format(out=out, extra=extra))
    return path


def is_hdf5(path):
    return path.is_file() and not path.is_symlink() and path.read_bytes()[:8] == b"\x89HDF\r\n\x1a\n"


# --------------------------------------------------------------------------------------- 1. temporary names

# (planted name in out/, namelist, command): every temporary name the program used to open by name
PLANTED = {
    "timeseries output .tmp": ("s.h5.tmp", TS, []),
    "scene output .tmp": ("s.h5.tmp", SWEEP, []),
    "journal .new": ("s.h5.journal.new", SWEEP, []),
    "part .tmp": ("s.part-1-of-2.h5.tmp", SWEEP, ["--slice", "1/2"]),
    "part journal .new": ("s.part-1-of-2.h5.journal.new", SWEEP, ["--slice", "1/2"]),
}


@pytest.mark.parametrize("case", sorted(PLANTED))
def test_link_planted_at_a_temporary_name_is_never_followed(exe, tmp_path, victim, case):
    planted, template, args = PLANTED[case]
    nml(tmp_path, template)
    link = tmp_path / "out" / planted
    link.symlink_to(victim)
    proc = run(exe, "s.nml", *args, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert victim.read_bytes() == VICTIM
    assert link.is_symlink()
    final = tmp_path / "out" / ("s.part-1-of-2.h5" if args else "s.h5")
    assert is_hdf5(final)


def test_link_planted_at_the_snapshot_temporary_is_never_followed(exe, tmp_path, victim):
    """A scene stopped by a signal writes its partial snapshot: not through a link at `<out>.partial.h5.tmp`."""
    nml(tmp_path, SWEEP)
    link = tmp_path / "out" / "s.h5.partial.h5.tmp"
    link.symlink_to(victim)
    proc = run(exe, "s.nml", cwd=tmp_path, env={"SUPRATRANS_STOP_AFTER": "2", "OMP_NUM_THREADS": "1"})
    assert proc.returncode == 5, proc.stderr
    assert victim.read_bytes() == VICTIM
    assert is_hdf5(tmp_path / "out" / "s.h5.partial.h5")
    assert run(exe, "s.nml", cwd=tmp_path).returncode == 0
    assert victim.read_bytes() == VICTIM and link.is_symlink()


def test_dangling_link_at_the_lock_creates_nothing(exe, tmp_path):
    """The lock file is opened without following a link: a dangling link there creates no file anywhere."""
    nml(tmp_path)
    target = tmp_path / "home" / "created_by_supratrans"
    target.parent.mkdir()
    (tmp_path / "out" / "s.h5.lock").symlink_to(target)
    proc = run(exe, "s.nml", cwd=tmp_path)
    one_line(proc, 4, "s.h5.lock", "symbolic link")
    assert not target.exists()
    assert not (tmp_path / "out" / "s.h5").exists()


@pytest.mark.parametrize("overwrite", [False, True])
def test_output_that_is_a_link_is_refused_and_neither_it_nor_its_target_changes(exe, tmp_path, victim, overwrite):
    """Documented choice: a symbolic link at the output path is refused (never written through, never replaced)."""
    nml(tmp_path, extra=", overwrite = .true." if overwrite else "")
    link = tmp_path / "out" / "s.h5"
    link.symlink_to(victim)
    proc = run(exe, "s.nml", cwd=tmp_path)
    one_line(proc, 2, "s.nml", "s.h5")
    assert link.is_symlink() and os.readlink(link) == str(victim)
    assert victim.read_bytes() == VICTIM
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["s.h5"]


@pytest.mark.parametrize("overwrite", [False, True])
def test_fifo_at_the_output_is_never_replaced(exe, tmp_path, overwrite):
    nml(tmp_path, extra=", overwrite = .true." if overwrite else "")
    fifo = tmp_path / "out" / "s.h5"
    os.mkfifo(fifo)
    proc = run(exe, "s.nml", cwd=tmp_path, timeout=60)
    one_line(proc, 2, "s.h5")
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)


def make_parts(exe, tmp_path, n=2):
    nml(tmp_path, SWEEP, out="parts/p.h5", name="p.nml")
    for i in range(1, n + 1):
        proc = run(exe, "p.nml", "--slice", f"{i}/{n}", cwd=tmp_path)
        assert proc.returncode == 0, proc.stderr
    return sorted((tmp_path / "parts").glob("p.part-*.h5"))


def test_fifo_at_the_partial_snapshot_is_never_replaced(exe, tmp_path):
    parts = make_parts(exe, tmp_path)
    fifo = tmp_path / "parts" / "p.h5.partial.h5"
    os.mkfifo(fifo)
    proc = run(exe, "merge", "--partial", parts[0], cwd=tmp_path, timeout=60)
    assert proc.returncode != 0, proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1, proc.stderr
    assert "p.h5.partial.h5" in proc.stderr
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    assert not (tmp_path / "parts" / "p.h5.journal").exists()


def test_temporaries_of_a_killed_run_are_cleaned_under_the_lock(exe, tmp_path, victim):
    """What a SIGKILL leaves (`<out>.tmp-XXXXXX`, the journal's and snapshot's) is deleted by the next run, with a
    line; a link or a file that does not match is left alone."""
    nml(tmp_path, SWEEP)
    (tmp_path / "s.nml").write_text((tmp_path / "s.nml").read_text().replace(", quiet = .true.", ""))
    out = tmp_path / "out"
    left = ["s.h5.tmp-Ab3dE9", "s.h5.journal.tmp-zz9ZZ0", "s.h5.partial.h5.tmp-000000"]
    for name in left:
        (out / name).write_bytes(b"half-written")
    (out / "s.h5.tmp-LINK00").symlink_to(victim)
    (out / "s.h5.tmp-toolong1").write_bytes(b"not a temporary of ours")
    proc = run(exe, "s.nml", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert "deleted 3 temporary file(s)" in proc.stderr, proc.stderr
    assert sorted(p.name for p in out.iterdir()) == ["s.h5", "s.h5.tmp-LINK00", "s.h5.tmp-toolong1"]
    assert victim.read_bytes() == VICTIM


# --------------------------------------------------------------------------------------- 2. the lock


def test_lock_file_is_removed_by_its_holder_and_an_orphan_is_no_lock(exe, tmp_path):
    """The instance that holds the lock removes its file as it ends, while still holding it. A second instance that
    had opened the file meanwhile and locks it afterwards holds the lock of a file that no longer has the name: it
    counts only if the name still refers to the file locked (supratrans_lock checks the inode after flock), so a
    third instance is not refused by it and takes a new file, which it removes in turn."""
    nml(tmp_path, LONG)
    first = subprocess.Popen([exe, "s.nml"], cwd=tmp_path, stderr=subprocess.PIPE, text=True)
    lock = tmp_path / "out" / "s.h5.lock"
    deadline = time.time() + 60
    while not lock.exists() and time.time() < deadline:
        time.sleep(0.01)
    assert lock.exists()
    second = os.open(lock, os.O_RDWR)            # the second instance has opened the lock file ...
    try:
        first.send_signal(signal.SIGTERM)
        first.communicate(timeout=120)
        assert first.returncode == 5
        assert not lock.exists()                 # removed by its holder as it ended
        fcntl.flock(second, fcntl.LOCK_EX | fcntl.LOCK_NB)     # ... and locks the old file once the first has ended
        third = run(exe, "s.nml", cwd=tmp_path)  # not refused: that file is no longer the lock
        assert third.returncode == 0, third.stderr
    finally:
        os.close(second)
    assert (tmp_path / "out" / "s.h5").exists() and not lock.exists()


@pytest.mark.parametrize("command", ["scene", "merge", "merge --partial", "slice"])
def test_every_writing_command_takes_the_lock_before_touching_the_output(exe, tmp_path, command):
    """While another instance holds the output's lock, no command writes anything there: the running scene's
    journal stays as it is (merge used to replace it before looking at the lock)."""
    parts = make_parts(exe, tmp_path)
    nml(tmp_path, SWEEP, out="out/s.h5")
    if command == "slice":
        out = tmp_path / "out" / "s.part-1-of-2.h5"
        args = ["s.nml", "--slice", "1/2"]
    else:
        out = tmp_path / "out" / "s.h5"
        args = {"scene": ["s.nml"], "merge": ["merge", "-o", out, *parts],
                "merge --partial": ["merge", "--partial", "-o", out, parts[0]]}[command]
    journal = Path(str(out) + ".journal")
    journal.write_text("journal of the running instance\n")
    before = {p.name: p.read_bytes() for p in out.parent.iterdir()}
    fd = os.open(str(out) + ".lock", os.O_RDWR | os.O_CREAT, 0o644)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        proc = run(exe, *args, cwd=tmp_path)
    finally:
        os.close(fd)
    one_line(proc, 4, "another supratrans")
    after = {p.name: p.read_bytes() for p in out.parent.iterdir()}
    before.setdefault(out.name + ".lock", b"")
    assert after == before


def test_concurrent_partial_merges_never_end_in_an_empty_snapshot(exe, tmp_path):
    """Two `merge --partial` of the same parts at once: each either writes the whole snapshot or is refused."""
    h5py = pytest.importorskip("h5py")
    parts = make_parts(exe, tmp_path)
    for _ in range(5):
        procs = [subprocess.Popen([exe, "merge", "--partial", *map(str, parts)], cwd=tmp_path,
                                  stderr=subprocess.PIPE, text=True) for _ in range(2)]
        results = [(p.wait(timeout=120), p.stderr.read()) for p in procs]
        assert any(status == 0 for status, _ in results), results
        for status, err in results:
            assert status == 0 or (status == 4 and "another supratrans" in err), err
        with h5py.File(tmp_path / "parts" / "p.h5.partial.h5") as f:
            assert f.attrs["runs_done"] == f.attrs["runs_total"] == 4
        assert not (tmp_path / "parts" / "p.h5.journal").exists()


# --------------------------------------------------------------------------------------- 3. no locks


@pytest.fixture(scope="module")
def no_flock(tmp_path_factory):
    """An LD_PRELOAD library whose flock(2) fails with ENOLCK, as on NFS without a lock manager."""
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        pytest.skip("no C compiler to build the ENOLCK shim")
    where = tmp_path_factory.mktemp("shim")
    (where / "noflock.c").write_text("#include <errno.h>\nint flock(int fd, int op) { (void)fd; (void)op; "
                                     "errno = ENOLCK; return -1; }\n")
    subprocess.run([cc, "-shared", "-fPIC", "-o", str(where / "noflock.so"), str(where / "noflock.c")], check=True)
    return str(where / "noflock.so")


def test_file_system_without_locks_is_named_with_what_to_do(exe, tmp_path, no_flock):
    nml(tmp_path)
    proc = run(exe, "s.nml", cwd=tmp_path, env={"LD_PRELOAD": no_flock})
    line = one_line(proc, 4, "s.h5", "refuses locks", "No locks available", "SUPRATRANS_NO_LOCK=1")
    assert "another supratrans" not in line
    assert not (tmp_path / "out" / "s.h5").exists()
    proc = run(exe, "s.nml", cwd=tmp_path, env={"LD_PRELOAD": no_flock, "SUPRATRANS_NO_LOCK": "1"})
    assert proc.returncode == 0, proc.stderr
    assert is_hdf5(tmp_path / "out" / "s.h5")


# --------------------------------------------------------------------------------------- names


@pytest.mark.parametrize("name", ["OUT/", "out/.", "out/.."])
def test_output_name_that_names_a_directory_is_refused(exe, tmp_path, name):
    nml(tmp_path, out=name)
    proc = run(exe, "s.nml", cwd=tmp_path)
    one_line(proc, 2, "s.nml", "directory")
    assert not (tmp_path / "OUT").exists()
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == []
    assert run(exe, "--check", "s.nml", cwd=tmp_path).returncode == 2


def test_nul_in_the_output_name_is_refused(exe, tmp_path):
    (tmp_path / "out").mkdir()
    (tmp_path / "s.nml").write_bytes(TS.format(out="out/a\x00b.h5", extra="").encode())
    proc = run(exe, "s.nml", cwd=tmp_path)
    one_line(proc, 2, "s.nml", "NUL")
    assert list((tmp_path / "out").iterdir()) == []


@pytest.mark.parametrize("length", [231, 233, 234, 247, 250, 253, 255])
def test_long_names_are_refused_before_the_work_or_written_whole(exe, tmp_path, length):
    """A name whose journal or temporary names would not fit NAME_MAX is refused before the work (today's names of
    247-253 characters passed the check and failed at the write); a shorter one is written."""
    name = "r" * (length - 3) + ".h5"
    nml(tmp_path, SWEEP, out="out/" + name)
    check = run(exe, "--check", "s.nml", cwd=tmp_path)
    proc = run(exe, "s.nml", cwd=tmp_path)
    if length <= 233:
        assert check.returncode == 0 and proc.returncode == 0, proc.stderr
        assert is_hdf5(tmp_path / "out" / name)
    else:
        one_line(check, 2, "name too long")
        one_line(proc, 2, "s.nml", "name too long", "233")
        assert list((tmp_path / "out").iterdir()) == []


@pytest.mark.parametrize("text", ["3/3/3", "1/2/", "1//2"])
def test_slice_with_more_than_one_slash_is_refused(exe, tmp_path, text):
    nml(tmp_path, SWEEP)
    proc = run(exe, "s.nml", "--slice", text, cwd=tmp_path)
    one_line(proc, 2, "--slice")
    assert list((tmp_path / "out").iterdir()) == []


def test_control_characters_are_never_printed(exe, tmp_path):
    """ESC and other control bytes of the namelist (and of its file name) reach no line the program prints."""
    name = "s\x1b[2J\x07.nml"
    out = "out/o\x1b]0;owned\x07\x1b[31m.h5"
    (tmp_path / "out").mkdir()
    (tmp_path / name).write_text(SWEEP.format(out=out, extra="").replace(", quiet = .true.", ""))
    for args in ([name], [name], ["--check", name, name], [name, "--slice", "1/2"]):
        proc = subprocess.run([exe, *args], cwd=tmp_path, capture_output=True, timeout=300)
        printed = proc.stdout + proc.stderr
        assert printed.strip(), args
        assert not any(b < 32 and b != 10 or b == 127 for b in printed), (args, printed)


# --------------------------------------------------------------------------------------- 10. stale journal


@pytest.mark.parametrize("slices", [False, True], ids=["scene", "slice"])
def test_finished_output_with_a_stale_journal_is_recognised_and_cleaned(exe, tmp_path, slices):
    """A kill after the output was renamed into place and before the journal was deleted leaves journal + lock: the
    rerun recognises the finished output of this input, deletes the stale journal with a line and exits 0."""
    path = nml(tmp_path, SWEEP)
    path.write_text(path.read_text().replace(", quiet = .true.", ""))
    args = ["s.nml", "--slice", "1/2"] if slices else ["s.nml"]
    out = tmp_path / "out" / ("s.part-1-of-2.h5" if slices else "s.h5")
    journal = Path(str(out) + ".journal")
    stopped = run(exe, *args, cwd=tmp_path, env={"SUPRATRANS_STOP_AFTER": "1", "OMP_NUM_THREADS": "1"})
    assert stopped.returncode == 5, stopped.stderr
    stale = journal.read_bytes()
    assert run(exe, *args, cwd=tmp_path).returncode == 0
    finished = out.read_bytes()
    journal.write_bytes(stale)                          # as a kill between the rename and the unlink leaves it
    proc = run(exe, *args, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert "complete already" in proc.stderr and "stale" in proc.stderr and journal.name in proc.stderr, proc.stderr
    assert not journal.exists()
    assert out.read_bytes() == finished
    assert run(exe, *args, cwd=tmp_path).returncode == (0 if slices else 2)    # no journal: as before


def test_stale_journal_beside_the_output_of_another_input_is_kept(exe, tmp_path):
    path = nml(tmp_path, SWEEP)
    journal = tmp_path / "out" / "s.h5.journal"
    assert run(exe, "s.nml", cwd=tmp_path, env={"SUPRATRANS_STOP_AFTER": "1", "OMP_NUM_THREADS": "1"}).returncode == 5
    stale = journal.read_bytes()
    assert run(exe, "s.nml", cwd=tmp_path).returncode == 0
    journal.write_bytes(stale)
    path.write_text(path.read_text() + "! another input\n")
    proc = run(exe, "s.nml", cwd=tmp_path)
    one_line(proc, 2, "exists")
    assert journal.read_bytes() == stale
