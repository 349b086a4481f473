"""Shared fixtures of the Python tests (test/*.py and postprocess/tests/*.py; configuration in pytest.ini).

- `debug_exe`, `release_exe`: the supratrans executable, built by fpm once per session (debug, or the release
  profile that make_figures.py uses), only when a selected test needs it; the tests are skipped without fpm.
  pytest runs on every core (pytest.ini: pytest-xdist, `-n auto`): the workers of one session share each build
  (the first to need it makes it under `build_lock`, the others read its path), and every command that runs fpm in
  this checkout holds `build_lock` (`.ci/with_commit` removes the library archives of every profile);
- `host_exe`: the release build for this machine's vector units (fpm's release flags plus HOST_FLAGS, in a build
  directory of its own: fpm hashes the flags), for the cross-build tests of test/test_host_build.py;
- `write_namelist`: writes a namelist into the test's tmp_path; `small_chain`: the text of a tiny timeseries;
- `tiny`: small HDF5 files of every scene, made by the program itself (tiny chains, short times) once per session,
  each the first time a test asks for it (`tiny.file("fig2")`); tests that change one copy it first;
- `call_main`: runs a script's `main(argv)` in the test's process and returns its exit status and output, as a
  subprocess would (without the second or so of starting Python and importing matplotlib for each call).

The tests of more than a few seconds (a compiler or a build, make_figures.py running fpm, the SciPy peer, a real
Slurm, long resumed runs) are marked `slow`; `bash test/run_tests.sh` runs everything, the fast tier
`python3 -m pytest -m "not slow"` skips them (docs/testing.md).
"""
from __future__ import annotations

import contextlib
import fcntl
import os
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import pytest

ROOT = Path(__file__).resolve().parent

# ------------------------------------------------------------------------------------------------ the program


#: Runs a command so that the program it builds records this checkout's commit (fpm cannot run git itself).
WITH_COMMIT = ["sh", str(ROOT / ".ci" / "with_commit")]


#: Compiler flags of the host build, added to fpm's release flags: SUPRATRANS_HOST_FLAGS, else -march=native
#: (every vector unit of the machine that builds it; docs/benchmark.md, "Builds for the hardware").
HOST_FLAGS = os.environ.get("SUPRATRANS_HOST_FLAGS", "-march=native")


def build_program(root: Path, profile: str = "debug", with_commit: bool = True, flags: str = "") -> Path:
    """Build the program in the source tree `root` with fpm (`debug` or `release`, plus compiler `flags` when
    given: fpm's `--flag`), through `.ci/with_commit` (the commit recorded) or with plain fpm; the path of its
    executable. Raises CalledProcessError."""
    args = ["--profile", profile] + (["--flag", flags] if flags else [])
    wrapper = ["sh", str(root / ".ci" / "with_commit")] if with_commit else []
    # one fpm call builds and names the executable: with_commit relinks at every call
    out = subprocess.run([*wrapper, "fpm", "run", *args, "--runner", "echo"], cwd=root, check=True,
                         capture_output=True, text=True)
    return root / out.stdout.strip().splitlines()[-1].split()[0]


@contextlib.contextmanager
def build_lock():
    """Hold the lock of this checkout's build tree (an flock on build/.tests.lock) while fpm builds in it: the
    pytest workers of a session, and any other process that takes it, never build at the same time (two fpm in one
    tree would race, and `.ci/with_commit` removes the library archive of every profile as it starts)."""
    folder = ROOT / "build"
    folder.mkdir(exist_ok=True)
    with open(folder / ".tests.lock", "a") as f:
        fcntl.flock(f, fcntl.LOCK_EX)
        yield


def session_folder(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A folder shared by every worker of this pytest session (pytest-xdist's workers have their own base
    temporary folders in one shared folder) and by no other session."""
    base = tmp_path_factory.getbasetemp()
    return base.parent if hasattr(request.config, "workerinput") else base


def _build(profile: str, shared: Path, flags: str = "") -> Path:
    """Build the program with fpm (`debug` or `release`, plus `flags`) once for the session whose shared folder is
    `shared`, and return the path of a copy of its executable in `shared`: the first worker to ask builds it under
    `build_lock` and copies it, the others find the copy. Tests run the copy, so that a later build in this checkout
    (make_figures.py and builds.py build through fpm; a developer's `fpm build`) never relinks a program while a
    test starts it."""
    if shutil.which("fpm") is None:
        pytest.skip("fpm not installed")
    copy = shared / f"exe-{profile}-{flags.encode().hex()}" / "supratrans"
    if not copy.is_file():
        with build_lock():
            if not copy.is_file():
                try:
                    exe = build_program(ROOT, profile, flags=flags)
                except subprocess.CalledProcessError as e:
                    pytest.fail(f"fpm build --profile {profile} --flag '{flags}' failed:\n"
                                f"{(e.stdout + e.stderr)[-3000:]}")
                copy.parent.mkdir(exist_ok=True)
                part = copy.with_suffix(".part")
                shutil.copy2(exe, part)
                part.rename(copy)          # whole or absent, for a worker that looks without the lock
    return copy


@pytest.fixture(scope="session")
def debug_exe(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The supratrans executable, debug profile (what `fpm build` makes)."""
    return _build("debug", session_folder(request, tmp_path_factory))


@pytest.fixture(scope="session")
def exe(debug_exe: Path) -> str:
    """The debug executable as a string (test/test_slices.py, test_slurm.py, test_fuzz.py, test_verdicts.py)."""
    return str(debug_exe)


@pytest.fixture(scope="session")
def release_exe(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The supratrans executable, release profile (what make_figures.py runs)."""
    return _build("release", session_folder(request, tmp_path_factory))


@pytest.fixture(scope="session")
def host_exe(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The supratrans executable, release profile built for this machine's vector units (HOST_FLAGS)."""
    return _build("release", session_folder(request, tmp_path_factory), HOST_FLAGS)


@pytest.fixture
def write_namelist(tmp_path: Path) -> Callable[..., Path]:
    """`write_namelist(text, name="case.nml")`: the path of a namelist file with that text in the test's
    tmp_path."""

    def write(text: str, name: str = "case.nml") -> Path:
        path = tmp_path / name
        path.write_text(text)
        return path

    return write


# ------------------------------------------------------------------------------------------------ the workers


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """The order in which pytest-xdist deals the test files to its workers (`--dist loadfile
    --no-loadscope-reorder`, pytest.ini: a file's tests run on one worker, in order, so that its module-scoped
    fixtures, a costly reference, the Slurm cluster, a temporary repository, are made once): the files that hold a
    `slow` test first, in the order collected, so that the long ones do not come last and leave one worker running
    them while the other idles. (Per-test dealing with `xdist_group` marks for the shared fixtures would balance
    finer, but pytest-xdist 3.8 cannot group under pytest 9: it renames the node ids, which pytest 9 no longer
    lets it do.)"""
    slow_files = {item.nodeid.split("::")[0] for item in items if item.get_closest_marker("slow")}
    items.sort(key=lambda item: item.nodeid.split("::")[0] not in slow_files)     # stable: collected order otherwise


# ------------------------------------------------------------------------------------------------ tiny files

#: A small chain (N = 40, T short): `{potential}`, `{amplitude}`, `{t_final}` to fill in.
SMALL = """&chain
    potential = '{potential}'
    n = 40
    n0 = 30
/
&drive
    amplitude = {amplitude}
    ramp_time = 5.0
/
&numerics
    t_final = {t_final}
/
&record
    probes = 1, 20, 30
/
"""
#: The `&output` group of every tiny namelist: `{out}` to fill in.
OUTPUT = """&output
    file = '{out}'
    overwrite = .true.
    quiet = .true.
/
"""
#: The tiny grid scenes of the figures: name (the figure the stem stands for) -> &scene group.
SCENES = {
    "fig2": """&scene
    kind = 'amplitude_sweep'
    potentials = 'sine-gordon', 'klein-gordon'
    vary = 'gamma'
    values = 0.0, 0.03
    amplitude_min = 1.0
    amplitude_max = 2.0
    amplitude_step = 0.5
/
""",
    "fig3": """&scene
    kind = 'amplitude_sweep'
    potentials = 'sine-gordon'
    vary = 'm2'
    values = -0.01, 0.0, 0.01
    amplitude_min = 1.0
    amplitude_max = 2.0
    amplitude_step = 0.5
/
""",
    "fig11": """&scene
    kind = 'map'
    potentials = 'sine-gordon', 'klein-gordon'
    amplitude_min = 1.0
    amplitude_max = 2.0
    amplitude_step = 0.5
    omega_min = 0.5
    omega_max = 0.9
    omega_step = 0.4
/
""",
    "bif3": """&scene
    kind = 'bifurcation'
    vary = 'm2'
    values = -0.19, 0.0, 0.21
    amplitude_min = 1.0
    amplitude_max = 4.0
    coarse_step = 1.0
    resolution = 0.25
    omega_min = 0.7
    omega_max = 1.0
    omega_step = 0.3
/
""",
}
#: The chain of the tiny work_precision files: every term on (beta, gamma, m^2, the absorber).
WORKPREC_CHAIN = """&chain
    potential = '{potential}'
    c = 2.0
    beta = {beta}
    gamma = {gamma}
    m2 = {m2}
    n = 24
    n0 = 14
    kappa = 0.5
    sigma = 2.0
/
&drive
    amplitude = 1.5
    omega = 0.9
    ramp_time = 5.0
/
&numerics
    t_final = 20.0
/
&record
    probes = 6
/
"""
WORKPREC = """&scene
    kind = 'work_precision'
    amplitudes = 1.0, 2.0
    methods = 'linearized', 'rk4', 'rk8'
    dts = 0.25, 0.125, 0.0625
    repeats = 1
    reference_dt = 0.05
/
"""
STABILITY = """&chain
    potential = 'sine-gordon'
    n = 20
    n0 = 14
    kappa = 0.0
/
&drive
    amplitude = 0.5
    ramp_time = 5.0
/
&numerics
    t_final = 20.0
    blowup_threshold = 1.5
/
&scene
    kind = 'stability'
    methods = 'newton', 'linearized', 'rk4'
    c_values = 2.0, 4.0
    dts = 0.1, 0.2, 0.3, 0.4
    vary = 'beta'
    values = 0.0, 0.5
    resolution = 0.01
/
"""


@pytest.fixture(scope="session")
def small_chain() -> Callable[..., str]:
    """`small_chain(potential, amplitude, t_final, out)`: the text of a tiny timeseries namelist (SMALL) that
    writes `out`."""

    def text(potential: str, amplitude: float, t_final: float, out: Path) -> str:
        return SMALL.format(potential=potential, amplitude=amplitude, t_final=t_final) + OUTPUT.format(out=out)

    return text


def tiny_namelists() -> dict[str, str]:
    """The namelist text (without `&output`) of every tiny file, by name: the four Fig. 1 runs
    (`fig1_{sg,kg}_A{150,250}`), the grid scenes of SCENES, `wp_sg` and `wp_kg` (work_precision) and `stab`
    (stability)."""
    texts = {}
    for p, pot in (("s", "sine-gordon"), ("k", "klein-gordon")):
        for a in (150, 250):
            texts[f"fig1_{p}g_A{a}"] = SMALL.format(potential=pot, amplitude=a / 100, t_final=10.0)
    for name, scene in SCENES.items():
        texts[name] = SMALL.format(potential="sine-gordon", amplitude=1.77, t_final=20.0).replace(
            "probes = 1, 20, 30", "probes = 1") + scene
    texts["wp_sg"] = WORKPREC_CHAIN.format(potential="sine-gordon", beta=0.1, gamma=0.01, m2=0.05) + WORKPREC
    texts["wp_kg"] = WORKPREC_CHAIN.format(potential="klein-gordon", beta=0.0, gamma=0.02, m2=-0.03) + WORKPREC
    texts["stab"] = STABILITY
    return texts


class TinyFiles:
    """The tiny HDF5 files, made by the program in one folder the first time each is asked for (by any worker of
    the session: the folder is shared, and each file is made under a lock of its own)."""

    def __init__(self, exe: Path, folder: Path) -> None:
        self.exe, self.folder = exe, folder
        self.texts = tiny_namelists()
        self.made: dict[str, Path | str] = {}

    def file(self, name: str) -> Path:
        """The file `name` (see `tiny_namelists`); the test is skipped when the program does not know its scene
        (yet), and fails when the program fails on it."""
        if name not in self.made:
            out = self.folder / f"{name}.h5"
            verdict = self.folder / f"{name}.made"      # "" when made, else why not
            with open(self.folder / f"{name}.lock", "a") as lock:
                fcntl.flock(lock, fcntl.LOCK_EX)
                if not verdict.is_file():
                    nml = self.folder / f"{name}.nml"
                    nml.write_text(self.texts[name] + OUTPUT.format(out=out))
                    proc = subprocess.run([str(self.exe), str(nml)], cwd=self.folder, capture_output=True,
                                          text=True, timeout=120)
                    ok = proc.returncode == 0 and out.is_file()
                    verdict.write_text("" if ok else (proc.stderr.strip() or "no file"))
                why = verdict.read_text()
            self.made[name] = why if why else out
        made = self.made[name]
        if isinstance(made, Path):
            return made
        if "not implemented" in made or "&scene: kind" in made:
            pytest.skip(f"the program cannot write this scene yet: {made.splitlines()[-1]}")
        pytest.fail(f"the program failed on the tiny {name} namelist: {made}")


@pytest.fixture(scope="session")
def tiny(debug_exe: Path, request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> TinyFiles:
    """The tiny HDF5 files of every scene, made by the program (debug build) on first use."""
    folder = session_folder(request, tmp_path_factory) / "tiny"
    folder.mkdir(exist_ok=True)
    return TinyFiles(debug_exe, folder)


# ------------------------------------------------------------------------------------------------ scripts


@dataclass
class Ran:
    """What a script did: its exit status and what it printed (as subprocess.CompletedProcess has them)."""

    returncode: int
    stdout: str
    stderr: str


@pytest.fixture
def call_main(capsys: pytest.CaptureFixture) -> Callable[..., Ran]:
    """`call_main(main, *args)`: run a script's `main(argv)` in this process; its exit status and output."""

    def call(main: Callable[[list[str]], int], *args: object) -> Ran:
        capsys.readouterr()
        try:
            code = main([str(a) for a in args])
        except SystemExit as exc:  # argparse
            code = exc.code if isinstance(exc.code, int) else 2
        out = capsys.readouterr()
        return Ran(int(code or 0), out.out, out.err)

    return call


@pytest.fixture(autouse=True)
def _close_figures():
    """Figures drawn by a test (and not saved, which closes them) are closed after it."""
    yield
    plt = sys.modules.get("matplotlib.pyplot")
    if plt is not None:
        plt.close("all")
