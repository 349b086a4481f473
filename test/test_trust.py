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


# --------------------------------------------------------------------------------------- issue 43: another user's files

OTHER = ["setpriv", "--reuid=nobody", "--regid=nogroup", "--clear-groups"]


@pytest.fixture
def shared():
    """A folder every user may write, without the sticky bit (0777), as a project's shared folder often is; files
    are planted there as another user (`nobody`, through setpriv)."""
    if os.geteuid() != 0 or shutil.which("setpriv") is None:
        pytest.skip("needs root and setpriv to act as another user")
    import tempfile
    where = Path(tempfile.mkdtemp(prefix="supratrans-shared-", dir="/tmp"))
    os.chmod(where, 0o777)
    (where / "out").mkdir()
    os.chmod(where / "out", 0o777)
    yield where
    shutil.rmtree(where, ignore_errors=True)


def plant_as_other(path, data):
    """Write `data` at `path` as the user nobody."""
    subprocess.run([*OTHER, "sh", "-c", 'cat > "$1"', "sh", str(path)], input=data, check=True)
    assert path.stat().st_uid != os.geteuid()


@pytest.mark.parametrize("name, template", [("s.h5.partial.h5", SWEEP), ("s.h5.checkpoint-3", SWEEP),
                                            ("s.h5.journal", SWEEP), ("s.h5.checkpoint", TS)])
def test_another_users_files_in_a_shared_folder_are_neither_deleted_nor_used(exe, shared, name, template):
    """Issue 43, failure 1: a run removed another user's `OUT.partial.h5` and `OUT.checkpoint-<t>` and exited 0.
    Now it refuses in one line (status 4), and the file is left as it was; `--check` says the same."""
    (shared / "s.nml").write_text(template.format(out="out/s.h5", extra=""))
    planted = shared / "out" / name
    plant_as_other(planted, b"another user's file\n")
    before = planted.stat()
    for args in (["s.nml"], ["--check", "s.nml"]):
        proc = run(exe, *args, cwd=shared)
        one_line(proc, 4, name, "another user")
        after = planted.stat()
        assert (after.st_ino, after.st_uid, after.st_mtime_ns) == (before.st_ino, before.st_uid, before.st_mtime_ns)
        assert planted.read_bytes() == b"another user's file\n"
        assert not (shared / "out" / "s.h5").exists()


def forge(journal_text, value):
    """The journal with the first value of its first record replaced by `value`, every checksum recomputed (as
    supratrans computes them: zlib's CRC-32, records bound to the header line)."""
    import zlib
    lines = journal_text.splitlines()
    header = lines[0]
    words = lines[1].rsplit(" *", 1)[0].split()
    words[1] = f"{value:.17e}"
    body = " ".join(words)
    crc = zlib.crc32(body.encode(), zlib.crc32((header + "\n").encode()))
    return "\n".join([header, f"{body} *{crc:08X}", *lines[2:]]) + "\n"


@pytest.fixture
def forged_journal(exe, tmp_path):
    """A journal of a stopped sweep with a value changed and its checksum recomputed: a forgery no checksum finds."""
    path = nml(tmp_path, SWEEP)
    stopped = run(exe, "s.nml", cwd=tmp_path, env={"SUPRATRANS_STOP_AFTER": "2", "OMP_NUM_THREADS": "1"})
    assert stopped.returncode == 5, stopped.stderr
    journal = tmp_path / "out" / "s.h5.journal"
    assert stat.S_IMODE(journal.stat().st_mode) & 0o022 == 0       # supratrans writes its files rw-r--r--
    journal.write_text(forge(journal.read_text(), 1000.0))
    return path, journal


def test_journal_forged_by_another_user_is_not_resumed_from(exe, forged_journal):
    """Issue 43, failure 2: another user's journal with a value changed and its checksum recomputed was resumed from
    (exit 0, the forged value in the output) and then deleted. Now: one line, status 4, the journal untouched."""
    if os.geteuid() != 0:
        pytest.skip("needs root to give the journal to another user")
    path, journal = forged_journal
    os.chown(journal, 65534, 65534)
    text = journal.read_bytes()
    proc = run(exe, path.name, cwd=path.parent)
    one_line(proc, 4, "s.h5.journal", "another user")
    assert journal.read_bytes() == text and journal.stat().st_uid == 65534
    assert not (path.parent / "out" / "s.h5").exists()


def test_journal_others_could_write_is_not_resumed_from(exe, forged_journal):
    """The same forgery in the user's own journal left writable by others (mode 0666): refused, kept."""
    path, journal = forged_journal
    os.chmod(journal, 0o666)
    text = journal.read_bytes()
    proc = run(exe, path.name, cwd=path.parent)
    one_line(proc, 4, "s.h5.journal", "writable by group or others", "0666")
    assert journal.read_bytes() == text
    os.chmod(journal, 0o644)                   # the owner vouches for it: resumed, as any journal of the user's own
    assert run(exe, path.name, cwd=path.parent).returncode == 0


def test_part_of_another_user_is_not_taken_for_a_finished_slice(exe, shared):
    """A part file found under a slice's name is "complete already" only if it is the user's own."""
    (shared / "p.nml").write_text(SWEEP.format(out="out/p.h5", extra=""))
    assert run(exe, "p.nml", "--slice", "1/2", cwd=shared).returncode == 0
    part = shared / "out" / "p.part-1-of-2.h5"
    data = part.read_bytes()
    part.unlink()
    plant_as_other(part, data)
    proc = run(exe, "p.nml", "--slice", "1/2", cwd=shared)
    one_line(proc, 4, "p.part-1-of-2.h5", "another user")
    assert part.read_bytes() == data and part.stat().st_uid != os.geteuid()


# --------------------------------------------------------------------------------------- issue 43: a scheduler's limits

LIMITS = {"ulimit -v 250 MiB": "ulimit -v 256000", "ulimit -d 20 MiB": "ulimit -d 20480", "ulimit -s 64 KiB": "ulimit -s 64"}


DENSE = {"stability": """&chain n = 40, n0 = 30 /
&numerics t_final = 10.0 /
&scene kind = 'stability', methods = 'rk4', c_values = 4.0, dts = 0.1 /
&output file = 'out/s.h5', quiet = .true. /
""", "continuation": """&chain n = 40, n0 = 30 /
&numerics method = 'newton', dt = 0.05 /
&scene kind = 'continuation', omega_min = 0.9, omega_max = 0.9, omega_step = 0.1, amplitude_max = 3.0 /
&output file = 'out/s.h5', quiet = .true. /
"""}


@pytest.mark.parametrize("limit", sorted(LIMITS))
@pytest.mark.parametrize("what", ["--version", "timeseries", "sweep", "stability", "continuation"])
def test_limits_of_a_scheduler_end_in_a_result_or_one_line(exe, tmp_path, limit, what):
    """Issue 43, failure 3: under `ulimit -v` of 150-300 MiB or `ulimit -d 20000` even `--version` spun forever
    (OpenBLAS's start-up retrying a 128 MiB mmap before main), and under `ulimit -s 64` a run ended in SIGSEGV (139)
    with a journal left. Each now runs (status 0) or ends at once with one line and status 2; never a hang, never a
    signal. Two threads asked, as on a node of several processors."""
    if what == "--version":
        args = ["--version"]
    elif what in DENSE:                       # dense LAPACK: OpenBLAS maps a working buffer in the run (it hung)
        (tmp_path / "out").mkdir()
        (tmp_path / "s.nml").write_text(DENSE[what])
        args = ["s.nml"]
    else:
        nml(tmp_path, TS if what == "timeseries" else SWEEP)
        args = ["s.nml"]
    command = LIMITS[limit] + ' && exec "$@"'
    proc = subprocess.run(["bash", "-c", command, "bash", exe, *args], cwd=tmp_path, capture_output=True, text=True,
                          timeout=120, env=dict(os.environ, OMP_NUM_THREADS="2"))
    errors = [line for line in proc.stderr.splitlines() if line.startswith("error")]
    if proc.returncode == 0:
        assert not errors, proc.stderr
        if what != "--version":
            assert is_hdf5(tmp_path / "out" / "s.h5")
            assert not (tmp_path / "out" / "s.h5.journal").exists()
    else:
        one_line(proc, 2, limit.split(" ")[0] + " " + limit.split(" ")[1])
        assert not (tmp_path / "out" / "s.h5.journal").exists()


# --------------------------------------------------------------------------------------- issue 43: --slice, merge


@pytest.mark.parametrize("args", [["--slice", "1/3", "--slice", "2/3"], ["--slice", "2/3", "--slice", "2/3"],
                                  ["--slice", "08/09"], ["--slice", "1/08"], ["--slice", "0/3"], ["--slice", "00001/2"]])
def test_slice_given_twice_or_with_leading_zeros_is_refused(exe, tmp_path, args):
    """Issue 43, failure 6: `--slice 1/3 --slice 2/3` silently took the last, `--slice 08/09` was accepted."""
    nml(tmp_path, SWEEP)
    proc = run(exe, "s.nml", *args, cwd=tmp_path)
    one_line(proc, 2, "--slice")
    assert list((tmp_path / "out").iterdir()) == []


def test_merge_catches_stop_signals_before_the_libraries_start(exe, tmp_path):
    """Issue 43, failure 6: SIGTERM to `merge` in its first 50 ms ended it with 143: the handler came after the
    libraries' start-up (OpenBLAS maps its buffers in a constructor) and the parsing. Seen without racing a signal:
    the system calls in order, the handler's rt_sigaction before any library constructor's mmap of a buffer and
    before any part file is opened."""
    if shutil.which("strace") is None:
        pytest.skip("strace not installed")
    parts = make_parts(exe, tmp_path)
    log = tmp_path / "strace.log"
    proc = subprocess.run(["strace", "-f", "-o", str(log), "-e", "trace=rt_sigaction,mmap,openat", exe, "merge",
                           *map(str, parts)], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    calls = log.read_text().splitlines()
    handler = next(k for k, c in enumerate(calls) if "rt_sigaction(SIGTERM, {sa_handler=0x" in c)
    buffers = [k for k, c in enumerate(calls) if "mmap(NULL, 134217728," in c]
    opened = [k for k, c in enumerate(calls) if "openat(" in c and ".part-" in c]
    assert opened and handler < opened[0]
    assert not buffers or handler < buffers[0], calls[:handler + 1]


# --------------------------------------------------------------------------------------- issue 43: work_precision

WORKPREC = """&chain n = {n}, n0 = {n0} /
&numerics t_final = 200.0 /
&scene kind = 'work_precision', methods = 'rk4', dts = {dts}, repeats = {repeats}, reference_dt = {reference_dt} /
&output file = 'out/s.h5' /
"""


@pytest.mark.parametrize("repeats, n, dts, status", [(2147483647, 100, "0.1", 2), (1000, 100000, "0.001, 0.0005", 2),
                                                    (1, 100000, "0.001, 0.0005", 0)])
def test_repeats_of_work_precision_are_bounded_and_counted_in_the_work_limit(exe, tmp_path, repeats, n, dts, status):
    """Issue 43, failure 4: `repeats = 2147483647` passed --check (the repeats were in no limit)."""
    (tmp_path / "s.nml").write_text(WORKPREC.format(n=n, n0=n - 10, dts=dts, repeats=repeats, reference_dt=0.1))
    proc = run(exe, "--check", "s.nml", cwd=tmp_path)
    assert proc.returncode == status, proc.stderr
    if status:
        one_line(proc, 2, "s.nml", "repeats")


@pytest.mark.parametrize("when", ["reference solutions", "timed runs"])
def test_work_precision_stops_at_sigterm_within_a_second(exe, tmp_path, when):
    """Issue 43, failure 4: work_precision ignored SIGTERM for minutes (its repeats and its reference runs never
    looked at the stop flag). The signal is sent once the scene says it has begun that stage (its progress line);
    a timed run of 1000 repeats and its references take far longer than the test waits."""
    (tmp_path / "out").mkdir()
    # references of 3 x 200/0.005 rk8 steps when they are signalled, of 3 x 200/0.1 when the timed runs are
    reference_dt = 0.005 if when == "reference solutions" else 0.1
    (tmp_path / "s.nml").write_text(WORKPREC.format(n=500, n0=490, dts="0.01", repeats=1000, reference_dt=reference_dt))
    proc = subprocess.Popen([exe, "s.nml"], cwd=tmp_path, stderr=subprocess.PIPE, text=True)
    try:
        seen = []
        for line in proc.stderr:
            seen.append(line)
            if when in line:
                break
        assert when in seen[-1], seen
        signalled = time.monotonic()
        proc.send_signal(signal.SIGTERM)
        rest = proc.communicate(timeout=30)[1]
        stopped = time.monotonic() - signalled
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 5, rest
    errors = [line for line in rest.splitlines() if line.startswith("error")]
    assert len(errors) == 1 and "stopped by signal 15" in errors[0], rest
    assert stopped < 2.0, stopped
    assert not (tmp_path / "out" / "s.h5").exists()


def test_sweep_without_checkpoints_stops_at_sigterm_within_a_second(exe, tmp_path):
    """With `checkpoint_every = 0` a run of a sweep (or a hysteresis stair, a search, a stability run) did not look
    at the stop flag and ran to its end after SIGTERM. Signalled once the scene has started its runs (its line)."""
    (tmp_path / "out").mkdir()
    (tmp_path / "s.nml").write_text("""&chain n = 2000, n0 = 1900 /
&numerics t_final = 100000.0 /
&scene kind = 'amplitude_sweep', amplitude_min = 1.0, amplitude_max = 1.2, amplitude_step = 0.2 /
&output file = 'out/s.h5', checkpoint_every = 0 /
""")
    proc = subprocess.Popen([exe, "s.nml"], cwd=tmp_path, stderr=subprocess.PIPE, text=True,
                            env=dict(os.environ, OMP_NUM_THREADS="1"))
    try:
        for line in proc.stderr:
            if "already done" in line:
                break
        signalled = time.monotonic()
        proc.send_signal(signal.SIGTERM)
        rest = proc.communicate(timeout=30)[1]
        stopped = time.monotonic() - signalled
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 5, rest
    assert "stopped by signal 15" in rest and stopped < 5.0, (stopped, rest)
    assert not (tmp_path / "out" / "s.h5").exists()


# --------------------------------------------------------------------------------------- issue 43: the batch scripts

SLURM = Path(__file__).resolve().parent.parent / "input" / "slurm"


@pytest.fixture
def stub_sbatch(tmp_path):
    """A stub `sbatch` first on PATH: it records its arguments (one line per call) and prints a job id."""
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    (bin_dir / "sbatch").write_text('#!/bin/bash\nprintf "%s\\n" "$*" >> "$SBATCH_LOG"\necho "4242;cluster"\n')
    os.chmod(bin_dir / "sbatch", 0o755)
    return bin_dir


def submit(exe, tmp_path, stub, *args):
    nml(tmp_path, SWEEP, name="study.nml")
    env = dict(os.environ, PATH=f"{stub}:{os.environ['PATH']}", SUPRATRANS=exe, SBATCH_LOG=str(tmp_path / "sbatch.log"))
    proc = subprocess.run(["bash", str(SLURM / "submit.sh"), "study.nml", *args], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=120)
    log = tmp_path / "sbatch.log"
    return proc, log.read_text().splitlines() if log.exists() else []


@pytest.mark.parametrize("args", [
    ["3", "--", "-c", "i[$(touch INJECTED)]"],
    ["3", "--", "--cpus-per-task=i[$(touch INJECTED)]"],
    ["3", "--", "-ci[$(touch INJECTED)]"],
    ["3", "i[$(touch INJECTED)]"],
    ["i[$(touch INJECTED)]"],
], ids=["-c VALUE", "--cpus-per-task=", "-cVALUE", "THROTTLE", "N"])
def test_submit_never_evaluates_user_text_as_arithmetic(exe, tmp_path, stub_sbatch, args):
    """Issue 43, failure 5: `submit.sh s.nml 3 -- -c 'i[$(id>/tmp/x)]'` ran `id` (the value went into $(( ))) and
    submitted. Now refused in one line, status 2, nothing submitted, nothing run."""
    proc, calls = submit(exe, tmp_path, stub_sbatch, *args)
    assert proc.returncode == 2, proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1 and "decimal" in proc.stderr, proc.stderr
    assert calls == []
    assert not (tmp_path / "INJECTED").exists()


@pytest.mark.parametrize("args", [["08"], ["010"], ["18446744073709551619"], ["100001"], ["0"], ["3", "08"],
                                  ["3", "18446744073709551619"], ["3", "--", "--cpus-per-task=08"],
                                  ["3", "--", "-c", "99999999999999999999"]])
def test_submit_refuses_leading_zeros_and_numbers_beyond_their_bound(exe, tmp_path, stub_sbatch, args):
    """Issue 43, failure 5: `N = 08` printed a bash error and submitted --array=1-08%08; N = 18446744073709551619
    wrapped past the "at most 100000" check."""
    proc, calls = submit(exe, tmp_path, stub_sbatch, *args)
    assert proc.returncode == 2, proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1 and "decimal" in proc.stderr, proc.stderr
    assert calls == []


@pytest.mark.parametrize("args, array", [(["3"], "--array=1-3%3"), (["16", "4", "--", "-c", "2"], "--array=1-16%4"),
                                         (["100000"], "--array=1-100000%100000")])
def test_submit_with_valid_numbers_and_no_options_submits_both_jobs(exe, tmp_path, stub_sbatch, args, array):
    proc, calls = submit(exe, tmp_path, stub_sbatch, *args)
    assert proc.returncode == 0, proc.stderr
    assert len(calls) == 2 and array in calls[0] and "--dependency=afterok:4242" in calls[1], calls
    assert "--mem=" in calls[0]


def test_batch_scripts_expand_arrays_as_bash_4_2_allows_under_set_u():
    """bash before 4.4 calls an empty array "unbound" under `set -u`: every array is expanded as ${a[@]+"${a[@]}"}
    (bash 4.2 is not installed here to run them; this reads them). No user value reaches $(( )) or (( )) unchecked:
    every variable in an arithmetic expression of submit.sh is one `decimal` checked, or the script's own."""
    import re
    for script in sorted(SLURM.iterdir()):
        text = "\n".join(line for line in script.read_text().splitlines() if not line.lstrip().startswith("#"))
        bare = re.findall(r'(?<!\+)"\$\{(\w+)\[@\]\}"', text)
        assert not bare, (script.name, bare)
    text = (SLURM / "submit.sh").read_text()
    allowed = {"i", "per_thread", "cpus", "user_mem", "status", "requeue", "text", "max"}
    for expr in re.findall(r"\$?\(\((.*?)\)\)", text):
        names = set(re.findall(r"\b([a-z_]+)\b", expr)) - {"array_opts"}
        assert names <= allowed, (expr, names - allowed)


def test_address_space_limit_with_one_processor_of_several(exe, tmp_path):
    """OpenBLAS counts the machine's processors, not the affinity mask: under `taskset -c 0` it still mapped a
    buffer for each, and a start-up that counted the mask's one hung under `ulimit -v 250 MiB`."""
    if shutil.which("taskset") is None or os.cpu_count() < 2:
        pytest.skip("needs taskset and two processors")
    proc = subprocess.run(["bash", "-c", 'ulimit -v 256000 && exec taskset -c 0 "$@"', "bash", exe, "--version"],
                          cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert proc.returncode in (0, 2), proc.stderr
    assert proc.returncode == 2 or proc.stdout.startswith("supratrans ")
