"""The program as a user runs it: every bad-input case of the namelist gets one line on stderr that names the file
and the key, exit status 2, and no output file; a good input writes its HDF5 file."""
import subprocess

import pytest


@pytest.fixture
def exe(debug_exe):
    """Path of the supratrans executable (debug profile, built by fpm once per session: conftest.py)."""
    return str(debug_exe)


@pytest.fixture
def run(exe, tmp_path, write_namelist):
    """`run(text)`: the program run in tmp_path on a namelist `case.nml` with that text; (process, namelist)."""

    def run_case(text):
        nml = write_namelist(text)
        (tmp_path / "out_dir").mkdir(exist_ok=True)
        return subprocess.run([exe, str(nml)], cwd=tmp_path, capture_output=True, text=True), nml

    return run_case


OUT = "&output file = 'result.h5' /\n"

CASES = {
    "unknown key": ("&chain cc = 4.0 /\n" + OUT, "'cc'"),
    "unknown group": ("&chian c = 4.0 /\n" + OUT, "&chian"),
    "wrong type": ("&chain n = 2.5 /\n" + OUT, "'n'"),
    "N < 2": ("&chain n = 1, n0 = 0 /\n&record probes = 1 /\n" + OUT, "n = 1"),
    "dt <= 0": ("&numerics dt = -0.1 /\n" + OUT, "dt"),
    "T <= 0": ("&numerics t_final = 0.0 /\n" + OUT, "t_final"),
    "omega outside the gap": ("&drive omega = 1.2 /\n" + OUT, "omega"),
    "stability violated": ("&numerics dt = 0.3 /\n" + OUT, "dt"),
    # limits checked before any work (each gave a silent wrong answer, a crash or a hang before)
    "more than 2^31 steps": ("&numerics dt = 1e-6, t_final = 2200 /\n" + OUT, "t_final/dt"),
    "t_final = 1e12": ("&numerics t_final = 1e12 /\n" + OUT, "t_final/dt"),
    "dt = 1e-310": ("&numerics dt = 1e-310 /\n" + OUT, "t_final/dt"),
    "resolution = 1e-10": ("&scene kind = 'bifurcation', resolution = 1e-10 /\n" + OUT, "resolution"),
    "omega_step = 1e-15": ("&scene kind = 'bifurcation', omega_step = 1e-15 /\n" + OUT, "omega_step"),
    "omega_step = 1e-9": ("&scene kind = 'map', omega_step = 1e-9 /\n" + OUT, "omega_step"),
    "n = 2e9": ("&chain n = 2000000000, n0 = 10 /\n&record probes = 1 /\n" + OUT, "n = "),
    "c = 1e308": ("&chain c = 1e308 /\n" + OUT, "c = "),
    "10^9 runs": ("&scene kind = 'map', amplitude_step = 0.001, amplitude_max = 1000.0, omega_step = 0.0001 /\n" + OUT,
                  "runs"),
    "empty file": ("", "no namelist group"),
    "comments only": ("! nothing here\n   \n", "no namelist group"),
    "no equals sign": ("&chain c 4.0 /\n" + OUT, "'='"),
    "output is a directory": ("&output file = 'out_dir' /\n", "directory"),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_bad_input(run, tmp_path, case):
    text, key = CASES[case]
    proc, nml = run(text)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert str(nml) in lines[0] and key in lines[0], lines[0]
    assert not (tmp_path / "result.h5").exists()
    assert not list(tmp_path.glob("result.h5*"))


def test_missing_file(exe, tmp_path):
    proc = subprocess.run([exe, str(tmp_path / "nowhere.nml")], capture_output=True, text=True)
    assert proc.returncode == 2
    assert "nowhere.nml" in proc.stderr and len(proc.stderr.strip().splitlines()) == 1


def test_output_exists_is_refused_then_overwritten(run, tmp_path):
    (tmp_path / "result.h5").write_text("not mine")
    small = "&chain n = 40, n0 = 30 /\n&record probes = 5 /\n&numerics t_final = 2.0 /\n"
    proc, nml = run(small + OUT)
    assert proc.returncode == 2
    assert "exists" in proc.stderr and "file" in proc.stderr
    assert (tmp_path / "result.h5").read_text() == "not mine"
    proc, nml = run(small + "&output file = 'result.h5', overwrite = .true., quiet = .true. /\n")
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""
    h5py = pytest.importorskip("h5py")
    with h5py.File(tmp_path / "result.h5") as f:
        assert f.attrs["scene"] == b"timeseries"
        assert f["probes/u"].attrs["units"] == b"rad"
        assert f["run"].attrs["status"] == b"ok"
    assert not (tmp_path / "result.h5.tmp").exists()


def test_output_path_never_reaches_a_shell(run, tmp_path):
    """A path with shell syntax is a path: its directories are made literally and no command runs."""
    small = "&chain n = 40, n0 = 30 /\n&record probes = 5 /\n&numerics t_final = 2.0 /\n"
    hostile = "out/x'; echo INJECTED > PWNED; echo '/r.h5"
    proc, _ = run(small + f"&output file = \"{hostile}\", quiet = .true. /\n")
    assert proc.returncode == 0, proc.stderr
    assert not (tmp_path / "PWNED").exists()
    assert (tmp_path / hostile).is_file()


def test_nested_output_directories_are_created(run, tmp_path):
    small = "&chain n = 40, n0 = 30 /\n&record probes = 5 /\n&numerics t_final = 2.0 /\n"
    proc, _ = run(small + "&output file = 'a/b//c/r.h5', quiet = .true. /\n")
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "a" / "b" / "c" / "r.h5").is_file()


def test_output_that_is_the_input_is_refused(exe, tmp_path):
    nml = tmp_path / "case.nml"
    text = "&chain n = 40, n0 = 30 /\n&output file = 'case.nml', overwrite = .true. /\n"
    nml.write_text(text)
    proc = subprocess.run([exe, str(nml)], cwd=tmp_path, capture_output=True, text=True)
    assert proc.returncode == 2 and "input file itself" in proc.stderr, proc.stderr
    assert nml.read_text() == text


def test_memory_beyond_the_process_limit_is_refused_before_work(exe, tmp_path):
    import resource

    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (4 * 10**9, 4 * 10**9))
    nml = tmp_path / "case.nml"
    nml.write_text("&chain n = 100000000, n0 = 10 /\n&record probes = 1 /\n&output file = 'r.h5' /\n")
    proc = subprocess.run([exe, str(nml)], cwd=tmp_path, capture_output=True, text=True, preexec_fn=limit, timeout=60)
    assert proc.returncode == 2, proc.stderr
    assert "GB available" in proc.stderr and len(proc.stderr.strip().splitlines()) == 1


@pytest.mark.parametrize("args,status,words", [
    (["--help"], 0, "usage"), (["-h"], 0, "usage"), (["--version"], 0, "supratrans 0."),
    (["--frobnicate"], 2, "unknown option"), ([], 2, "usage"), (["--slice", "0/3", "x.nml"], 2, "--slice"),
])
def test_command_line_conventions(exe, tmp_path, args, status, words):
    proc = subprocess.run([exe, *args], cwd=tmp_path, capture_output=True, text=True)
    assert proc.returncode == status, proc.stderr
    assert words in (proc.stdout if status == 0 else proc.stderr)
    if status:
        assert len(proc.stderr.strip().splitlines()) == 1


def test_binary_garbage_is_not_echoed_raw(exe, tmp_path):
    nml = tmp_path / "case.nml"
    nml.write_bytes(b"&chain \x1b[31mc\x00\xff = 4 /\n")
    proc = subprocess.run([exe, str(nml)], cwd=tmp_path, capture_output=True)
    assert proc.returncode == 2
    line = proc.stderr.decode("latin-1").strip()
    assert len(line.splitlines()) == 1 and all(32 <= ord(c) < 127 for c in line), line


@pytest.mark.parametrize("scene", ["timeseries", "amplitude_sweep"])
def test_every_output_records_its_provenance(run, tmp_path, scene):
    h5py = pytest.importorskip("h5py")
    extra = "" if scene == "timeseries" else \
        "&scene kind = 'amplitude_sweep', amplitude_min = 1.0, amplitude_max = 1.2, amplitude_step = 0.1 /\n"
    text = "&chain n = 40, n0 = 30 /\n&record probes = 5 /\n&numerics t_final = 2.0 /\n" + extra + \
        "&output file = 'result.h5', quiet = .true. /\n"
    proc, nml = run(text)
    assert proc.returncode == 0, proc.stderr
    with h5py.File(tmp_path / "result.h5") as f:
        p = f["provenance"].attrs
        assert p["version"].decode().count(".") == 2
        commit = p["git_commit"].decode()
        assert len(commit) == 40 and int(commit, 16) >= 0       # built by conftest.py through .ci/with_commit
        assert p["git_dirty"] in (0, 1)
        assert p["compiler"].decode().startswith("GCC")
        assert "-fopenmp" in p["compiler_options"].decode() or "openmp" in p["compiler_options"].decode()
        assert p["omp_max_threads"] >= 1 and p["host"] and p["started"].decode()[:2] == "20"
        assert p["input_file"].decode() == str(nml)
        assert f["provenance/namelist"][()].decode() == text
