"""An independent check of the continuation scene's fold with AUTO-07p (issue 25).

AUTO-07p (Debian package `auto-07p`, installed by .ci/install) continues the periodic orbits of the method-of-lines
ODE of a short chain (test/auto/mol.f90.in: the ODE of src/numerics/supratrans_mol.f90, the drive made autonomous by
the oscillator whose limit cycle is (sin Omega t, cos Omega t)) by orthogonal collocation from A = 0 to its first
fold (LP), with test/auto/run_mol.py in a temporary folder. The scene then has to find the same fold:

- with `method = 'rk8'` at dt ~ 0.05 (its eighth-order error is ~1e-11 there) to 1e-5, with the Floquet stability
  along the branch and for the fold alone (`floquet_every = 0`, M = 140 even: the branch on the half-period map);
- with the paper's Newton scheme, second order in dt: its folds at dt = 0.05 and dt/2 (the scene's own
  `/convergence/fold_half_dt`) approach AUTO's with the observed order 2, and their Richardson extrapolation (the
  scene's `/convergence/richardson`) removes that dt^2 error down to its O(dt^4) remainder. That remainder, relative
  to the dt^2 error at dt/2, is O((dt/2)^2) ~ 6e-4 (measured: 9e-4, 1.4e-3); the test asks for less than 1e-2 of it.

The chain: 10 sites with a 4-site absorber (N0 = 6, kappa = 0.5, sigma = 1), sine-Gordon, c = 4, Omega = 0.9,
undamped, and again with every term of the ODE on (gamma = 0.01, beta = 0.05, m^2 = 0.1). There the branch has a
clean fold (A_f = 3.1015143811 undamped: the short chain's own; the scene gives 1.99 for 20 sites). AUTO's fold
does not move with its mesh (NTST = 20, 40, 80 agree to 3e-9) and its period stays 2 pi / Omega. Where AUTO-07p (or
gfortran, which compiles its equations) is missing the test is skipped, with the reason in the warnings summary.
Marked `slow`: per chain AUTO's compile and run and two scene runs, ~30 s on a loaded machine.
"""
from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import h5py
import pytest

# end-to-end runs of an outside tool whose equations gfortran compiles, and of the scene (~1 minute, loaded machine)
pytestmark = pytest.mark.slow

HERE = Path(__file__).resolve().parent
RUN_MOL = HERE / "auto" / "run_mol.py"

#: The chains of the check (the keys of run_mol.py; SCENE writes the same chain): undamped, and with every term of
#: the ODE on (gamma, beta, m^2).
CASES = {
    "undamped": {"n": 10, "n0": 6, "c": 4.0, "kappa": 0.5, "sigma": 1.0, "omega": 0.9, "potential": 1},
    "damped": {"n": 10, "n0": 6, "c": 4.0, "kappa": 0.5, "sigma": 1.0, "omega": 0.9, "potential": 1,
               "gamma": 0.01, "beta": 0.05, "m2": 0.1},
}
SCENE = """&chain potential = 'sine-gordon', n = {n}, n0 = {n0}, c = {c}, kappa = {kappa}, sigma = {sigma},
  gamma = {gamma}, beta = {beta}, m2 = {m2} /
&drive omega = {omega} /
&numerics method = '{method}', dt = {dt} /
&scene kind = 'continuation', omega_min = {omega}, omega_max = {omega}, omega_step = 0.1, amplitude_max = 4.0,
  fold_convergence = {convergence}, potentials = 'sine-gordon', floquet_every = {floquet_every}, solver = '{solver}' /
&output file = 'fold.h5', quiet = .true. /
"""
#: The Newton scheme's dt (dt/2 is the scene's own convergence run).
NEWTON_DT = 0.05


def auto_missing() -> str | None:
    """Why AUTO-07p cannot run here, or None when it can."""
    auto_dir = Path(os.environ.get("AUTO_DIR", "/usr/lib/auto-07p"))
    if not (auto_dir / "python" / "auto" / "__init__.py").is_file():
        return f"AUTO-07p is not installed (no {auto_dir}/python/auto; Debian: apt-get install auto-07p)"
    if shutil.which("gfortran") is None:
        return "gfortran (which compiles AUTO's equations file) is not installed"
    return None


@pytest.fixture(scope="module", params=list(CASES))
def case(request: pytest.FixtureRequest) -> dict:
    """One chain of CASES."""
    return CASES[request.param]


@pytest.fixture(scope="module")
def auto_fold(case: dict, tmp_path_factory: pytest.TempPathFactory) -> dict:
    """AUTO-07p's fold of `case` (run_mol.py's JSON: amplitude, period, points, seconds), computed in a temporary
    folder."""
    reason = auto_missing()
    if reason is not None:
        warnings.warn(f"AUTO-07p check not run: {reason}", stacklevel=1)
        pytest.skip(reason)
    work = tmp_path_factory.mktemp("auto")
    env = dict(os.environ, OMP_NUM_THREADS="1")
    proc = subprocess.run([sys.executable, str(RUN_MOL), str(work / "run"), json.dumps(case)], capture_output=True,
                          text=True, timeout=600, env=env, cwd=work)
    assert proc.returncode == 0, (proc.stdout + proc.stderr)[-3000:]
    result = json.loads(proc.stdout.strip().splitlines()[-1])
    print(f"AUTO-07p: fold A_f = {result['amplitude']!r} (point {result['point']} of {result['points']}), "
          f"period {result['period']!r}, {result['seconds']:.1f} s")
    return result


def scene_fold(exe: str, folder: Path, case: dict, method: str, dt: float, convergence: bool,
               floquet_every: int = 4, solver: str = "shooting") -> h5py.File:
    """The continuation scene's file for `case` with `method` at `dt` (fold_convergence and floquet_every as asked),
    opened."""
    folder.mkdir(parents=True, exist_ok=True)
    chain = {"gamma": 0.0, "beta": 0.0, "m2": 0.0} | case
    (folder / "case.nml").write_text(SCENE.format(method=method, dt=dt, **chain, floquet_every=floquet_every,
                                                  convergence=".true." if convergence else ".false.", solver=solver))
    proc = subprocess.run([exe, "case.nml"], cwd=folder, capture_output=True, text=True, timeout=600,
                          env=dict(os.environ, OMP_NUM_THREADS="1"))
    assert proc.returncode == 0, proc.stderr[-3000:]
    f = h5py.File(folder / "fold.h5")
    assert f["status"][0, 0] == 0, f["status"][()]
    assert f["fold_residual"][0, 0] < 1e-8
    return f


def test_auto_keeps_the_period_of_the_drive(case, auto_fold):
    # the oscillator's cycle holds AUTO's free period at 2 pi / Omega: AUTO continued the driven orbits
    assert auto_fold["period"] == pytest.approx(2 * math.pi / case["omega"], abs=1e-8)
    assert 0.5 < auto_fold["amplitude"] < 4.0


def test_rk8_scene_finds_autos_fold(case, auto_fold, exe, tmp_path):
    with scene_fold(exe, tmp_path, case, "rk8", 0.05, False) as f:
        fold = float(f["fold_amplitude"][0, 0])
        print(f"rk8 scene (dt {float(f['dt_used'][0, 0])!r}): A_f = {fold!r}, "
              f"AUTO - rk8 = {auto_fold['amplitude'] - fold:.2e}")
        assert fold == pytest.approx(auto_fold["amplitude"], abs=1e-5)
        # the fold is where the branch turns (the scene's verdict: a real multiplier through +1)
        assert f["instability_type"][0, 0] == 1


def test_rk8_fold_alone_on_half_a_period_finds_autos_fold(case, auto_fold, exe, tmp_path):
    # the fold alone with M even: the branch from rest continued on the half-period map (P = G o G)
    with scene_fold(exe, tmp_path, case, "rk8", 0.05, False, floquet_every=0) as f:
        assert int(f["steps_per_period"][0, 0]) % 2 == 0
        fold = float(f["fold_amplitude"][0, 0])
        print(f"rk8 scene, fold alone on half a period: A_f = {fold!r}, AUTO - rk8 = {auto_fold['amplitude'] - fold:.2e}")
        assert fold == pytest.approx(auto_fold["amplitude"], abs=1e-5)
        # the multiplier through +1 at the fold is P's (the square of the half-period map's)
        assert abs(float(f["multipliers/real"][0, 2, 0]) - 1.0) < 1e-3


def test_newton_folds_extrapolate_to_autos_fold(case, auto_fold, exe, tmp_path):
    with scene_fold(exe, tmp_path, case, "newton", NEWTON_DT, True) as f:
        a_dt = float(f["fold_amplitude"][0, 0])
        a_half = float(f["convergence/fold_half_dt"][0, 0])
        richardson = float(f["convergence/richardson"][0, 0])
    exact = auto_fold["amplitude"]
    err_dt, err_half = a_dt - exact, a_half - exact
    order = math.log2(err_dt / err_half)
    print(f"Newton scheme: A_f(dt = {NEWTON_DT}) = {a_dt!r}, A_f(dt/2) = {a_half!r}, Richardson {richardson!r}; "
          f"errors against AUTO {err_dt:.3e}, {err_half:.3e} (order {order:.3f}), {richardson - exact:.2e}")
    # the Newton scheme's own dt^2 error, measured against AUTO's fold: large enough to see, of order 2
    assert abs(err_half) > 1e-5
    assert order == pytest.approx(2.0, abs=0.05)
    # its extrapolation (order 2, the scene's) from dt and dt/2, as the test computes it too
    assert richardson == pytest.approx(a_half + (a_half - a_dt) / 3, abs=1e-12)
    # what is left is the O(dt^4) remainder: (dt/2)^2 ~ 6e-4 of the dt^2 error at dt/2, well under 1e-2 of it
    assert abs(richardson - exact) < 1e-2 * abs(err_half)


def test_harmonic_balance_finds_autos_fold(case, auto_fold, exe, tmp_path):
    # the frequency domain (issue 41): the ODE's fold with no dt, converged in the number of harmonics
    with scene_fold(exe, tmp_path, case, "rk8", 0.05, False, floquet_every=0, solver="harmonic_balance") as f:
        fold = float(f["fold_amplitude"][0, 0])
        closure = float(f["fold_period_closure"][0, 0])
        print(f"harmonic balance (K = {int(f['harmonics'][0, 0])}): A_f = {fold!r}, "
              f"AUTO - HB = {auto_fold['amplitude'] - fold:.2e}, rk8 period closure {closure:.1e}")
        assert fold == pytest.approx(auto_fold["amplitude"], abs=1e-6)
        assert closure < 5e-9   # the state converged to harmonics_tol = 1e-9 in its top harmonic
