"""Verdicts with their margins, and the numerical limits of the model: each case a clear verdict or a clear refusal."""
import subprocess

import h5py
import numpy as np
import pytest

SWEEP = """&chain gamma = {gamma} /
&drive omega = 0.9 /
&scene kind = 'amplitude_sweep', amplitude_min = {a0}, amplitude_max = {a1}, amplitude_step = {da} /
&output file = 'sweep.h5', quiet = .true. /
"""


def run(exe, tmp_path, text):
    (tmp_path / "case.nml").write_text(text)
    return subprocess.run([exe, "case.nml"], cwd=tmp_path, capture_output=True, text=True, timeout=300)


def test_strong_damping_verdicts_are_flagged_thin_and_without_energy_jump(exe, tmp_path):
    """gamma = 0.1 at Omega = 0.9: |u| beyond the detector hovers near pi and the energy does not jump."""
    proc = run(exe, tmp_path, SWEEP.format(gamma=0.1, a0=2.4, a1=3.2, da=0.1))
    assert proc.returncode == 0, proc.stderr
    with h5py.File(tmp_path / "sweep.h5") as f:
        thin = f["runs/thin_verdict"][0]
        margin = f["runs/verdict_margin"][0]
        change = f["runs/verdict_change"][0]
        jump = f["runs/energy_jump"][0]
        assert f["runs"].attrs["verdict_changes_without_energy_jump"] >= 1
    assert thin.sum() >= 4 and np.all(margin[thin == 1] < 0.2)
    at = change == 1
    assert at.any() and np.all(jump[at] < 3)


def test_undamped_threshold_is_a_clear_verdict_with_an_energy_jump(exe, tmp_path):
    proc = run(exe, tmp_path, SWEEP.format(gamma=0.0, a0=1.70, a1=1.86, da=0.04))
    assert proc.returncode == 0, proc.stderr
    with h5py.File(tmp_path / "sweep.h5") as f:
        change = f["runs/verdict_change"][0]
        jump = f["runs/energy_jump"][0]
        thin = f["runs/thin_verdict"][0]
        assert f["runs"].attrs["verdict_changes_without_energy_jump"] == 0
    assert (change == 1).sum() == 1 and jump[change == 1][0] > 20
    assert thin.sum() == 0


TS = """&chain n = 100, n0 = 75, m2 = {m2} /
&drive amplitude = {a}, omega = {w} /
&numerics t_final = 150.0 /
&output file = 'ts.h5', quiet = .true. /
"""


def outcome(exe, tmp_path, a, w, m2=0.0):
    proc = run(exe, tmp_path, TS.format(a=a, w=w, m2=m2))
    if proc.returncode != 0:
        return proc, None
    with h5py.File(tmp_path / "ts.h5") as f:
        return proc, dict(f["run"].attrs)


def test_tiny_amplitude_transmits_nothing(exe, tmp_path):
    proc, r = outcome(exe, tmp_path, 1e-6, 0.9)
    assert r["status"] == b"ok" and not r["transmitting"]
    assert r["verdict_margin"] > 0.999 and not r["thin_verdict"]


def test_huge_amplitude_is_recorded_as_a_blow_up_or_a_clear_transmission(exe, tmp_path):
    proc, r = outcome(exe, tmp_path, 1e3, 0.9)
    assert r is not None, proc.stderr
    assert r["status"] in (b"diverged", b"ok")
    if r["status"] == b"ok":
        assert r["transmitting"] and r["verdict_margin"] > 0.2
    else:
        assert "blow" in r["reason"].decode() or "diverg" in r["reason"].decode() or "|u" in r["reason"].decode()


@pytest.mark.parametrize("w", [0.99, 0.999])
def test_band_edge_gives_a_clear_verdict(exe, tmp_path, w):
    proc, r = outcome(exe, tmp_path, 0.5, w)
    assert r is not None, proc.stderr
    assert r["status"] == b"ok" and r["verdict_margin"] == r["verdict_margin"]


def test_at_and_beyond_the_band_edge_is_refused(exe, tmp_path):
    for w in (1.0, 1.5):
        proc, r = outcome(exe, tmp_path, 0.5, w)
        assert proc.returncode == 2 and "gap" in proc.stderr and len(proc.stderr.strip().splitlines()) == 1


def test_imaginary_mass_near_one(exe, tmp_path):
    """m^2 = -0.99: the gap is Omega < 0.1; inside it a clear verdict, outside it and at m^2 = -1 a refusal."""
    proc, r = outcome(exe, tmp_path, 0.5, 0.05, m2=-0.99)
    assert r is not None, proc.stderr
    assert r["status"] in (b"ok", b"diverged") and r["reason"] is not None
    proc, r = outcome(exe, tmp_path, 0.5, 0.5, m2=-0.99)
    assert proc.returncode == 2 and "gap" in proc.stderr
    proc, r = outcome(exe, tmp_path, 0.5, 0.05, m2=-1.0)
    assert proc.returncode == 2 and "m2" in proc.stderr


JUMP_SWEEP = """&chain gamma = 0.1 /
&drive omega = 0.9 /
&scene kind = 'amplitude_sweep', amplitude_min = 2.6, amplitude_max = 2.8, amplitude_step = 0.1{key} /
&output file = 'sweep.h5' /
"""

#: What differs between two runs of one input however it is set: timings, when and where the file was made.
NOT_RESULTS = ("wall_time", "provenance", "created")


def everything(path):
    """Every dataset's values and every attribute of a file, by (object, attribute) path, but NOT_RESULTS and the
    dimension scales' references."""
    out = {}

    def visit(name, obj):
        if any(s in name for s in NOT_RESULTS):
            return
        if isinstance(obj, h5py.Dataset):
            out[(name, None)] = obj[()]
        for k, v in obj.attrs.items():
            if k not in ("DIMENSION_LIST", "REFERENCE_LIST") and not any(s in k for s in NOT_RESULTS):
                out[(name, k)] = v

    with h5py.File(path) as f:
        visit("/", f)
        f.visititems(visit)
    return out


def differences(a, b):
    """The keys of `everything` whose values differ between two files (NaN equal to NaN)."""
    def same(x, y):
        x, y = np.asarray(x), np.asarray(y)
        if x.shape != y.shape:
            return False
        return bool(np.array_equal(x, y, equal_nan=x.dtype.kind == "f" and y.dtype.kind == "f"))
    return sorted(k for k in set(a) | set(b) if k not in a or k not in b or not same(a[k], b[k]))


def test_min_energy_jump_moves_the_count_of_unbacked_verdict_changes_and_nothing_else(exe, tmp_path):
    """&scene min_energy_jump: unset and 3 (its default) make the same file; 1.05, below the ratio 1.11 of the
    verdict change at A = 2.7 (gamma = 0.1, Omega = 0.9), backs that change: the /runs attribute
    verdict_changes_without_energy_jump and the summary's warning move, /parameters records the value, and every
    other dataset and attribute stays as it was."""
    files, printed = {}, {}
    for name, key in (("unset", ""), ("default", ", min_energy_jump = 3"), ("low", ", min_energy_jump = 1.05")):
        proc = run(exe, tmp_path, JUMP_SWEEP.format(key=key))
        assert proc.returncode == 0, proc.stderr
        files[name] = everything(tmp_path / "sweep.h5")
        printed[name] = proc.stdout + proc.stderr
        (tmp_path / "sweep.h5").unlink()
    unset, default, low = files["unset"], files["default"], files["low"]
    assert differences(unset, default) == []
    assert unset[("parameters", "min_energy_jump")] == 3.0
    change, jump = unset[("runs/verdict_change", None)][0], unset[("runs/energy_jump", None)][0]
    assert (change == 1).sum() == 1 and 1.05 < jump[change == 1][0] < 3
    assert unset[("runs", "verdict_changes_without_energy_jump")] == 1
    assert low[("runs", "verdict_changes_without_energy_jump")] == 0
    assert low[("parameters", "min_energy_jump")] == 1.05
    assert differences(unset, low) == [("parameters", "min_energy_jump"),
                                       ("runs", "verdict_changes_without_energy_jump")]
    assert "1 verdict change(s) without an energy jump" in printed["unset"]
    assert "1 verdict change(s) without an energy jump" not in printed["low"]
