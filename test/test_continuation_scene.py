"""The continuation scene as a user drives it: a fold line identical for 1 and 2 threads and for a sliced run
merged (with the Floquet stability along the branch, and for the fold alone), the statuses and codes of its file, and one clear line (exit 2, nothing written) for each input that has no
periodic state to continue."""
import os
import subprocess

import h5py
import numpy as np
import pytest

import compare_results

FOLD = """&chain n = 30, n0 = 22 /
&numerics dt = 0.1 /
&scene kind = 'continuation', omega_min = 0.7, omega_max = 0.8, omega_step = 0.1, amplitude_max = 4.0,
  fold_convergence = .false., potentials = 'sine-gordon', 'klein-gordon' /
&output file = 'out/fold.h5', quiet = .true. /
"""


@pytest.fixture(scope="module")
def rel(release_exe):
    """The release build (what make_figures.py runs), for the runs that continue branches and check them against
    slow ramps (marked slow): 9 times faster than the debug build, whose run-time checks cover the same code in the
    Fortran suite (test/test_continuation*.pf, on smaller cases) and the bad inputs here."""
    return str(release_exe)


def sh(exe, *args, cwd, threads=1, check=True):
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    proc = subprocess.run([exe, *map(str, args)], cwd=cwd, capture_output=True, text=True, timeout=600, env=env)
    if check:
        assert proc.returncode == 0, proc.stderr
    return proc


@pytest.fixture(scope="module")
def fold_line(rel, tmp_path_factory):
    """The fold line of FOLD computed with one thread: the folder it lives in."""
    tmp = tmp_path_factory.mktemp("fold")
    (tmp / "fold.nml").write_text(FOLD)
    sh(rel, "fold.nml", cwd=tmp)
    return tmp


@pytest.mark.slow
def test_fold_line_has_folds_with_their_stability(fold_line):
    with h5py.File(fold_line / "out" / "fold.h5") as f:
        assert f.attrs["scene"] == b"continuation"
        status = f["status"][()]
        fold = f["fold_amplitude"][()]
        assert status.shape == (2, 2)
        assert (status == 0).all(), status
        # a fold where the branch turns: the amplitude of the points past it falls back below A_f
        points = f["branch/points"][()]
        amp = f["branch/amplitude"][()]
        for c in range(2):
            for w in range(2):
                a = amp[c, w, : points[c, w]]
                assert a.max() == pytest.approx(fold[c, w], abs=1e-6)
                assert a[-1] < fold[c, w] - 1e-4
        assert np.all(f["fold_residual"][()] < 1e-8)
        # the model's threshold is the smaller of the fold and the first loss of stability, and says which
        thr = f["threshold"][()]
        inst = f["instability_amplitude"][()]
        assert np.all(thr <= fold + 1e-12)
        assert np.all((thr == fold) | (thr == inst))
        assert "torus" in f["instability_type"].attrs["codes"].decode()
        assert f["dt_used"][0, 0] <= 0.1 and f["steps_per_period"][0, 0] == np.ceil(2 * np.pi / 0.7 / 0.1)
        # every fold has its fate, coded, with the time it took (or the time watched)
        fate = f["fold_fate"][()]
        assert np.isin(fate, (1, 2)).all(), fate
        assert np.all(f["fold_fate_time"][()] > 0)
        assert "localized" in f["fold_fate"].attrs["codes"].decode()
        # a fold that transmits is the transmission fold, reached on the first branch
        trans = f["transmission_fold"][()]
        first = fate == 1
        np.testing.assert_array_equal(trans[first], fold[first])
        assert (f["branches"][()][first] == 1).all() and (f["transmission_status"][()][first] == 0).all()


@pytest.mark.slow
def test_fold_line_is_the_same_for_two_threads_and_for_slices(rel, fold_line, tmp_path):
    (tmp_path / "fold.nml").write_text(FOLD)
    sh(rel, "fold.nml", cwd=tmp_path, threads=2)
    diffs, compared, _ = compare_results.compare(fold_line / "out" / "fold.h5", tmp_path / "out" / "fold.h5")
    assert compared > 10 and not diffs, diffs
    (tmp_path / "out" / "fold.h5").unlink()
    for i in (1, 2, 3):
        sh(rel, "fold.nml", "--slice", f"{i}/3", cwd=tmp_path)
    parts = sorted((tmp_path / "out").glob("fold.part-*.h5"))
    assert len(parts) == 3
    sh(rel, "merge", *parts, cwd=tmp_path)
    diffs, compared, _ = compare_results.compare(fold_line / "out" / "fold.h5", tmp_path / "out" / "fold.h5")
    assert compared > 10 and not diffs, diffs


@pytest.mark.slow
def test_the_fold_alone_is_the_same_for_two_threads_and_for_slices(rel, tmp_path):
    """floquet_every = 0, where a period of an even number of steps (Omega = 0.7: M = 90; 0.8: M = 79) has its
    branch from rest continued on the half-period map: the same file for 1 and 2 threads and for a sliced run."""
    text = FOLD.replace("fold_convergence", "floquet_every = 0, fold_convergence")
    one = _same_for_threads_and_slices(rel, tmp_path, text)
    with h5py.File(one) as f:
        assert sorted(f["steps_per_period"][0, :] % 2) == [0, 1]


@pytest.mark.slow
def test_the_switch_past_a_branch_point_is_the_same_for_two_threads_and_for_slices(rel, tmp_path):
    """The chain of SYMMETRY at Omega = 0.38, 0.40, 0.42, where the fold line switches branch at a branch point
    below the fold (once supercritical, twice subcritical): the same file for 1 and 2 threads and for a sliced run."""
    one = _same_for_threads_and_slices(rel, tmp_path, SYMMETRY.replace(
        "omega_min = 0.4, omega_max = 0.5, omega_step = 0.05", "omega_min = 0.38, omega_max = 0.42, omega_step = 0.02"))
    with h5py.File(one) as f:
        np.testing.assert_array_equal(f["branch_switch"][0], [1, 2, 2])


def _same_for_threads_and_slices(rel, tmp_path, text):
    """The fold line of `text` with 1 and 2 threads and in 3 slices merged: the same file (its path returned)."""
    one, two, sliced = (tmp_path / name for name in ("one", "two", "sliced"))
    for folder, threads in ((one, 1), (two, 2)):
        folder.mkdir()
        (folder / "fold.nml").write_text(text)
        sh(rel, "fold.nml", cwd=folder, threads=threads)
    sliced.mkdir()
    (sliced / "fold.nml").write_text(text)
    for i in (1, 2, 3):
        sh(rel, "fold.nml", "--slice", f"{i}/3", cwd=sliced)
    sh(rel, "merge", *sorted((sliced / "out").glob("fold.part-*.h5")), cwd=sliced)
    for other in (two, sliced):
        diffs, compared, _ = compare_results.compare(one / "out" / "fold.h5", other / "out" / "fold.h5")
        assert compared > 10 and not diffs, diffs
    return one / "out" / "fold.h5"


@pytest.mark.slow
def test_the_fold_alone_is_the_same_fold_without_stability(rel, fold_line, tmp_path):
    """floquet_every = 0: the same folds (to the location tolerance) and fates, no multipliers along the branch; the
    sign of det(J + I) watched along it does not change (no real multiplier through -1), so no first loss of
    stability: the threshold is the fold; one eigenvalue call a fold (the first branch's and those of the branches
    followed past a fold where the chain stays localized), fewer than along the whole branch."""
    (tmp_path / "fold.nml").write_text(FOLD.replace("fold_convergence", "floquet_every = 0, fold_convergence"))
    sh(rel, "fold.nml", cwd=tmp_path)
    with h5py.File(fold_line / "out" / "fold.h5") as full, h5py.File(tmp_path / "out" / "fold.h5") as alone:
        assert (alone["status"][()] == 0).all()
        np.testing.assert_allclose(alone["fold_amplitude"][()], full["fold_amplitude"][()], rtol=0, atol=1e-8)
        np.testing.assert_array_equal(alone["fold_fate"][()], full["fold_fate"][()])
        assert np.isnan(alone["instability_amplitude"][()]).all() and np.isnan(alone["instability_lower"][()]).all()
        np.testing.assert_array_equal(alone["threshold"][()], alone["fold_amplitude"][()])
        np.testing.assert_array_equal(alone["cost/eigen_calls"][()], alone["branches"][()])
        assert (full["cost/eigen_calls"][()] > alone["cost/eigen_calls"][()]).all()
        stable = alone["branch/stable"][()]
        points = alone["branch/points"][()]
        amp = alone["branch/amplitude"][()]
        for c in range(2):
            for w in range(2):
                verdict = stable[c, w, : points[c, w]] >= 0                  # only the fold point has a verdict
                assert verdict.sum() == 1 and amp[c, w, : points[c, w]][verdict][0] == alone["fold_amplitude"][c, w]


SYMMETRY = """&chain c = 2, n = 30, n0 = 20, sigma = 2 /
&numerics dt = 0.1 /
&scene kind = 'continuation', omega_min = 0.4, omega_max = 0.5, omega_step = 0.05, amplitude_max = 7,
  floquet_every = 0, continuation_step_max = 0.5, beyond_fold = 0, fold_convergence = .false. /
&output file = 'out/fold.h5', quiet = .true. /
"""


@pytest.mark.slow
def test_the_fold_alone_sees_the_symmetry_break_before_the_fold(rel, tmp_path):
    """On this short chain (M = 158, 140, 126: all even, the branch on the half-period map G) the symmetric branch
    loses its stability before its fold: a real multiplier of G through -1, which is P's through +1 where the branch
    does not turn (the half-period symmetry breaks). The fold alone sees it by the sign of det(J + I) and locates it;
    the full Floquet path on P (multipliers at every point, an independent computation) puts the same loss between
    its last stable and first unstable points and locates it at the same amplitude, and the threshold is that loss,
    called a real multiplier through +1."""
    for name, text in (("alone", SYMMETRY), ("full", SYMMETRY.replace("floquet_every = 0", "floquet_every = 1"))):
        (tmp_path / name).mkdir()
        (tmp_path / name / "fold.nml").write_text(text)
        sh(rel, "fold.nml", cwd=tmp_path / name)
    with h5py.File(tmp_path / "alone/out/fold.h5") as alone, h5py.File(tmp_path / "full/out/fold.h5") as full:
        assert (alone["steps_per_period"][()] % 2 == 0).all()
        assert (alone["status"][()] == 0).all()
        inst = alone["instability_amplitude"][0]
        assert (alone["instability_type"][()] == 1).all() and (full["instability_type"][()] == 1).all()
        assert (inst < alone["fold_amplitude"][0] - 0.5).all()
        np.testing.assert_array_equal(alone["threshold"][0], inst)
        np.testing.assert_array_equal(alone["threshold_kind"][0], [1, 1, 1])
        for w in range(3):
            n = full["branch/points"][0, w]
            amp = full["branch/amplitude"][0, w, :n]
            stable = full["branch/stable"][0, w, :n]
            first = np.argmax(stable == 0)
            assert first > 0 and (stable[:first] == 1).all()
            assert amp[first - 1] < inst[w] <= amp[first] + 1e-9, (w, amp[first - 1], inst[w], amp[first])
        # both locate it (the full path by its secant on the multipliers, or at 0.45, where that fails at the branch
        # point, by bisection on the bordered determinant's sign): the same crossing
        np.testing.assert_allclose(inst, full["instability_amplitude"][0], rtol=0, atol=1e-6)
        # located: the bracket's lower end is the loss itself
        for f in (alone, full):
            np.testing.assert_allclose(f["instability_lower"][0], f["instability_amplitude"][0], rtol=0, atol=1e-9)


SLOW_RAMP = """&chain c = 2, n = 30, n0 = 20, sigma = 2 /
&drive ramp_time = 2000.0 /
&numerics dt = 0.1, t_final = 3000.0 /
&scene kind = 'bifurcation', omega_min = 0.38, omega_max = 0.42, omega_step = 0.02, amplitude_min = 3.0,
  amplitude_max = 6.0, coarse_step = 0.1, resolution = 0.01, screen_method = 'none' /
&output file = 'out/scan.h5', quiet = .true. /
"""


@pytest.mark.slow
def test_past_a_branch_point_the_chain_transmits_where_a_slow_ramp_does(rel, tmp_path):
    """On the chain of SYMMETRY the half-period symmetry breaks at a branch point below the symmetric branch's fold
    (0.6 .. 0.8 below it). At Omega = 0.38 the other branch leaves it above its amplitude (supercritical:
    /branch_switch 1) and folds just above it; there the chain transmits (/transmission_fold, a second branch). At
    0.40 and 0.42 it leaves below (subcritical: 2), and driven 1% past the branch point the chain transmits, so
    /transmission_fold is the branch point. Checked against an independent protocol, the scan with a slow ramp
    (2000 time units, 1000 more at full amplitude): its threshold is /transmission_fold to its resolution (the first
    amplitude at or above it that transmits in that time), 0.6 below the symmetric fold the fold line gave before
    the branch was switched."""
    (tmp_path / "fold.nml").write_text(SYMMETRY.replace("omega_min = 0.4, omega_max = 0.5, omega_step = 0.05",
                                                        "omega_min = 0.38, omega_max = 0.42, omega_step = 0.02"))
    (tmp_path / "scan.nml").write_text(SLOW_RAMP)
    sh(rel, "fold.nml", cwd=tmp_path)
    sh(rel, "scan.nml", cwd=tmp_path)
    with h5py.File(tmp_path / "out/fold.h5") as fold, h5py.File(tmp_path / "out/scan.h5") as scan:
        np.testing.assert_allclose(fold["omega"][()], scan["omega"][()], rtol=0, atol=1e-12)
        np.testing.assert_array_equal(fold["branch_switch"][0], [1, 2, 2])
        assert b"subcritical" in fold["branch_switch"].attrs["codes"]
        np.testing.assert_array_equal(fold["threshold_kind"][0], [1, 1, 1])
        threshold, transmission = fold["threshold"][0], fold["transmission_fold"][0]
        assert (threshold < fold["fold_amplitude"][0] - 0.5).all()
        np.testing.assert_array_equal(fold["transmission_status"][0], [0, 0, 0])
        # supercritical: the other branch's fold, above the branch point and far below the symmetric fold
        assert threshold[0] < transmission[0] < threshold[0] + 0.01 and fold["branches"][0, 0] >= 2
        np.testing.assert_array_equal(transmission[1:], threshold[1:])
        ramp = scan["threshold"][0]
        assert ((transmission <= ramp) & (ramp <= transmission + 0.02)).all(), (ramp, transmission)


TORUS = """&chain c = 4, n = 90, n0 = 30, sigma = 10 /
&numerics dt = 0.05 /
&scene kind = 'continuation', omega_min = 0.35, omega_max = 0.35, omega_step = 0.01, amplitude_max = 7,
  floquet_every = 0, continuation_step_max = 0.5, beyond_fold = 0, fold_convergence = .false. /
&output file = 'out/fold.h5', quiet = .true. /
"""

TORUS_RAMP = """&chain c = 4, n = 90, n0 = 30, sigma = 10 /
&drive ramp_time = 2000.0 /
&numerics dt = 0.05, t_final = 3000.0 /
&scene kind = 'bifurcation', omega_min = 0.35, omega_max = 0.35, omega_step = 0.01, amplitude_min = 4.5,
  amplitude_max = 5.5, coarse_step = 0.1, resolution = 0.01, screen_method = 'none' /
&output file = 'out/scan.h5', quiet = .true. /
"""


@pytest.mark.slow
def test_past_a_torus_the_chain_transmits_where_a_slow_ramp_does(rel, tmp_path):
    """On a 90-site chain at Omega = 0.35 the branch from rest loses its stability to a torus (a complex pair of
    multipliers leaves the unit circle) 0.8 below its fold. No branch of periodic states leaves there; the chain,
    driven up in stairs from the torus's state (/branch_switch 4), transmits on a stair between the two, and the
    scan with a slow ramp (2000 time units from rest, 1000 more at full amplitude), an independent protocol, gives
    that amplitude to within its resolution and the stair's height. (The fold's own fate is to transmit: before the
    stairs, /transmission_fold was the fold, 0.76 above the ramp.)"""
    (tmp_path / "fold.nml").write_text(TORUS)
    (tmp_path / "scan.nml").write_text(TORUS_RAMP)
    sh(rel, "fold.nml", cwd=tmp_path)
    sh(rel, "scan.nml", cwd=tmp_path)
    with h5py.File(tmp_path / "out/fold.h5") as fold, h5py.File(tmp_path / "out/scan.h5") as scan:
        assert fold["threshold_kind"][0, 0] == 3 and fold["branch_switch"][0, 0] == 4
        assert b"stairs" in fold["branch_switch"].attrs["codes"]
        torus, top, transmission = (fold[name][0, 0] for name in ("threshold", "fold_amplitude", "transmission_fold"))
        assert fold["transmission_status"][0, 0] == 0 and fold["fold_fate"][0, 0] == 1
        assert fold["transmission_stairs"][0, 0] == 1
        assert torus < transmission < top - 0.5, (torus, transmission, top)
        ramp = scan["threshold"][0, 0]
        assert abs(ramp - transmission) <= 0.02, (ramp, transmission)
        _check_spread(fold["transmission_spread"][0, 0], transmission, torus)


def _check_spread(spread, transmission, start):
    """A stair's spread: a whole number of stairs (both climbs stand on the grid start + k 0.01), at most as far as
    the first climb went above its start plus one stair (the second climb's bound)."""
    stairs = spread / 0.01
    assert np.isfinite(spread) and abs(stairs - round(stairs)) < 1e-6, spread
    assert 0.0 <= spread <= transmission - start + 0.01 + 1e-9, (spread, transmission, start)


@pytest.mark.slow
def test_the_stairs_past_a_torus_are_the_same_for_two_threads_and_for_slices(rel, tmp_path):
    """The chain of TORUS at Omega = 0.35 (stairs past a torus) and 0.36 (a branch point): the same file for 1 and 2
    threads and for a sliced run."""
    one = _same_for_threads_and_slices(rel, tmp_path, TORUS.replace("omega_max = 0.35", "omega_max = 0.36"))
    with h5py.File(one) as f:
        np.testing.assert_array_equal(f["branch_switch"][0], [4, 1])
        assert np.isfinite(f["transmission_spread"][0, 0]) and np.isnan(f["transmission_spread"][0, 1])


@pytest.mark.parametrize("old,new,words", [
    ("dt = 0.1", "method = 'rk4', dt = 0.4, allow_unstable = .true.", "linear stability limit"),
    ("omega_min = 0.7", "omega_min = 0.0", "omega_min"),
    ("n = 30, n0 = 22", "n = 20000, n0 = 15000", "dense shooting matrices"),
    ("n = 30, n0 = 22", "c = 4.0", "say chain = 'short' for that (the old behaviour) or chain = 'input'"),
    ("fold_convergence = .false.", "fold_convergence = .false., short_sigma_min = 30.0", "short_sigma_max = 20"),
    ("fold_convergence = .false.", "fold_convergence = .false., continuation_slow_iter = 2, continuation_fast_iter = 2",
     "continuation_slow_iter = 2: must be > continuation_fast_iter = 2"),
    ("fold_convergence = .false.", "fold_convergence = .false., continuation_step_min = 0.1",
     "continuation_step_min = 0.1: must be <= continuation_step = 0.05"),
], ids=["dt beyond stability", "omega zero", "dense system too large", "old rule of the short chain",
        "short sigma range", "slow not above fast", "smallest step above the first"])
def test_no_periodic_state_is_one_line_and_nothing_written(exe, tmp_path, old, new, words):
    assert old in FOLD
    (tmp_path / "bad.nml").write_text(FOLD.replace(old, new))
    proc = sh(exe, "bad.nml", cwd=tmp_path, check=False)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and words in lines[0], proc.stderr
    assert not (tmp_path / "out" / "fold.h5").exists()


def test_the_short_chain_is_a_choice_the_input_names(exe, tmp_path):
    """A fold line without n, n0, sigma: refused in one line naming the new spelling (above); with chain = 'short'
    or 'input' named it is accepted (--check)."""
    for chain in ("short", "input"):
        text = FOLD.replace("n = 30, n0 = 22", "c = 4.0")
        text = text.replace("amplitude_max = 4.0,", f"amplitude_max = 4.0, chain = '{chain}',")
        (tmp_path / f"{chain}.nml").write_text(text)
        proc = sh(exe, "--check", f"{chain}.nml", cwd=tmp_path, check=False)
        assert proc.returncode == 0, proc.stderr


RESONANT = """&chain n = 90, n0 = 30, sigma = 6.0 /
&numerics dt = 0.05 /
&scene kind = 'continuation', omega_min = 0.34, omega_max = 0.34, amplitude_max = 7.0, continuation_step_max = 0.4,
  fold_convergence = .false. /
&output file = 'out/resonant.h5', quiet = .true. /
"""


RESONANT_RAMP = """&chain n = 90, n0 = 30, sigma = 6.0 /
&drive ramp_time = 2000.0 /
&numerics dt = 0.05, t_final = 3000.0 /
&scene kind = 'bifurcation', omega_min = 0.34, omega_max = 0.34, omega_step = 0.01, amplitude_min = 3.0,
  amplitude_max = 6.0, coarse_step = 0.1, resolution = 0.01, screen_method = 'none' /
&output file = 'out/scan.h5', quiet = .true. /
"""


@pytest.mark.slow
def test_a_fold_at_a_harmonic_resonance_is_not_called_the_transmission_threshold(rel, tmp_path):
    """Omega = 0.34 (3 Omega at the band edge) on a short chain: the branch folds, but the chain driven 1% past the
    fold stays localized for the whole watch; the scene follows the branch it settles on, and where the chain
    then settles on no stable periodic state it drives the chain itself up in stairs from there
    (/transmission_stairs 1). The stair where it transmits is 1.4 above the fold, and the scan with a slow ramp
    (2000 time units from rest, 1000 more at full amplitude), an independent protocol, transmits within 0.05 of it
    (0.04 below). Before the stairs, /transmission_fold was NaN here."""
    (tmp_path / "r.nml").write_text(RESONANT)
    (tmp_path / "s.nml").write_text(RESONANT_RAMP)
    sh(rel, "r.nml", cwd=tmp_path)
    sh(rel, "s.nml", cwd=tmp_path)
    with h5py.File(tmp_path / "out" / "resonant.h5") as f, h5py.File(tmp_path / "out" / "scan.h5") as scan:
        assert f["status"][0, 0] == 0
        assert f["fold_fate"][0, 0] == 2
        assert f["fold_fate_time"][0, 0] >= 1000.0
        assert f["branches"][0, 0] >= 2
        assert f["transmission_status"][0, 0] == 0 and f["transmission_stairs"][0, 0] == 1
        assert f["branch_switch"][0, 0] == 0
        transmission = f["transmission_fold"][0, 0]
        assert transmission > f["fold_amplitude"][0, 0] + 1.0
        _check_spread(f["transmission_spread"][0, 0], transmission, f["fold_amplitude"][0, 0])
        assert abs(scan["threshold"][0, 0] - transmission) <= 0.05, (scan["threshold"][0, 0], transmission)
