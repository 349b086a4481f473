"""A full disk during the final HDF5 write (issue 22, item 7): one line naming the file and the system's reason, the
documented I/O status 4 (docs/failures.md), nothing partial under the output's name, and a scene's journal that lets
the same command finish once there is space, without computing again.

Two ways to run out of space, whichever this machine allows:
- a small tmpfs mounted in a private mount namespace (`unshare -rm`, no root needed where user namespaces are on):
  a real ENOSPC, "No space left on device"; then the tmpfs is grown and the command run again;
- `RLIMIT_FSIZE` (a file size limit, set in the child, SIGXFSZ ignored so that write(2) fails with EFBIG, "File too
  large"): the journals of these tiny scenes fit under it, no HDF5 output does.
Before the fix, both ended in SIGSEGV (exit 139) in HDF5's exit handler with the error line lost.
"""
from __future__ import annotations

import re
import resource
import shutil
import signal
import subprocess
from pathlib import Path

import pytest

from conftest import OUTPUT, tiny_namelists

#: The file size limit (bytes): above every journal of the scenes below (< 12 KiB), below every HDF5 output of a
#: scene (> 100 KiB, /parameters and its schema included).
LIMIT = 32 * 1024
#: The size of the small tmpfs (KiB): room for the journal and the lock, not for the output.
TMPFS_KIB = 48

#: The cases: name -> (namelist of conftest's tiny files, extra arguments, whether the scene keeps a journal, file
#: size limit in bytes, tmpfs size in KiB). A part file is small (6 KiB for half of the tiny sweep, its journal
#: 3.5 KiB): its limits are set between the two.
CASES = {
    "timeseries": ("fig1_sg_A150", [], False, LIMIT, TMPFS_KIB),
    "amplitude_sweep": ("fig2", [], True, LIMIT, TMPFS_KIB),
    "stability": ("stab", [], True, LIMIT, TMPFS_KIB),
    "slice": ("fig2", ["--slice", "1/2"], True, 5000, 8),
}
NOISY = ("quiet = .true.", "quiet = .false.")


def namelist(name: str, out: Path) -> str:
    """The tiny namelist `name` writing `out`, with progress lines (they say how many tasks the journal holds)."""
    return (tiny_namelists()[name] + OUTPUT.format(out=out)).replace(*NOISY)


def limited(limit: int):
    """A preexec_fn: SIGXFSZ ignored (so write(2) returns EFBIG instead of killing) and RLIMIT_FSIZE set."""

    def apply() -> None:
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    return apply


def output_of(out: Path, args: list[str]) -> Path:
    """The file a run writes: the output, or for `--slice I/N` its part file."""
    if "--slice" in args:
        i, n = args[args.index("--slice") + 1].split("/")
        return out.with_name(f"{out.stem}.part-{i}-of-{n}.h5")
    return out


def check_failure(code: int, stderr: str, target: Path, left: list[str], reason: str) -> None:
    """The run that ran out of space: status 4, one error line naming the file and the reason, nothing partial."""
    assert code == 4, f"exit {code}, expected the I/O status 4:\n{stderr}"
    errors = [line for line in stderr.splitlines() if line.startswith("error: ")]
    assert len(errors) == 1, stderr
    assert str(target) in errors[0] and reason in errors[0].lower(), errors[0]
    assert "Backtrace" not in stderr and "Segmentation" not in stderr, stderr
    assert target.name not in left, f"{target.name} left under its final name: {left}"
    assert not [f for f in left if ".tmp-" in f], f"temporary files left: {left}"


def check_resumed(code: int, stderr: str, journal: bool) -> None:
    """The same command once there is space: success, every task taken from the journal."""
    assert code == 0, stderr
    if journal:
        m = re.search(r"(\d+) [^,\n]*, (\d+) already done", stderr)
        assert m, stderr
        assert m.group(1) == m.group(2), f"tasks computed again: {m.group(0)}"


@pytest.mark.parametrize("case", CASES)
def test_file_size_limit(exe, tmp_path, case):
    name, args, journal, limit, _ = CASES[case]
    out = tmp_path / "out.h5"
    nml = tmp_path / "case.nml"
    nml.write_text(namelist(name, out))
    proc = subprocess.run([exe, str(nml), *args], cwd=tmp_path, capture_output=True, text=True, timeout=300,
                          preexec_fn=limited(limit))
    target = output_of(out, args)
    check_failure(proc.returncode, proc.stderr, target, sorted(p.name for p in tmp_path.iterdir()), "file too large")
    if journal:
        assert (tmp_path / f"{target.name}.journal").is_file(), "the journal is kept for the rerun"
    again = subprocess.run([exe, str(nml), *args], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    check_resumed(again.returncode, again.stderr, journal)
    assert target.is_file()


def test_merge_under_a_file_size_limit(exe, tmp_path):
    out = tmp_path / "out.h5"
    nml = tmp_path / "case.nml"
    nml.write_text(namelist("fig2", out))
    for i in (1, 2):
        subprocess.run([exe, str(nml), "--slice", f"{i}/2"], cwd=tmp_path, check=True, capture_output=True, timeout=300)
    parts = [str(output_of(out, ["--slice", f"{i}/2"])) for i in (1, 2)]
    merged = tmp_path / "merged.h5"
    proc = subprocess.run([exe, "merge", "-o", str(merged), *parts], cwd=tmp_path, capture_output=True, text=True,
                          timeout=300, preexec_fn=limited(LIMIT))
    check_failure(proc.returncode, proc.stderr, merged, sorted(p.name for p in tmp_path.iterdir()), "file too large")
    again = subprocess.run([exe, "merge", "-o", str(merged), *parts], cwd=tmp_path, capture_output=True, text=True,
                           timeout=300)
    assert again.returncode == 0, again.stderr
    assert merged.is_file()


#: Run inside a private mount namespace: mount a small tmpfs at $1, run the command, list what is left, grow the
#: tmpfs, run the command again, list again. Exit 97 when the tmpfs cannot be mounted.
TMPFS_SCRIPT = r"""
mnt=$1; logs=$2; shift 2
mount -t tmpfs -o size={kib}k tmpfs "$mnt" || exit 97
"$@" 2>"$logs/err1"; echo $? >"$logs/rc1"; ls -A "$mnt" >"$logs/left1"
mount -o remount,size=16m "$mnt" || exit 97
"$@" 2>"$logs/err2"; echo $? >"$logs/rc2"; ls -A "$mnt" >"$logs/left2"
"""


@pytest.fixture(scope="module")
def tmpfs_ok(tmp_path_factory) -> None:
    """Skip (with the reason) unless a tmpfs can be mounted in a private mount namespace here."""
    if shutil.which("unshare") is None:
        pytest.skip("no unshare(1): cannot mount a small tmpfs (the RLIMIT_FSIZE tests cover the full disk)")
    where = tmp_path_factory.mktemp("probe")
    proc = subprocess.run(["unshare", "-rm", "sh", "-c", 'mount -t tmpfs -o size=64k tmpfs "$1"', "sh", str(where)],
                          capture_output=True, text=True)
    if proc.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs in a user namespace here ({proc.stderr.strip() or proc.returncode}); "
                    "the RLIMIT_FSIZE tests cover the full disk")


@pytest.mark.parametrize("case", CASES)
def test_full_tmpfs(exe, tmp_path, tmpfs_ok, case):
    name, args, journal, _, kib = CASES[case]
    mnt, logs = tmp_path / "mnt", tmp_path / "logs"
    mnt.mkdir()
    logs.mkdir()
    out = mnt / "out.h5"
    nml = tmp_path / "case.nml"
    nml.write_text(namelist(name, out))
    script = TMPFS_SCRIPT.format(kib=kib)
    proc = subprocess.run(["unshare", "-rm", "sh", "-c", script, "sh", str(mnt), str(logs), exe, str(nml), *args],
                          cwd=tmp_path, capture_output=True, text=True, timeout=600)
    if proc.returncode == 97:
        pytest.skip("the tmpfs could not be mounted or grown here")
    read = lambda f: (logs / f).read_text()  # noqa: E731
    target = output_of(out, args)
    check_failure(int(read("rc1")), read("err1"), target, read("left1").split(), "no space left")
    if journal:
        assert any(f.endswith(".journal") for f in read("left1").split()), read("left1")
    check_resumed(int(read("rc2")), read("err2"), journal)
    assert target.name in read("left2").split()
