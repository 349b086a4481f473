"""Curves over any numeric key (`&scene vary`, issue 40 item 4): each curve of a varied sweep is the run of the
namelist with that value written in its group, bit for bit (c, n, dt, kappa at tiny size); `/curves` names the key
and its units; the keys a varied key depends on are checked per value, before anything is created; an unknown or
non-numeric key, a fractional value of an integer key and a key the scene sets itself are each one line."""
from __future__ import annotations

import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest

#: The base namelist's groups (the keys a case varies or writes are set in these).
BASE = {"chain": {"n": 40, "n0": 30}, "drive": {"omega": 0.9}, "numerics": {"t_final": 20.0, "dt": 0.05}}
SCENE = "&scene kind = 'amplitude_sweep', amplitude_min = 1.0, amplitude_max = 1.2, amplitude_step = 0.1 {scene}/\n"
OUT = "&output file = 'out/s.h5', quiet = .true. /\n"


def namelist(scene: str = "", **given: dict) -> str:
    """The sweep's namelist: BASE with the keys of `given` ({group: {key: value}}) set, and `scene` added."""
    text = ""
    for group, keys in BASE.items():
        keys = keys | given.get(group, {})
        text += f"&{group} " + ", ".join(f"{k} = {v}" for k, v in keys.items()) + " /\n"
    return text + SCENE.format(scene=scene) + OUT


#: key -> (group, values, units): two values each, unlike the base (c = 4, N = 40, dt = 0.05, kappa = 0.5)
CASES = {
    "c": ("chain", [3.0, 3.5], "1/time"),
    "n": ("chain", [44, 52], "1"),
    "dt": ("numerics", [0.04, 0.025], "time"),
    "kappa": ("chain", [0.2, 1.0], "1/time"),
    # the sweep has no frequency axis: each curve runs at its own Omega (every curve ran at &drive omega before)
    "omega": ("drive", [0.5, 0.7], "1/time"),
}


def run(exe: str, folder: Path, text: str) -> subprocess.CompletedProcess:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "case.nml").write_text(text)
    return subprocess.run([exe, "case.nml"], cwd=folder, capture_output=True, text=True, timeout=300)


def results(path: Path) -> dict[str, np.ndarray]:
    """The per-run result datasets of a sweep file (/energy/*, /runs/*), curve axis first (not the wall clock)."""
    out = {}
    with h5py.File(path) as f:
        for group in ("energy", "runs"):
            for name, d in f[group].items():
                if d.ndim == 2 and name != "wall_time":
                    out[f"{group}/{name}"] = d[()]
    return out


@pytest.mark.parametrize("key", CASES)
def test_each_curve_is_the_run_with_its_value_written(exe, tmp_path, key):
    group, values, units = CASES[key]
    shown = ", ".join(str(v) for v in values)
    varied = run(exe, tmp_path / "varied", namelist(f", vary = '{key}', values = {shown} "))
    assert varied.returncode == 0, varied.stderr
    path = tmp_path / "varied" / "out" / "s.h5"
    with h5py.File(path) as f:
        assert f["curves"].attrs["vary"] == key.encode()
        np.testing.assert_array_equal(f["curves/value"][()], values)
        assert f["curves/value"].attrs["units"] == units.encode()
    got = results(path)
    for i, v in enumerate(values):
        single = run(exe, tmp_path / f"single{i}", namelist(**{group: {key: v}}))
        assert single.returncode == 0, single.stderr
        want = results(tmp_path / f"single{i}" / "out" / "s.h5")
        assert set(want) == set(got)
        for name, data in want.items():
            np.testing.assert_array_equal(got[name][i], data[0], err_msg=f"{name}, curve {i + 1} ({key} = {v})")
    # the values differ in what they give: the curves are not copies of one run
    assert not np.array_equal(got["energy/injected"][0], got["energy/injected"][1])
    if key == "omega":
        # A_s is each curve's, at its own Omega
        with h5py.File(path) as f:
            a_s = f["curves/threshold_As"][()]
        for i, v in enumerate(values):
            with h5py.File(tmp_path / f"single{i}" / "out" / "s.h5") as f:
                assert a_s[i] == f["curves/threshold_As"][0]
        assert a_s[0] != a_s[1]


@pytest.mark.parametrize("scene,words", [
    (", vary = 'n', values = 40, 20 ", "curve 2 (sine-gordon, n = 20): &chain: n0 = 30: need 0 <= N0 <= N = 20"),
    (", vary = 'dt', values = 0.05, 0.3 ", "curve 2 (sine-gordon, dt = 0.3): &numerics: dt = 0.3 violates"),
    (", vary = 'sigma', values = 0.0 ", "curve 1 (sine-gordon, sigma = 0.0): &chain: sigma = 0.0: must be > 0"),
    (", vary = 'n', values = 40.5 ", "values(1) = 40.5: vary = 'n' is an integer key: give whole numbers"),
    (", vary = 'potential', values = 1 ", "vary = 'potential': unknown numeric key (known: none, c, m2,"),
    (", vary = 'cc', values = 1 ", "vary = 'cc': unknown numeric key"),
    (", vary = 'amplitude', values = 1 ", "kind = 'amplitude_sweep' sets amplitude itself in every task"),
], ids=["n0 beyond a value of n", "dt unstable for one value", "sigma out of range", "fractional n",
        "non-numeric key", "unknown key", "the scene's own axis"])
def test_a_bad_value_or_key_is_one_line_and_nothing_is_created(exe, tmp_path, scene, words):
    for args in (["case.nml"], ["--check", "case.nml"]):
        folder = tmp_path / args[0].strip("-")
        folder.mkdir()
        (folder / "case.nml").write_text(namelist(scene))
        proc = subprocess.run([exe, *args], cwd=folder, capture_output=True, text=True, timeout=60)
        assert proc.returncode == 2, proc.stderr
        lines = proc.stderr.strip().splitlines()
        assert len(lines) == 1 and words in lines[0], proc.stderr
        assert sorted(p.name for p in folder.iterdir()) == ["case.nml"]


def test_a_base_value_no_curve_runs_is_not_checked(exe, tmp_path):
    """vary = 'dt': the base dt (0.3, unstable at c = 4) is not run, so it is not refused; the curves' are."""
    proc = run(exe, tmp_path, namelist(", vary = 'dt', values = 0.05, 0.04 ", numerics={"dt": 0.3}))
    assert proc.returncode == 0, proc.stderr
