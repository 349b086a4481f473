"""The stability scene's linear theory (the spectra of the linearised chain, LAPACK dgeev on 400 x 400 matrices) is
bit-identical for 1 and 2 threads: a threaded BLAS splits its blocks by the thread count, so the spectra are computed
where it runs on one thread (with 2 threads they moved by 1e-15 before)."""
import os
import subprocess

import h5py
import numpy as np

STABILITY = """&chain n = 200, n0 = 150, kappa = 0.0 /
&drive amplitude = 0.5, omega = 0.9, ramp_time = 5.0 /
&numerics t_final = 10.0, blowup_threshold = 1.5 /
&scene kind = 'stability', methods = 'rk4', 'rk8', c_values = 1.0, 4.0, dts = 0.1, 0.2, resolution = 0.05 /
&output file = 'out/st.h5', quiet = .true. /
"""


def test_linear_theory_is_the_same_for_one_and_two_threads(exe, tmp_path):
    boundaries = []
    for threads in (1, 2):
        cwd = tmp_path / f"t{threads}"
        cwd.mkdir()
        (cwd / "s.nml").write_text(STABILITY)
        env = dict(os.environ, OMP_NUM_THREADS=str(threads))
        proc = subprocess.run([exe, "s.nml"], cwd=cwd, capture_output=True, text=True, timeout=600, env=env)
        assert proc.returncode == 0, proc.stderr
        with h5py.File(cwd / "out" / "st.h5") as f:
            boundaries.append((f["boundary/linear"][()], f["boundary/rk4"][()], f["boundary/observed"][()]))
    for one, two in zip(*boundaries):
        assert np.all(np.isfinite(one[~np.isnan(one)]))
        np.testing.assert_array_equal(one, two)
