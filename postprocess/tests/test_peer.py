"""The SciPy peer (supratrans_post.peer) and the work-precision and stability charts (supratrans_post.charts).

- the peer's right-hand side: against a site-by-site transcription of `rk4_rhs` and against the energy
  balance by finite differences (dH/dt = injected power - dissipated power, which ties together the coupling,
  beta, the absorber, the drive's velocity and the fixed end);
- the peer against the real program: tiny `work_precision` files made by supratrans (conftest `tiny`: both
  potentials, with gamma, beta, m^2 and the absorber all on): DOP853 at a tight tolerance reproduces the
  reference's injected energy to 1e-9 (skipped when fpm is missing);
- the charts are drawn into non-empty PNGs from tiny files, the equal-error table is printed;
- a file of the wrong scene, a truncated or a missing one gives the one line `error: <file>: ...`, exit 2;
- the equal-error rule (no credit for a lucky cancellation, no extrapolation).
"""
from __future__ import annotations

import math
import re
import shutil

import numpy as np
import pytest

from supratrans_post import peer as ps
from supratrans_post.charts import stability as cs
from supratrans_post.charts import work_precision as wp

h5py = pytest.importorskip("h5py")
pytest.importorskip("scipy")
pytest.importorskip("matplotlib")

def tiny_chain(potential="sine-gordon", **kw):
    p = dict(potential=potential, c=2.0, beta=0.3, gamma=0.02, m2=-0.04, n=7, n0=3, kappa=0.5, sigma=1.5,
             omega=0.9, ramp_time=5.0, t_final=20.0)
    if potential == "double-sine-gordon":
        p["eta"] = 0.3
    p.update(kw)
    return ps.Chain.from_params(p)


def loop_rhs(ch, a, t, y, ramping):
    """rk4_rhs of src/numerics/supratrans_rk4.f90, site by site."""
    n = ch.n
    r, dr = (t / ch.ramp_time, 1.0 / ch.ramp_time) if ramping else (1.0, 0.0)
    psi = a * r * math.sin(ch.omega * t)
    dpsi = a * (dr * math.sin(ch.omega * t) + r * ch.omega * math.cos(ch.omega * t))
    out = np.zeros_like(y)
    u_left, v_left = psi, dpsi
    for i in range(n):
        ui, vi = y[i], y[n + i]
        u_right, v_right = (y[i + 1], y[n + i + 1]) if i < n - 1 else (0.0, 0.0)
        gp = ch.kappa * (1 + math.tanh((2 * (i + 1) - ch.n0 - ch.n) / (2 * ch.sigma))) if i + 1 > ch.n0 else 0.0
        force = {"sine-gordon": math.sin(ui), "klein-gordon": ui - ui ** 3 / 6 + ui ** 5 / 120,
                 "double-sine-gordon": math.sin(ui) + ch.eta * 4 * math.sin(ui) * math.cos(ui)}[ch.potential]
        out[i] = vi
        out[n + i] = (ch.c ** 2 * (u_right - 2 * ui + u_left) + ch.beta * (v_right - 2 * vi + v_left)
                      - (ch.gamma + gp) * vi - ch.m2 * ui - force)
        u_left, v_left = ui, vi
    out[2 * n] = ch.c ** 2 * (psi - y[0]) * dpsi + ch.beta * (dpsi - y[n]) * dpsi
    return out


def energy(ch, a, t, y, ramping):
    """H = sum [v^2/2 + m^2 u^2/2 + V(u)] + c^2/2 sum_{n=0}^{N} (u_{n+1} - u_n)^2, u_0 = psi(t), u_{N+1} = 0."""
    n = ch.n
    u, v = y[:n], y[n:2 * n]
    psi = ch.drive(a, ramping)(t)[0]
    pot = {"sine-gordon": 1 - np.cos(u), "klein-gordon": u ** 2 / 2 - u ** 4 / 24 + u ** 6 / 720,
           "double-sine-gordon": 1 - np.cos(u) + ch.eta * (1 - np.cos(2 * u))}[ch.potential]
    full = np.concatenate([[psi], u, [0.0]])
    return float(np.sum(v ** 2 / 2 + ch.m2 * u ** 2 / 2 + pot) + ch.c ** 2 / 2 * np.sum(np.diff(full) ** 2))


@pytest.mark.parametrize("potential", ["sine-gordon", "klein-gordon", "double-sine-gordon"])
@pytest.mark.parametrize("ramping, t", [(True, 2.3), (False, 7.9)])
def test_rhs_matches_the_fortran_formula(potential, ramping, t):
    ch = tiny_chain(potential)
    y = np.random.default_rng(1).normal(size=2 * ch.n + 1)
    got = ch.rhs(1.7, ramping)(t, y)
    assert np.allclose(got, loop_rhs(ch, 1.7, t, y, ramping), rtol=1e-13, atol=1e-13)


@pytest.mark.parametrize("potential", ["sine-gordon", "klein-gordon", "double-sine-gordon"])
@pytest.mark.parametrize("ramping, t", [(True, 2.3), (False, 7.9)])
def test_rhs_balances_the_energy(potential, ramping, t):
    """d/dt H along the flow (central differences in t and y together) = W' - (gamma + gamma') v^2 - beta (dv)^2."""
    ch = tiny_chain(potential)
    a, n = 1.7, ch.n
    y = 0.5 * np.random.default_rng(2).normal(size=2 * n + 1)
    f = ch.rhs(a, ramping)
    dydt = f(t, y)
    h = 1e-5
    dh = (energy(ch, a, t + h, y + h * dydt, ramping) - energy(ch, a, t - h, y - h * dydt, ramping)) / (2 * h)
    v = y[n:2 * n]
    dpsi = ch.drive(a, ramping)(t)[1]
    dv = np.diff(np.concatenate([[dpsi], v, [0.0]]))
    dissipated = np.sum(ch.alpha * v ** 2) + ch.beta * np.sum(dv ** 2)
    assert dh == pytest.approx(dydt[2 * n] - dissipated, rel=1e-8, abs=1e-8)


def test_absorber_and_segments():
    ch = tiny_chain(n=200, n0=150, sigma=3.0, kappa=0.5)
    g = ch.absorber()
    assert np.all(g[:150] == 0) and g[150] < 1e-6 and g[-1] == pytest.approx(1.0, abs=1e-6)
    assert g[174] == pytest.approx(0.5)  # n = 175, the centre (N0 + N)/2: kappa
    assert g[175] == pytest.approx(0.5 * (1 + math.tanh(2 / 6)))  # n = 176
    assert ch.segments() == [(0.0, 5.0, True), (5.0, 20.0, False)]
    # the drive is continuous at the kink, its velocity jumps by -A sin(Omega t_r)/t_r
    p1, d1 = ch.drive(2.0, True)(5.0)
    p2, d2 = ch.drive(2.0, False)(5.0)
    assert p1 == pytest.approx(p2) and d1 - d2 == pytest.approx(2.0 * math.sin(4.5) / 5.0)


def test_time_at_error_rule():
    times = [1.0, 2.0, 4.0, 8.0]
    errors = [1e-1, 1e-6, 1e-3, 1e-5]  # 1e-6 at t = 2 is a lucky cancellation: costlier runs are worse
    t, how = wp.time_at_error(times, errors, 1e-4)
    assert how == "interpolated" and 4.0 < t < 8.0
    assert wp.time_at_error(times, errors, 1e-3) == (2.0, "interpolated")  # credited with t = 4's error
    assert wp.time_at_error(times, errors, 0.5) == (1.0, "cheapest run")
    assert math.isnan(wp.time_at_error(times, errors, 1e-7)[0])
    t, _ = wp.time_at_error([1.0, 10.0], [1e-2, 1e-4], 1e-3)
    assert t == pytest.approx(math.sqrt(10.0))


def assert_png(path):
    assert path.is_file() and path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 5000


def assert_one_line_error(proc, *words):
    assert proc.returncode == 2, (proc.returncode, proc.stdout, proc.stderr)
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), proc.stderr
    for w in words:
        assert w in lines[0], (w, lines[0])


@pytest.mark.slow
@pytest.mark.parametrize("name", ["wp_sg", "wp_kg"])
def test_peer_reproduces_the_programs_reference(tiny, name):
    w = ps.read_work_precision(tiny.file(name))
    check, refs = ps.check_model(w, log=lambda *a: None)
    assert len(check) == 2
    for c in check:
        assert c["passed"] and c["relative_error"] < ps.CHECK_LIMIT, c
        assert c["error_u_final"] < 1e-8, c


def test_peer_prints_its_progress_with_the_time_left(tiny, capsys, monkeypatch):
    """The peer's timing (about 1.5 min on the paper's file) prints its progress on stderr: points done of all,
    elapsed and time left; here at every step that passes the interval (1e-9 s: a tenth of the time elapsed)."""
    monkeypatch.setenv("SUPRATRANS_PROGRESS_EVERY", "1e-9")
    w = ps.read_work_precision(tiny.file("wp_sg"))
    capsys.readouterr()
    r = ps.run_peer(w, methods=["DOP853"], tols=[1e-3, 1e-5], repeats=1, log=lambda *a: None)
    lines = capsys.readouterr().err.splitlines()
    total = 2 + 2 * 2                           # the model check per amplitude, then 2 amplitudes x 2 tolerances
    assert len(r["points"]) == 4 and lines, lines
    pattern = rf"^  SciPy peer: [1-{total}]/{total} solves and points, [0-9]+ s elapsed, about [0-9]+ s left$"
    assert all(re.match(pattern, x) for x in lines), lines
    assert lines[0].startswith(f"  SciPy peer: 1/{total} "), lines      # the first step always prints
    assert ps.point_cost("RK45", 1e-12, 5, 10.0) > ps.point_cost("RK45", 1e-3, 5, 10.0)


@pytest.mark.slow
def test_work_precision_charts_and_table(tiny, tmp_path, call_main):
    peer = tmp_path / "peer.json"
    proc = call_main(wp.main, "--h5", tiny.file("wp_sg"), "--tols", "1e-3", "1e-6", "1e-9", "--repeats", "1",
               "--peer-out", peer, "--outdir", tmp_path / "figs")
    assert proc.returncode == 0, proc.stderr
    for png in ("work_precision.png", "work_precision_dt.png"):
        assert_png(tmp_path / "figs" / png)
    assert "fastest of ours" in proc.stdout and "SciPy best" in proc.stdout
    assert ("goal (5x" in proc.stdout)
    r = ps.read_points(peer)
    ok = [p for p in r["points"] if p["status"] == "ok"]
    assert len(ok) == 2 * 2 * 3 and all(p["wall_time"] > 0 and p["error_energy"] < 1e-1 for p in ok)
    assert {row["level"] for row in r["equal_error_table"]} == set(wp.LEVELS)
    # the charts again from the points written, nothing run
    proc = call_main(wp.main, "--h5", tiny.file("wp_sg"), "--peer", peer, "--outdir", tmp_path / "again", "-q")
    assert proc.returncode == 0, proc.stderr
    assert_png(tmp_path / "again" / "work_precision.png")


def test_stability_chart(tiny, tmp_path, call_main):
    out = tmp_path / "stability.png"
    proc = call_main(cs.main, tiny.file("stab"), "-o", out)
    assert proc.returncode == 0, proc.stderr
    assert_png(out)
    assert "beta = 0.5" in proc.stdout and "paper" in proc.stdout


def test_wrong_scene_truncated_missing(tiny, tmp_path, call_main):
    wpf, stab = tiny.file("wp_sg"), tiny.file("stab")
    assert_one_line_error(call_main(cs.main, wpf, "-o", tmp_path / "x.png"), str(wpf),
                          "scene is 'work_precision', expected 'stability'")
    assert_one_line_error(call_main(wp.main, "--h5", stab, "--outdir", tmp_path), str(stab),
                          "scene is 'stability', expected 'work_precision'")
    assert_one_line_error(call_main(ps.main, stab, "--check"), "expected 'work_precision'")
    cut = tmp_path / "cut.h5"
    raw = wpf.read_bytes()
    cut.write_bytes(raw[: len(raw) // 2])
    assert_one_line_error(call_main(ps.main, cut), str(cut), "truncated")
    broken = tmp_path / "broken.h5"
    shutil.copy(wpf, broken)
    with h5py.File(broken, "r+") as h:
        del h["reference/injected"]
    assert_one_line_error(call_main(wp.main, "--h5", broken, "--outdir", tmp_path), "reference/injected")
    assert_one_line_error(call_main(cs.main, tmp_path / "nowhere.h5"), "nowhere.h5", "no such file")
    assert not (tmp_path / "x.png").exists() and not list(tmp_path.glob("work_precision*.png"))
