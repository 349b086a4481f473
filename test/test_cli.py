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
