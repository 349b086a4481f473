"""The commit in /provenance (src/base/supratrans_build_info.c, `.ci/with_commit`).

The sources as they are now are committed into a temporary repository and built there, once for the module (from a
copy of this checkout's build tree without the objects of the build-info C file, so that only what changed, that
file and the links are redone; marked slow all the same); each test then sets the state it needs and rebuilds through
`.ci/with_commit` (one C file and the links) or with plain fpm. A run built through `.ci/with_commit` records the
commit of its build, whatever its working directory, the directory of its executable, or a later checkout say. A
plain `fpm build` (the README's path) records the commit read when the program runs from the `.git` of the tree it
was built in (attribute `git_commit_source` "read at run time ...", dirty flag -1: not known), also from a fresh
clone whose branch is only in packed-refs; a copy without .git records "unknown (built without commit)".
"""
from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

from conftest import ROOT, build_lock, build_program

pytestmark = pytest.mark.slow

NO_COMMIT = "unknown (built without commit)"

NAMELIST = "&chain n = 40, n0 = 30 /\n&numerics t_final = 2.0 /\n&output file = 'r.h5', quiet = .true., " \
           "overwrite = .true. /\n"


def git(repo: Path, *args: str) -> str:
    """Run git in `repo` (a test identity for commits); its output, stripped."""
    out = subprocess.run(["git", "-c", "user.name=test", "-c", "user.email=test@example.invalid", *args], cwd=repo,
                         check=True, capture_output=True, text=True)
    return out.stdout.strip()


def provenance(exe: Path, where: Path, source: bool = False) -> tuple:
    """Run `exe` on a tiny namelist in directory `where`; `git_commit` and `git_dirty` of its file (and, with
    `source`, `git_commit_source`)."""
    h5py = pytest.importorskip("h5py")
    where.mkdir(parents=True, exist_ok=True)
    (where / "case.nml").write_text(NAMELIST)
    proc = subprocess.run([str(exe), "case.nml"], cwd=where, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    with h5py.File(where / "r.h5") as f:
        attrs = f["provenance"].attrs
        if source:
            return attrs["git_commit"].decode(), int(attrs["git_dirty"]), attrs["git_commit_source"].decode()
        return attrs["git_commit"].decode(), int(attrs["git_dirty"])


@pytest.fixture(scope="module")
def repo(tmp_path_factory) -> Path:
    """A git repository holding the sources as they are now (tracked and new files), built once."""
    if shutil.which("fpm") is None or shutil.which("git") is None:
        pytest.skip("fpm or git not installed")
    listed = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"], cwd=ROOT,
                            check=True, capture_output=True, text=True).stdout.split("\0")
    dest = tmp_path_factory.mktemp("build_commit") / "repo"
    for name in filter(None, listed):
        src = ROOT / name
        if src.is_file():
            (dest / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / name)
    git(dest, "init", "-q")
    git(dest, "add", "-A")
    git(dest, "commit", "-q", "-m", "the sources under test")
    if (ROOT / "build").is_dir():
        # fpm recompiles what differs from the copied objects; the build-info objects, which carry this checkout's
        # commit, are not copied (as .ci/with_commit removes them before each build); copied while no other worker
        # of the session builds in it
        with build_lock():
            shutil.copytree(ROOT / "build", dest / "build", symlinks=True,
                            ignore=shutil.ignore_patterns("*supratrans_build_info*", ".tests.lock"))
    build_program(dest)
    return dest


def test_a_run_records_the_commit_of_its_build(repo, tmp_path):
    built = git(repo, "rev-parse", "HEAD")
    exe = build_program(repo)
    assert provenance(exe, tmp_path / "elsewhere") == (built, 0)
    # another commit checked out after the build: the program (not rebuilt) still records its build's
    (repo / "NOTE.txt").write_text("a later commit\n")
    git(repo, "add", "NOTE.txt")
    git(repo, "commit", "-q", "-m", "a later commit")
    later = git(repo, "rev-parse", "HEAD")
    git(repo, "checkout", "-q", "--detach", later)
    assert later != built
    assert provenance(exe, repo / "out" / "run") == (built, 0)  # out/: ignored, the tree stays clean
    # run from another repository, the executable copied into it: neither its directory nor the working one counts
    other = tmp_path / "other"
    other.mkdir()
    git(other, "init", "-q")
    git(other, "commit", "-q", "--allow-empty", "-m", "another repository")
    shutil.copy2(exe, other / "supratrans")
    assert provenance(other / "supratrans", other) == (built, 0)
    # built again: now the later commit
    assert provenance(build_program(repo), tmp_path / "again") == (later, 0)


def test_uncommitted_changes_are_recorded_and_undone(repo, tmp_path):
    head = git(repo, "rev-parse", "HEAD")
    assert provenance(build_program(repo), tmp_path / "clean") == (head, 0)
    scratch = repo / "scratch.txt"
    scratch.write_text("not committed\n")
    try:
        assert provenance(build_program(repo), tmp_path / "dirty") == (head, 1)
    finally:
        scratch.unlink()
    # back to the clean tree, whose object fpm still has: the program must not keep the dirty build's flag
    assert provenance(build_program(repo), tmp_path / "clean_again") == (head, 0)


def test_plain_fpm_build_reads_the_commit_at_run_time(repo, tmp_path):
    git(repo, "checkout", "-q", "-B", "main")    # on a branch (an earlier test may have left HEAD detached)
    head = git(repo, "rev-parse", "HEAD")
    build_program(repo)
    assert provenance(build_program(repo), tmp_path / "wrapped", source=True) == (head, 0, "fixed at build")
    exe = build_program(repo, with_commit=False)
    commit, dirty, source = provenance(exe, tmp_path / "plain", source=True)
    assert (commit, dirty) == (head, -1)
    assert source.startswith(f"read at run time from {repo / '.git'}: ") and "moved" not in source, source
    # the branch only in packed-refs (as after git gc): read there
    git(repo, "pack-refs", "--all")
    assert not (repo / ".git" / "refs" / "heads" / "main").exists()
    assert provenance(exe, tmp_path / "packed") == (head, -1)
    # a commit made after the build: the program reads the new HEAD and says that HEAD moved after it was built
    (repo / "LATER.txt").write_text("a later commit\n")
    git(repo, "add", "LATER.txt")
    git(repo, "commit", "-q", "-m", "a later commit")
    try:
        commit, dirty, source = provenance(exe, tmp_path / "moved", source=True)
        assert (commit, dirty) == (git(repo, "rev-parse", "HEAD"), -1)
        assert source.endswith("HEAD moved after the executable was written"), source
    finally:
        git(repo, "reset", "-q", "--hard", head)
    assert provenance(build_program(repo), tmp_path / "wrapped_again") == (head, 0)


def test_a_fresh_clone_built_with_plain_fpm_records_its_commit(repo, tmp_path):
    """The README's path: clone, `fpm build`, run; /provenance names `git rev-parse HEAD` of the clone. The clone
    gets the repository's build tree without the build-info objects (as `repo` does), so that fpm redoes the C file
    and the links, not the whole program (a compile from nothing is `fpm test`'s on a fresh clone)."""
    clone = tmp_path / "clone"
    subprocess.run(["git", "clone", "-q", str(repo), str(clone)], check=True, capture_output=True)
    assert not (clone / "build").exists()
    shutil.copytree(repo / "build", clone / "build", symlinks=True,
                    ignore=shutil.ignore_patterns("*supratrans_build_info*"))
    subprocess.run(["fpm", "build"], cwd=clone, check=True, capture_output=True, text=True)
    exe = build_program(clone, with_commit=False)
    commit, dirty, source = provenance(exe, clone / "out" / "run", source=True)
    assert commit == git(clone, "rev-parse", "HEAD")
    assert dirty == -1 and source.startswith("read at run time from "), source


def test_a_copy_without_git_records_no_commit(repo, tmp_path):
    copy = tmp_path / "copy"
    # the sources and the build tree (so that only the C file and the links are redone), not .git
    shutil.copytree(repo, copy, ignore=shutil.ignore_patterns(".git"), symlinks=True)
    assert not (copy / ".git").exists()
    assert provenance(build_program(copy), tmp_path / "run") == (NO_COMMIT, -1)
