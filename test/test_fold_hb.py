"""The continuation scene with `solver = 'harmonic_balance'` against the time domain (issue 41).

Harmonic balance gives the ODE's fold with no dt. Two methods of the code give it otherwise, on a 40-site chain
(N0 = 30, the paper's absorber shape) at Omega = 0.5, 0.7, 0.9:
- Newton-shooting with rk8 at dt ~ 0.05, whose eighth-order error is ~1e-11 there: the same fold to 1e-7;
- Newton-shooting with the paper's scheme at dt and dt/2, extrapolated in dt (the scene's `/convergence/richardson`):
  the same fold to 1e-5 (the extrapolation's O(dt^4) remainder).
The release build runs them (the numerics, not the checks of the debug build, are under test here). The file's own
checks are asserted too: one rk8 period from the fold's state closes to 1e-9, K converged the fold to
harmonics_tol, the absorber family and the radiation closure agree where the far field is linear (Omega = 0.9), and
the continuum limit is extrapolated from c = 4 and 8.
"""
from __future__ import annotations

import subprocess

import h5py
import numpy as np
import pytest

CHAIN = "&chain potential = 'sine-gordon', c = {c}, n = {n}, n0 = {n0}, sigma = 3.0 /\n"
SCENE = """&numerics method = '{method}', dt = 0.05 /
&scene kind = 'continuation', solver = '{solver}', omega_min = {omega_min}, omega_max = {omega_max},
  omega_step = 0.2, amplitude_max = 7.0, floquet_every = {floquet}, beyond_fold = 0, fold_convergence = {convergence},
  continuation_step_max = {step_max} {extra} /
&output file = '{out}', quiet = .true. /
"""


def run_scene(exe: str, folder, name: str, *, solver: str, method: str = "rk8", convergence: bool = False,
              n: int = 40, n0: int = 30, c: float = 4.0, omega_min: float = 0.5, omega_max: float = 0.9,
              step_max: float = 0.2, floquet: int = 0, extra: str = "") -> h5py.File:
    """Run one continuation namelist in `folder` and open its file."""
    out = folder / f"{name}.h5"
    text = CHAIN.format(c=c, n=n, n0=n0) + SCENE.format(
        method=method, solver=solver, convergence=".true." if convergence else ".false.", omega_min=omega_min,
        omega_max=omega_max, step_max=step_max, floquet=floquet, extra=extra, out=out)
    (folder / f"{name}.nml").write_text(text)
    proc = subprocess.run([exe, str(folder / f"{name}.nml")], capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return h5py.File(out)


@pytest.fixture(scope="module")
def hb_file(release_exe, tmp_path_factory):
    """The harmonic-balance folds of the 40-site chain at Omega = 0.5, 0.7, 0.9."""
    folder = tmp_path_factory.mktemp("hb")
    with run_scene(str(release_exe), folder, "hb", solver="harmonic_balance", step_max=1.0, floquet=1) as f:
        yield {k: f[k][()] for k in ("fold_amplitude", "status", "harmonics", "fold_period_closure",
                                       "convergence/harmonics_error", "fold_multiplier_excess", "omega",
                                       "branch/amplitude", "branch/points", "spectrum", "multipliers/real")}


@pytest.mark.slow   # rk8 shooting's tangent through a period, ~20 s
def test_hb_fold_is_rk8_shootings(release_exe, tmp_path, hb_file):
    with run_scene(str(release_exe), tmp_path, "rk8", solver="shooting", method="rk8") as f:
        shooting = f["fold_amplitude"][0]
    hb = hb_file["fold_amplitude"][0]
    print("harmonic balance", hb.tolist(), "rk8 shooting", shooting.tolist(), "differences", (hb - shooting).tolist())
    assert np.all(hb_file["status"] == 0)
    assert np.all(np.abs(hb - shooting) < 1e-7)


def test_hb_fold_is_the_richardson_value_of_the_scheme(release_exe, tmp_path, hb_file):
    with run_scene(str(release_exe), tmp_path, "newton", solver="shooting", method="newton", convergence=True) as f:
        richardson = f["convergence/richardson"][0]
        at_dt = f["fold_amplitude"][0]
    hb = hb_file["fold_amplitude"][0]
    print("harmonic balance", hb.tolist(), "Richardson", richardson.tolist(), "scheme at dt", at_dt.tolist())
    assert np.all(np.abs(hb - richardson) < 1e-5)
    # and the scheme at dt alone is visibly not the ODE's fold: the extrapolation is what agrees
    assert np.max(np.abs(hb - at_dt)) > 1e-5


def test_hb_file_checks_itself(hb_file):
    # the fold's state is a periodic orbit of the ODE: one rk8 period from it returns to it
    assert np.all(hb_file["fold_period_closure"] < 1e-9)
    assert np.all(hb_file["convergence/harmonics_error"] <= 1e-9)
    # K grows as Omega falls (the fold's state is sharper)
    k = hb_file["harmonics"][0]
    assert k[0] > k[-1] >= 3
    # the branch climbs from rest to the fold, its largest amplitude (traced with the first K: the fold there moves
    # by the truncation of that K, < 1e-4, on the way to the converged one)
    pts = hb_file["branch/points"][0]
    for i in range(len(pts)):
        a = hb_file["branch/amplitude"][0, i, :pts[i]]
        assert a[0] == 0.0
        assert np.all(np.diff(a) > -1e-10)
        assert np.nanmax(a) == pytest.approx(hb_file["fold_amplitude"][0, i], abs=1e-4)
    # one multiplier of the rk8 monodromy at the fold is +1 (the fold's own)
    mult = hb_file["multipliers/real"][0]
    assert np.all(np.min(np.abs(mult - 1.0), axis=1) < 1e-3)
    # the spectrum: the first harmonic at site 1 is near the drive, the harmonics past K are NaN
    spec = hb_file["spectrum"][0]
    assert spec.shape[1] == 8
    assert np.all(spec[:, 0, 0] > 0.5)


def test_absorber_family_radiation_and_continuum(release_exe, tmp_path):
    # the paper's chain at Omega = 0.9, where the far field is linear: the fold moves by < 1e-5 with the absorber,
    # and the core closed by the radiation condition gives the longest absorber's fold
    with run_scene(str(release_exe), tmp_path, "family", solver="harmonic_balance", n=200, n0=150, omega_min=0.9, omega_max=0.9,
                   step_max=1.0, extra=", absorber_family = 1, c_values = 4.0, 8.0") as f:
        fold = f["fold_amplitude"][0, 0]
        spread = f["convergence/absorber_spread"][0, 0]
        semi = f["convergence/fold_semi_infinite"][0, 0]
        radiation = f["convergence/fold_radiation"][0, 0]
        far = f["convergence/far_field_umax"][0, 0]
        folds_c = f["continuum/folds"][0, 0]
        limit = f["continuum/fold"][0, 0]
        a_s = f["threshold_As"][0, 0]
    print(f"fold {fold!r}, spread {spread:.2e}, semi-infinite {semi!r}, radiation {radiation!r}, far field {far:.3f}, "
          f"c = 4, 8: {folds_c.tolist()}, limit {limit!r}, A_s {a_s!r}")
    assert 0 < spread < 1e-5
    assert far < 0.05
    assert abs(radiation - semi) < 1e-6
    assert folds_c[0] == pytest.approx(fold, abs=1e-9)          # c = 4 is the chain of the input
    assert limit == pytest.approx(folds_c[1] + (folds_c[1] - folds_c[0]) / 3, abs=1e-12)


@pytest.mark.slow   # rk8 shooting with the multipliers at every point, ~35 s
def test_hb_stability_brackets_shootings_first_loss(release_exe, tmp_path, hb_file):
    # the rk8 multipliers at the harmonic-balance branch's points bracket the first loss of stability that rk8
    # shooting locates on the same chain, with the same type (0.5: a real multiplier through +1, 0.7: a torus); at
    # 0.9 the branch stays stable up to the fold (shooting's loss is the fold itself)
    with run_scene(str(release_exe), tmp_path, "rk8stab", solver="shooting", method="rk8", floquet=1) as f:
        loss = f["instability_amplitude"][0]
        kind = f["instability_type"][0]
    with run_scene(str(release_exe), tmp_path, "hbstab", solver="harmonic_balance", step_max=0.5, floquet=1) as f:
        upper = f["instability_amplitude"][0]
        lower = f["instability_lower"][0]
        hb_kind = f["instability_type"][0]
        fold = f["fold_amplitude"][0]
        stable = f["branch/stable"][0]
    print("shooting", loss.tolist(), kind.tolist(), "harmonic balance", lower.tolist(), upper.tolist(), hb_kind.tolist())
    for i in (0, 1):
        assert lower[i] < loss[i] <= upper[i]
        assert hb_kind[i] == kind[i]
    assert np.isnan(upper[2]) and loss[2] == pytest.approx(fold[2], abs=1e-8)
    assert np.all(stable[2][stable[2] >= 0] == 1)
