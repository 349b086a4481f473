"""The release build for this machine's vector units (fpm's release flags plus HOST_FLAGS of conftest.py, by default
-march=native; docs/benchmark.md, "Builds for the hardware") against the default release build (SSE2 on x86-64).

The policy these tests hold:
- within one build, results are bit-identical for any thread count and any slicing (as for the default build,
  test_slices.py and the scene tests): checked here for the host build;
- between builds, thresholds are identical (at Omega = 0.3, 0.6, 0.9 of the paper's grid, paper-default chain, both
  potentials) and the energies of every run below the threshold agree to 1e-12 of the run's injected energy (the
  energy after the ramp, a difference of two larger numbers, to 1e-12 of the total, not of itself). Above it the chain
  transmits: the motion is irregular and amplifies roundoff (measured between the two builds up to 9e-9 relative
  at A = 2.9, T = 200), so there the verdicts must agree, not the last digits.

The statically linked executable (postprocess/builds.py links it from fpm's objects) gives the same results as the
dynamic one, bit for bit: the same objects, and LAPACK's dgtsv (beta > 0) from the static archive.

Each build takes minutes the first time (a build directory of its own, kept): marked slow.
"""
import os
import platform
import re
import shutil
import subprocess

import h5py
import numpy as np
import pytest

import compare_results
from conftest import ROOT, build_lock
from supratrans_post import builds

pytestmark = pytest.mark.slow

#: A small bifurcation diagram (from test_slices.py): 10 threshold searches.
BIF_SMALL = """&chain n = 60, n0 = 45 /
&numerics t_final = 40.0 /
&scene kind = 'bifurcation', amplitude_min = 0.5, amplitude_max = 6.0, omega_min = 0.5, omega_max = 0.9,
  omega_step = 0.1, coarse_step = 0.5, resolution = 0.1, potentials = 'sine-gordon', 'klein-gordon' /
&output file = 'out/study.h5', quiet = .true. /
"""
#: Thresholds of the paper-default chain (N = 200, T = 200, dt = 0.05) at a few Omega of the paper's grid, at the
#: paper's resolution.
BIF_PAPER = """&scene kind = 'bifurcation', potentials = 'sine-gordon', 'klein-gordon', omega_min = 0.3,
  omega_max = 0.9, omega_step = 0.3, amplitude_min = 0.5, amplitude_max = 10.0, coarse_step = 0.25,
  resolution = 0.01 /
&output file = 'out/study.h5', quiet = .true. /
"""
#: An amplitude sweep of the paper-default chain, both potentials, with and without external damping; the
#: threshold is near A = 1.8, so the amplitudes 1.0 .. 1.6 stay below it and 2.0 .. 2.4 transmit.
SWEEP_PAPER = """&scene kind = 'amplitude_sweep', potentials = 'sine-gordon', 'klein-gordon', vary = 'gamma',
  values = 0.0, 0.02, amplitude_min = 1.0, amplitude_max = 2.4, amplitude_step = 0.2 /
&output file = 'out/study.h5', quiet = .true. /
"""
#: The energies of a sweep that must agree between builds (below the threshold).
ENERGIES = ("injected", "injected_after_ramp", "stored", "dissipated_gamma", "dissipated_absorber")


def run(exe, text, folder, *args, threads=1):
    """Run the program on `text` in `folder` (created); the path of the file it wrote (or of `out/` for slices)."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "study.nml").write_text(text)
    proc = subprocess.run([str(exe), "study.nml", *args], cwd=folder, capture_output=True, text=True, timeout=600,
                          env=dict(os.environ, OMP_NUM_THREADS=str(threads)))
    assert proc.returncode == 0, proc.stderr
    return folder / "out" / "study.h5"


def identical(a, b):
    diffs, compared, _ = compare_results.compare(a, b)
    assert compared > 5 and not diffs, diffs


def test_host_build_results_are_identical_for_threads_and_slices(host_exe, tmp_path):
    one = run(host_exe, BIF_SMALL, tmp_path / "one", threads=1)
    two = run(host_exe, BIF_SMALL, tmp_path / "two", threads=2)
    identical(one, two)
    sliced = tmp_path / "sliced"
    for i in (1, 2, 3):
        run(host_exe, BIF_SMALL, sliced, "--slice", f"{i}/3", threads=2)
    parts = sorted((sliced / "out").glob("study.part-*.h5"))
    assert len(parts) == 3
    proc = subprocess.run([str(host_exe), "merge", *map(str, parts)], cwd=sliced, capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stderr
    identical(one, sliced / "out" / "study.h5")


def test_host_and_default_builds_find_identical_thresholds(host_exe, release_exe, tmp_path):
    default = run(release_exe, BIF_PAPER, tmp_path / "default", threads=2)
    host = run(host_exe, BIF_PAPER, tmp_path / "host", threads=2)
    with h5py.File(default) as fd, h5py.File(host) as fh:
        a, b = fd["threshold"][()], fh["threshold"][()]
        # Klein-Gordon at Omega = 0.3, 0.6 has no threshold in the range (status: none found), in both builds
        assert a.shape == (2, 3) and np.isfinite(a).sum() >= 4, a
        assert np.array_equal(a, b, equal_nan=True), (a, b)
        assert np.array_equal(fd["status"][()], fh["status"][()])


def test_host_and_default_builds_agree_to_1e_12_below_the_threshold(host_exe, release_exe, tmp_path):
    default = run(release_exe, SWEEP_PAPER, tmp_path / "default", threads=2)
    host = run(host_exe, SWEEP_PAPER, tmp_path / "host", threads=2)
    with h5py.File(default) as fd, h5py.File(host) as fh:
        transmitting = fd["runs/transmitting"][()].astype(bool)
        assert np.array_equal(transmitting, fh["runs/transmitting"][()].astype(bool))
        assert np.array_equal(fd["runs/status"][()], fh["runs/status"][()])
        quiet = ~transmitting
        assert quiet.sum() >= 12 and transmitting.sum() >= 8, transmitting
        differ = 0
        scale = np.abs(fd["energy/injected"][()][quiet])    # the run's energy scale: what the drive put in
        assert np.all(scale > 0)
        for name in ENERGIES:
            a, b = fd[f"energy/{name}"][()][quiet], fh[f"energy/{name}"][()][quiet]
            rel = np.abs(a - b)/scale
            assert rel.max() <= 1.0e-12, (name, rel.max())
            differ += int(np.count_nonzero(a != b))
        # the builds differ at all (else the host flags changed nothing and this test compares a build with itself)
        assert differ > 0


def has_avx2():
    """Whether this is an x86-64 machine with AVX2 and FMA (its host build then uses VEX-encoded vector code)."""
    try:
        flags = open("/proc/cpuinfo").read()
    except OSError:
        return False
    return platform.machine() == "x86_64" and " avx2" in flags and " fma" in flags


def vex_packed_per_routine(exe):
    """VEX-encoded packed-double instructions (vmulpd, vfmadd231pd, ... on xmm or ymm registers: AVX and later,
    never in an SSE2 build) in each routine of an executable (objdump -d). Not ymm alone: -march=native tunes
    for the machine, and on AMD Zen 1 (or a virtual machine that reports itself so) gcc prefers 128-bit vectors."""
    text = subprocess.run(["objdump", "-d", "--no-show-raw-insn", str(exe)], capture_output=True, text=True,
                          check=True).stdout
    packed = re.compile(r"\tv[a-z0-9]+pd\s")
    counts, name = {}, None
    for line in text.splitlines():
        if line.endswith(">:"):
            name = line.split("<", 1)[1][:-2]
        elif name and packed.search(line):
            counts[name] = counts.get(name, 0) + 1
    return counts


@pytest.mark.skipif(not has_avx2(), reason="no AVX2 and FMA on this machine")
def test_host_build_uses_the_vector_units_in_the_hot_loops(host_exe, release_exe):
    if shutil.which("objdump") is None:
        pytest.skip("objdump not installed")
    host, default = vex_packed_per_routine(host_exe), vex_packed_per_routine(release_exe)
    for routine in ("sin_cos_array", "sine_gordon_kernel", "newton_step", "rk8_step", "chain_rhs"):
        assert sum(c for n, c in host.items() if routine in n) > 100, routine
        assert sum(c for n, c in default.items() if routine in n) == 0, routine


#: Two paper-default runs, without and with internal damping (beta > 0: one LAPACK dgtsv per Newton iteration).
PAPER_RUNS = ("&drive amplitude = 1.9 /\n&output file = 'out/study.h5', quiet = .true. /\n",
              "&chain beta = 0.1 /\n&drive amplitude = 1.9 /\n&output file = 'out/study.h5', quiet = .true. /\n")


def test_static_link_gives_the_results_of_the_dynamic_build(release_exe, tmp_path):
    try:
        with build_lock():     # fpm in this checkout, as the session's builds
            exe, words = builds.build(ROOT, "")
        static = builds.link_static(ROOT, words, tmp_path / "static" / "supratrans")
    except builds.PlotError as exc:
        pytest.skip(exc.line())
    assert exe.read_bytes() == release_exe.read_bytes()      # the session's release build (a copy of it)
    libs = subprocess.run(["ldd", str(static)], capture_output=True, text=True).stdout
    assert "hdf5" not in libs and "lapack" not in libs and "gfortran" not in libs, libs
    for i, text in enumerate(PAPER_RUNS):
        identical(run(release_exe, text, tmp_path / f"dynamic{i}"), run(static, text, tmp_path / f"static{i}"))
