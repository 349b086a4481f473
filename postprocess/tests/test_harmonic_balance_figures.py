"""The figures of the continuation scene by harmonic balance (supratrans_post.figures.harmonic) on small files made
by the program itself (release build, N = 40): the reader takes the file by its root attribute `solver`; the fold
line shows the file's folds over a scan and beside a shooting fold line, its convergence on a log scale and K;
the continuum figure puts each fold at 1/c^2, the limit at 0 with its error bar, A_s of each c and of the
continuum, the absorber spread on the base chain's fold; the summary prints them; make_figures draws both at
200 dpi, and its --quick copies keep them cheap."""
from __future__ import annotations

import math
import subprocess
from pathlib import Path

import numpy as np
import pytest

from supratrans_post import figures, namelist, reader, runner
from supratrans_post.figures import harmonic
from supratrans_post.plot import main as plot_main

h5py = pytest.importorskip("h5py")
pytest.importorskip("matplotlib")
pytest.importorskip("f90nml")

ROOT = Path(__file__).resolve().parents[2]
HB = ("continuation", "harmonic_balance")

CHAIN = """&chain
    potential = 'sine-gordon'
    n = 40
    n0 = 30
/
&numerics
    method = 'rk8'
    dt = 0.05
/
"""
#: The tiny files: {name: &scene group}. `fold_hb`: the fold line alone at three frequencies; `continuum`: two
#: frequencies at c = 4, 8, 16 with one member of the absorber family; `shooting` and `scan`: the same chain's fold
#: line by shooting and its ramped scan (the time domain's, for the fold line's companions).
SCENES = {
    "fold_hb": """&scene
    kind = 'continuation'
    solver = 'harmonic_balance'
    omega_min = 0.7
    omega_max = 0.9
    omega_step = 0.1
    amplitude_max = 7.0
    floquet_every = 0
/
""",
    "continuum": """&scene
    kind = 'continuation'
    solver = 'harmonic_balance'
    omega_min = 0.7
    omega_max = 0.9
    omega_step = 0.2
    amplitude_max = 7.0
    floquet_every = 0
    absorber_family = 1
    c_values = 4.0, 8.0, 16.0
/
""",
    "shooting": """&scene
    kind = 'continuation'
    omega_min = 0.7
    omega_max = 0.9
    omega_step = 0.1
    amplitude_max = 7.0
    floquet_every = 0
    fold_convergence = .false.
/
""",
    "scan": """&drive
    ramp_time = 5.0
/
&numerics
    t_final = 20.0
/
&scene
    kind = 'bifurcation'
    amplitude_min = 1.0
    amplitude_max = 4.0
    coarse_step = 1.0
    resolution = 0.25
    omega_min = 0.7
    omega_max = 0.9
    omega_step = 0.1
/
""",
}
OUTPUT = "&output\n    file = '{out}'\n    overwrite = .true.\n    quiet = .true.\n/\n"


@pytest.fixture(scope="module")
def files(release_exe: Path, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """The tiny files of SCENES, made by the release build (a few seconds in all)."""
    folder = tmp_path_factory.mktemp("hb")
    out = {}
    for name, scene in SCENES.items():
        path, nml = folder / f"{name}.h5", folder / f"{name}.nml"
        chain = CHAIN if name != "scan" else CHAIN.replace("&numerics\n    method = 'rk8'\n    dt = 0.05\n/\n", "")
        nml.write_text(chain + scene + OUTPUT.format(out=path))
        proc = subprocess.run([str(release_exe), str(nml)], cwd=folder, capture_output=True, text=True, timeout=120)
        assert proc.returncode == 0 and path.is_file(), (name, proc.stderr)
        out[name] = path
    return out


def lines_by_gid(ax) -> dict[str, object]:
    return {ln.get_gid(): ln for ln in ax.get_lines() if ln.get_gid()}


def data(path: Path, name: str) -> np.ndarray:
    with h5py.File(path, "r") as h:
        return np.asarray(h[name][()], dtype=float)


# ------------------------------------------------------------------------------------------------ the reader


def test_reader_takes_the_file_by_its_solver(files):
    """The schema by harmonic balance names only what the program writes (with the absorber family and c_values,
    every optional dataset too); without them, none of /continuum and /convergence/absorber_folds."""
    s = reader.open_scene(files["continuum"], expect="continuation")
    assert s.solver == "harmonic_balance" and harmonic.is_harmonic_balance(s)
    assert sorted(s.data) == sorted(reader.SOLVER_SCHEMA[HB])
    for name, (dims, _) in reader.SOLVER_SCHEMA[HB].items():
        assert s.data[name].ndim == len(dims), name
    plain = reader.open_scene(files["fold_hb"])
    required = {k for k, (_, req) in reader.SOLVER_SCHEMA[HB].items() if req}
    assert required <= set(plain.data) and "continuum/folds" not in plain.data
    assert "convergence/absorber_folds" not in plain.data
    shooting = reader.open_scene(files["shooting"])
    assert shooting.solver == "" and not harmonic.is_harmonic_balance(shooting)
    assert "instability_amplitude" in shooting.data  # the shooting schema still applies to shooting files


# ------------------------------------------------------------------------------------------------ the fold line


def test_fold_line_over_the_scan_and_beside_shooting(files):
    hb = reader.open_scene(files["fold_hb"])
    scan = reader.open_scene(files["scan"], expect="bifurcation")
    shooting = reader.open_scene(files["shooting"])
    fig = figures.draw_continuation(hb, scan, shooting)
    top, bottom, k_axis = fig.get_axes()
    got = lines_by_gid(top)
    np.testing.assert_allclose(got["fold_hb:0"].get_xdata(), [0.7, 0.8, 0.9], rtol=1e-14)
    np.testing.assert_array_equal(got["fold_hb:0"].get_ydata(), data(files["fold_hb"], "fold_amplitude")[0])
    np.testing.assert_array_equal(got["fold_shooting:0"].get_ydata(), data(files["shooting"], "fold_amplitude")[0])
    np.testing.assert_array_equal(got["scan:0"].get_ydata(), data(files["scan"], "threshold")[0])
    np.testing.assert_array_equal(got["A_s"].get_ydata(), data(files["fold_hb"], "threshold_As")[0])
    # the two solvers agree on this chain to the shooting scheme's dt error, far below the scan's bracket
    np.testing.assert_allclose(got["fold_hb:0"].get_ydata(), got["fold_shooting:0"].get_ydata(), atol=5e-3)
    assert top.get_ylabel().startswith("driving amplitude $A$") and "[rad]" in top.get_ylabel()
    # the convergence panel: log scale, the file's truncation estimate and rk8 closure, K on the twin axis
    assert bottom.get_yscale() == "log"
    conv = lines_by_gid(bottom)
    closure = data(files["fold_hb"], "fold_period_closure")[0]
    np.testing.assert_array_equal(conv["fold_period_closure:0"].get_ydata(), closure)
    assert np.all(closure < 1e-6)  # the rk8 period from the fold's state closes
    trunc = data(files["fold_hb"], "convergence/harmonics_error")[0]
    np.testing.assert_array_equal(conv["convergence/harmonics_error:0"].get_ydata(), np.where(trunc > 0, trunc, np.nan))
    assert "convergence/absorber_spread:0" not in conv  # not computed for this file: not drawn
    assert conv["harmonics_tol"].get_ydata()[0] == pytest.approx(1e-9)
    (k_line,) = k_axis.get_lines()
    np.testing.assert_array_equal(k_line.get_ydata(), data(files["fold_hb"], "harmonics")[0])
    assert bottom.get_xlabel().startswith(r"driving frequency $\Omega$")
    # the legends sit right of the panels, off the data
    fig.canvas.draw()
    for ax in (top, bottom):
        assert ax.get_legend().get_window_extent().x0 >= ax.get_window_extent().x1
    assert "harmonic balance" in fig._suptitle.get_text() and "$N$ = 40" in fig._suptitle.get_text()


def test_fold_line_alone(files, tmp_path, call_main):
    """Without companions (plot.py): the fold line and A_s only, drawn into a PNG."""
    fig = figures.draw(reader.open_scene(files["fold_hb"]))
    assert sorted(lines_by_gid(fig.get_axes()[0])) == ["A_s", "fold_hb:0"]
    proc = call_main(plot_main, files["fold_hb"], "-o", tmp_path / "hb.png")
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "hb.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "(harmonic balance): Omega 0.7: A_f = " in proc.stdout


def test_charts_of_the_shooting_fold_line_refuse_it(files):
    """threshold_sg and ramp090 draw shooting's loss of stability: a file by harmonic balance is one line of
    PlotError, not a KeyError."""
    hb = reader.open_scene(files["fold_hb"])
    with pytest.raises(reader.PlotError, match="fold line by harmonic balance"):
        figures.draw_thresholds(hb)
    scan = reader.open_scene(files["scan"])
    with pytest.raises(reader.PlotError, match="fold line by harmonic balance"):
        figures.draw_ramp([scan], hb)


# ------------------------------------------------------------------------------------------------ the continuum


def test_continuum_figure(files):
    path = files["continuum"]
    s = reader.open_scene(path)
    fig = figures.draw(s)
    axes = np.array(fig.get_axes()).reshape(2, -1)
    omega, cs = data(path, "omega"), data(path, "continuum/c")
    folds, limit = data(path, "continuum/folds"), data(path, "continuum/fold")
    error, spread = data(path, "continuum/error_estimate"), data(path, "convergence/absorber_spread")
    np.testing.assert_array_equal(cs, [4.0, 8.0, 16.0])
    assert axes.shape == (2, omega.size)
    for w in range(omega.size):
        top, zoom = axes[:, w]
        assert top.get_title().startswith(rf"$\Omega$ = {omega[w]:g}")
        assert zoom.get_xlabel() == "$1/c^2$"
        for ax in (top, zoom):
            got = lines_by_gid(ax)
            np.testing.assert_allclose(got["folds:0"].get_xdata(), 1.0 / cs**2)  # one point per c
            np.testing.assert_array_equal(got["folds:0"].get_ydata(), folds[0, w])
        # the limit at 1/c^2 = 0 with the file's error estimate as its bar
        (bar,) = [c for c in top.containers if c.get_label().startswith("limit")]
        np.testing.assert_array_equal(bar.lines[0].get_xdata(), [0.0])
        np.testing.assert_array_equal(bar.lines[0].get_ydata(), [limit[0, w]])
        (segment,) = bar.lines[2][0].get_segments()
        np.testing.assert_allclose(segment[:, 1], [limit[0, w] - error[0, w], limit[0, w] + error[0, w]])
        # the Richardson line of the two largest c ends at the limit
        line = lines_by_gid(top)["richardson:0"]
        np.testing.assert_allclose(line.get_xdata(), [0.0, 1.0 / 64.0])
        np.testing.assert_allclose(line.get_ydata(), [limit[0, w], folds[0, w, -2]])
        # A_s of each c (the file's own A_s at the base c = 4) and of the continuum, 4 arccos(Omega)
        a_s = lines_by_gid(top)["A_s:0"].get_ydata()
        assert a_s[0] == pytest.approx(data(path, "threshold_As")[0, w], rel=1e-12)
        assert a_s[0] < a_s[1] < a_s[2] < 4 * math.acos(omega[w])
        star = lines_by_gid(top)["A_s_continuum:0"]
        assert star.get_xdata()[0] == 0.0 and star.get_ydata()[0] == pytest.approx(4 * math.acos(omega[w]))
        # the absorber spread as the error bar of the base chain's fold, only on the zoom
        (bar,) = [c for c in zoom.containers if c.get_label().startswith("absorber spread")]
        (segment,) = bar.lines[2][0].get_segments()
        base = data(path, "fold_amplitude")[0, w]
        np.testing.assert_allclose(segment, [[1 / 16, base - spread[0, w]], [1 / 16, base + spread[0, w]]])
        assert not [c for c in top.containers if c.get_label().startswith("absorber spread")]
    assert folds[0, 0, 0] == pytest.approx(data(path, "fold_amplitude")[0, 0], abs=1e-12)  # c = 4 is the base chain
    fig.canvas.draw()
    legend = axes[0, -1].get_legend()
    assert legend.get_window_extent().x0 >= axes[0, -1].get_window_extent().x1  # off the data
    assert "continuum limit" in fig._suptitle.get_text() and "$N$ = 40 at $c$ = 4" in fig._suptitle.get_text()


def test_fold_line_of_a_file_with_the_absorber_family(files):
    """The convergence panel of a fold line shows the absorber spread when the file has it (the continuum file,
    drawn as a fold line)."""
    s = reader.open_scene(files["continuum"])
    bottom = harmonic.draw_fold_line_hb(s).get_axes()[1]
    line = lines_by_gid(bottom)["convergence/absorber_spread:0"]
    np.testing.assert_array_equal(line.get_ydata(), data(files["continuum"], "convergence/absorber_spread")[0])


def test_summary_of_the_continuum(files):
    s = reader.open_scene(files["continuum"])
    (head, line) = figures.summary(s, full=True)
    assert head == str(files["continuum"])
    af = data(files["continuum"], "fold_amplitude")[0]
    assert f"Omega 0.7: A_f = {af[0]:.8f} (K " in line and "rk8 closure" in line
    assert line.count("limit c -> inf") == 2 and "A_s(inf) = " + f"{4 * math.acos(0.9):.5g}" in line
    spread = data(files["continuum"], "convergence/absorber_spread")[0, 1]
    semi = data(files["continuum"], "convergence/fold_semi_infinite")[0, 1]
    digits = harmonic.decimals(spread)
    assert f"semi-infinite chain {semi:.{digits}f}," in line  # no more digits than the spread allows


def test_decimals_follow_the_uncertainty():
    assert harmonic.decimals(0.018) == 2 and harmonic.decimals(3e-6) == 6 and harmonic.decimals(0.5) == 1
    assert harmonic.decimals(float("nan")) == 10 and harmonic.decimals(0.0) == 10 and harmonic.decimals(30.0) == 0


def test_threshold_as_of_a_chain_and_its_continuum():
    assert harmonic.threshold_as(4.0, 0.9) == pytest.approx(1.80333178, abs=1e-8)  # the file's /threshold_As
    assert harmonic.threshold_as(1e4, 0.5) == pytest.approx(4 * math.acos(0.5), abs=1e-7)
    assert math.isnan(harmonic.threshold_as(4.0, 1.1)) and math.isnan(harmonic.threshold_as_continuum(1.0))


# ------------------------------------------------------------------------------------------------ make_figures


def test_quick_copies_of_the_harmonic_balance_namelists(tmp_path):
    """--quick: the fold line from Omega = 0.15 by 0.1 (Omega = 0.05 alone costs minutes), the continuum's three
    frequencies kept and c = 32 dropped; a shooting fold line keeps its own grid."""
    def quick(stem: str) -> dict:
        copy = namelist.quick_copy(ROOT / "input" / f"{stem}.nml", tmp_path / f"{stem}.nml", tmp_path / "x.h5")
        return namelist.read(copy)["scene"]

    hb = quick("fold_hb_sg")
    assert (hb["omega_min"], hb["omega_max"], hb["omega_step"]) == (0.15, 0.99, 0.1)
    cont = quick("fold_continuum")
    assert (cont["omega_min"], cont["omega_max"], cont["omega_step"]) == (0.5, 0.9, 0.2)
    assert cont["c_values"] == [4.0, 8.0, 16.0] and cont["absorber_family"] == 2
    shoot = quick("fold_sg")
    assert (shoot["omega_min"], shoot["omega_step"]) == (0.05, 0.1)


def test_make_figures_draws_both_at_200_dpi(files, tmp_path, call_main, monkeypatch):
    """`--no-run --only fold_hb_sg fold_continuum` on namelists whose outputs are the tiny files: fold_hb_sg
    takes its scan along (COMPANIONS) and the shooting fold line of fold_sg from its file, though fold_sg is not
    among the jobs (SHOOTING_OF); every figure is saved at the house style's 200 dpi, the scan too."""
    inp = tmp_path / "input"
    inp.mkdir()
    for stem, name in (("fold_hb_sg", "fold_hb"), ("fold_continuum", "continuum"), ("fold_sg", "shooting"),
                       ("bif_undamped_sg", "scan")):
        kind = "bifurcation" if name == "scan" else "continuation"
        (inp / f"{stem}.nml").write_text(f"&scene kind = '{kind}' /\n&output file = '{files[name]}' /\n")
    drawn = []

    def spy(s, scan=None, shooting=None):
        drawn.append((s.name, scan, shooting))
        return draw(s, scan, shooting)

    saved = {}

    def save(fig, path, dpi):
        saved[Path(path).stem] = dpi
        return write(fig, path, dpi=dpi)

    draw, write = figures.draw_continuation, runner.style.save
    monkeypatch.setattr(figures, "draw_continuation", spy)
    monkeypatch.setattr(runner.style, "save", save)
    figs = tmp_path / "figs"
    proc = call_main(runner.main, "--no-run", "--input", inp, "--outdir", figs, "--only", "fold_hb_sg",
                     "fold_continuum")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    for stem in ("fold_hb_sg", "fold_continuum", "bif_undamped_sg"):
        assert (figs / f"{stem}.png").is_file(), (stem, proc.stdout)
    assert not (figs / "fold_sg.png").exists()  # not run nor drawn: only beside the fold line by harmonic balance
    (_, scan, shooting), = [d for d in drawn if d[0] == "fold_hb"]
    assert scan.path == str(files["scan"]) and shooting.path == str(files["shooting"])
    assert saved == {"fold_hb_sg": 200, "fold_continuum": 200, "bif_undamped_sg": 200}
    assert proc.stdout.count("(harmonic balance): Omega 0.7: A_f = ") == 2
