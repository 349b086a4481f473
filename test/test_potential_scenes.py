"""The double sine-Gordon potential (`&chain potential = 'double-sine-gordon'`, `&chain eta`; issue 40) in every
scene: each scene kind runs at a tiny size with it and writes a file whose `/parameters` records the potential and
eta (and `/curves/potential` names it where the scene has curves); eta given with a potential that does not take it
is refused in one line, by the run and by `--check` alike.
"""
from __future__ import annotations

import subprocess

import pytest

h5py = pytest.importorskip("h5py")

CHAIN = "&chain potential = 'double-sine-gordon', eta = 0.2, n = 40, n0 = 30 /\n"
SHORT = "&numerics t_final = 10.0 /\n"

#: scene kind -> the rest of the namelist (a few seconds each)
SCENES = {
    "timeseries": SHORT,
    "amplitude_sweep": SHORT + "&scene kind = 'amplitude_sweep', amplitude_min = 1.0, amplitude_max = 1.2, "
                               "amplitude_step = 0.1 /\n",
    "map": SHORT + "&scene kind = 'map', amplitude_min = 1.0, amplitude_max = 1.1, amplitude_step = 0.1, "
                   "omega_min = 0.8, omega_max = 0.9, omega_step = 0.1 /\n",
    "bifurcation": SHORT + "&scene kind = 'bifurcation', omega_min = 0.9, omega_max = 0.9, amplitude_min = 1.0, "
                           "amplitude_max = 2.0, coarse_step = 0.5, resolution = 0.25 /\n",
    "work_precision": "&numerics t_final = 4.0 /\n&drive ramp_time = 2.0 /\n&scene kind = 'work_precision', "
                      "amplitudes = 1.0, methods = 'newton', 'rk4', 'avf4', dts = 0.1, 0.05, "
                      "dt_smallest = 0.05, 0.05, 0.05, repeats = 1, reference_dt = 0.05 /\n",
    "stability": "&numerics t_final = 10.0 /\n&scene kind = 'stability', methods = 'newton', 'rk4', "
                 "c_values = 2.0, dts = 0.1, 0.4, 1.0, resolution = 0.05 /\n",
    "continuation": "&numerics t_final = 10.0 /\n&scene kind = 'continuation', omega_min = 0.9, omega_max = 0.9, "
                    "amplitude_max = 2.0, floquet_every = 0, fold_convergence = .false., beyond_fold = 0, "
                    "continuation_step_max = 0.5 /\n",
    "continuation_hb": "&numerics method = 'rk8' /\n&scene kind = 'continuation', solver = 'harmonic_balance', "
                       "omega_min = 0.9, omega_max = 0.9, amplitude_max = 3.0, harmonics_max = 8, "
                       "floquet_every = 0 /\n",
    "hysteresis": "&drive ramp_time = 5.0 /\n&scene kind = 'hysteresis', omega_min = 0.9, omega_max = 0.9, "
                  "amplitude_min = 1.0, amplitude_max = 1.04, stair_height = 0.02, stair_times = 20.0, "
                  "stair_ramp = 2.0 /\n",
}


def run(exe, where, text, *args):
    """The program run in `where` on `case.nml` holding `text`."""
    where.mkdir(parents=True, exist_ok=True)
    (where / "case.nml").write_text(text)
    return subprocess.run([exe, *args, "case.nml"], cwd=where, capture_output=True, text=True, timeout=600)


@pytest.mark.slow
@pytest.mark.parametrize("scene", sorted(SCENES))
def test_every_scene_runs_with_the_double_sine_gordon(exe, tmp_path, scene):
    proc = run(exe, tmp_path, CHAIN + SCENES[scene] + "&output file = 's.h5', quiet = .true. /\n")
    assert proc.returncode == 0, proc.stderr
    with h5py.File(tmp_path / "s.h5", "r") as f:
        params = f["parameters"].attrs
        name = params["potential"]
        assert (name.decode() if isinstance(name, bytes) else str(name)) == "double-sine-gordon"
        assert float(params["eta"]) == 0.2
        if "curves/potential" in f:
            names = [x.decode().strip() if isinstance(x, bytes) else str(x).strip() for x in f["curves/potential"][()]]
            assert names == ["double-sine-gordon"] * len(names) and names
        if "curves/band_gap_edge" in f:
            # the band gap of the double sine-Gordon: sqrt(V''(0) + m^2) = sqrt(1 + 4 eta)
            assert abs(float(f["curves/band_gap_edge"][0]) - (1.0 + 4 * 0.2) ** 0.5) < 1e-15


def test_eta_without_a_potential_that_takes_it_is_one_line(exe, tmp_path):
    text = "&chain potential = 'sine-gordon', eta = 0.2, n = 40, n0 = 30 /\n" + SHORT + \
           "&output file = 'out/s.h5', quiet = .true. /\n"
    check = run(exe, tmp_path / "check", text, "--check")
    ran = run(exe, tmp_path / "run", text)
    for proc in (check, ran):
        lines = proc.stderr.strip().splitlines()
        assert proc.returncode == 2 and len(lines) == 1, proc.stderr
        assert "eta = 0.2 is a parameter of no potential of this run" in lines[0], lines[0]
        assert "'double-sine-gordon'" in lines[0], lines[0]
    assert not (tmp_path / "run" / "out").exists()
    # given with the potential that takes it in &scene potentials, eta is used there and accepted
    text = text.replace("&numerics", "&scene kind = 'amplitude_sweep', potentials = 'sine-gordon', "
                        "'double-sine-gordon', amplitude_min = 1.0, amplitude_max = 1.1, amplitude_step = 0.1 /\n"
                        "&numerics")
    assert run(exe, tmp_path / "both", text, "--check").returncode == 0


def test_an_empty_band_gap_is_one_line(exe, tmp_path):
    """V''(0) + m^2 = 1 + 4 eta + m^2 <= 0 leaves no band gap: refused, naming V''(0)."""
    text = "&chain potential = 'double-sine-gordon', eta = -0.3, n = 40, n0 = 30 /\n" + SHORT + \
           "&output file = 's.h5', quiet = .true. /\n"
    proc = run(exe, tmp_path, text, "--check")
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode == 2 and len(lines) == 1 and "need V''(0) + m2 > 0" in lines[0], proc.stderr
