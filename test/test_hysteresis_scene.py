"""The hysteresis scene as a user drives it: on a tiny chain (N = 40) with short stairs, the upward edge lies at or
above the downward edge, both on the stair grid, the spreads are those of the edges over the stair lengths; the file
is identical for 1 and 2 threads and for a sliced run merged; bad stairs are one line, exit 2, nothing written."""
import os
import subprocess

import h5py
import numpy as np
import pytest

import compare_results

HYST = """&chain n = 40, n0 = 30 /
&drive ramp_time = 20 /
&numerics dt = 0.1 /
&scene kind = 'hysteresis', omega_min = 0.85, omega_max = 0.9, omega_step = 0.05, amplitude_min = 1.5,
  amplitude_max = 2.1, stair_height = 0.05, stair_times = 100, 200, stair_ramp = 10, power_threshold = 0.1 /
&output file = 'out/hyst.h5', quiet = .true. /
"""


def sh(exe, *args, cwd, threads=1, check=True):
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    proc = subprocess.run([exe, *map(str, args)], cwd=cwd, capture_output=True, text=True, timeout=900, env=env)
    if check:
        assert proc.returncode == 0, proc.stderr
    return proc


@pytest.fixture(scope="module")
def hysteresis(exe, tmp_path_factory):
    """The scene of HYST computed with one thread: the folder it lives in."""
    tmp = tmp_path_factory.mktemp("hyst")
    (tmp / "hyst.nml").write_text(HYST)
    sh(exe, "hyst.nml", cwd=tmp)
    return tmp


def test_edges_are_on_the_stair_grid_and_upward_above_downward(hysteresis):
    with h5py.File(hysteresis / "out" / "hyst.h5") as f:
        assert f.attrs["scene"] == b"hysteresis"
        status = f["status"][()]
        up = f["upward_threshold"][()]
        down = f["downward_threshold"][()]
        assert status.shape == (1, 2, 2)
        assert "none transmits" in f["status"].attrs["codes"].decode()
        # Omega = 0.9 finds both edges at both stair lengths
        assert (status[0, 1] == 0).all(), status
        found = status == 0
        assert np.all(up[found] >= down[found])
        np.testing.assert_allclose(f["window"][()][found], (up - down)[found], rtol=0, atol=1e-12)
        levels = f["stair_amplitude"][()]
        k = levels.size // 2
        assert levels.size == 2 * k + 1 and levels[k] == pytest.approx(2.1) and levels[0] == levels[-1] == 1.5
        for edge in (up, down):
            x = (edge[found] - 1.5) / 0.05
            assert np.allclose(x, np.round(x), atol=1e-9)
            assert np.all(np.isin(np.round(edge[found], 12), np.round(levels, 12)))
        # an edge is NaN exactly where the status says it does not exist
        assert np.all(np.isnan(up[status == 1])) and np.all(np.isnan(down[status == 1]))
        # the stairs' powers: the upward edge is the first stair up above the threshold
        power = f["power"][()]
        thr = f["power"].attrs["power_threshold"]
        assert power.shape == (1, 2, 2, levels.size)
        for w in range(2):
            for s in range(2):
                if status[0, w, s] != 0:
                    continue
                on = power[0, w, s] > thr
                assert levels[np.argmax(on[: k + 1])] == up[0, w, s]
                assert not on[0] and not on[-1]
        # the spreads are max - min of each edge over the stair lengths
        for name, edge in (("upward_spread", up), ("downward_spread", down)):
            spread = f[name][()]
            assert spread.shape == (1, 2)
            assert spread[0, 1] == pytest.approx(np.nanmax(edge[0, 1]) - np.nanmin(edge[0, 1]), abs=1e-12)
        assert f["stair_time"][()].tolist() == [100.0, 200.0]
        # the run covers the ramp from rest and every stair: T = ramp_time + (2K + 1) T_s (the three-level
        # scheme's first step is its start: M - 1 steps)
        assert abs(f["cost/steps"][0, 1, 1] - round((20 + levels.size * 200) / 0.1)) <= 1
        assert "stair_times" in f["parameters"].attrs


@pytest.mark.slow
def test_hysteresis_is_the_same_for_two_threads_and_for_slices(exe, hysteresis, tmp_path):
    (tmp_path / "hyst.nml").write_text(HYST)
    sh(exe, "hyst.nml", cwd=tmp_path, threads=2)
    diffs, compared, _ = compare_results.compare(hysteresis / "out" / "hyst.h5", tmp_path / "out" / "hyst.h5")
    assert compared > 10 and not diffs, diffs
    (tmp_path / "out" / "hyst.h5").unlink()
    for i in (1, 2, 3):
        sh(exe, "hyst.nml", "--slice", f"{i}/3", cwd=tmp_path)
    parts = sorted((tmp_path / "out").glob("hyst.part-*.h5"))
    assert len(parts) == 3
    sh(exe, "merge", *parts, cwd=tmp_path)
    diffs, compared, _ = compare_results.compare(hysteresis / "out" / "hyst.h5", tmp_path / "out" / "hyst.h5")
    assert compared > 10 and not diffs, diffs


@pytest.mark.parametrize("old,new,words", [
    ("stair_ramp = 10", "stair_ramp = 60", "stair_ramp"),
    ("amplitude_max = 2.1", "amplitude_max = 1.52", "at least one stair up"),
    ("omega_min = 0.85", "omega_min = 0.0", "omega_min"),
    ("stair_height = 0.05", "stair_height = 0.0001", "stairs: more than the limit"),
    ("stair_times = 100, 200", "stair_times = 100, 1e9", "time steps"),
], ids=["ramp longer than half a stair", "no stair up", "omega zero", "too many stairs", "too long a stair"])
def test_bad_stairs_are_one_line_and_nothing_written(exe, tmp_path, old, new, words):
    assert old in HYST
    (tmp_path / "bad.nml").write_text(HYST.replace(old, new))
    proc = sh(exe, "bad.nml", cwd=tmp_path, check=False)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and words in lines[0], proc.stderr
    assert not (tmp_path / "out" / "hyst.h5").exists()


def test_figure_draws_power_up_and_down_and_the_edges(exe, hysteresis, tmp_path, call_main):
    from supratrans_post import plot
    from supratrans_post.figures import draw, summary
    from supratrans_post.reader import open_scene

    s = open_scene(hysteresis / "out" / "hyst.h5", expect="hysteresis")
    lines = summary(s)
    up = s.data["upward_threshold"][0, 1, 0]
    assert any(f"up {up:g}" in line for line in lines), lines
    # two frequencies: the edges over Omega
    fig = draw(s)
    assert "edges" in fig._suptitle.get_text()
    # one frequency (Omega = 0.9 alone): the power of each stair vs its amplitude, the window shaded
    text = HYST.replace("omega_min = 0.85", "omega_min = 0.9").replace("stair_times = 100, 200", "stair_times = 100")
    (tmp_path / "one.nml").write_text(text)
    sh(exe, "one.nml", cwd=tmp_path)
    ran = call_main(plot.main, tmp_path / "out" / "hyst.h5", "-o", tmp_path / "one.png")
    assert ran.returncode == 0, ran.stderr
    assert (tmp_path / "one.png").stat().st_size > 10000
    one = open_scene(tmp_path / "out" / "hyst.h5")
    fig = draw(one)
    ax = fig.axes[0]
    windows = [ln for ln in ax.lines if (ln.get_gid() or "").startswith("window:")]
    reasons = [t for t in ax.texts if t.get_gid() == "reason"]
    assert len(ax.lines) >= 3 and (windows or reasons), "up and down branches, the threshold, the window or why not"
    assert ax.get_yscale() == "linear" and not ax.patches  # a linear power axis, windows as bars that do not blend
