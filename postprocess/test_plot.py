"""The plotting scripts on small files made by the program itself (tiny chains, short times): every scene is
drawn into a non-empty image; a file of the wrong scene, with a dataset missing, truncated, not HDF5 or absent
gives one line `error: <file>: ...` on stderr and exit status 2; a partial snapshot is drawn and marked as such.
Scenes the program does not know yet are skipped."""
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

h5py = pytest.importorskip("h5py")
pytest.importorskip("matplotlib")

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))

import make_figures  # noqa: E402
import supratrans_plot as sp  # noqa: E402

PLOT = [sys.executable, str(HERE / "plot.py")]
ENV = {**os.environ, "MPLBACKEND": "Agg"}

SMALL = """&chain
    potential = '{potential}'
    n = 40
    n0 = 30
/
&drive
    amplitude = {amplitude}
    ramp_time = 5.0
/
&numerics
    t_final = {t_final}
/
&record
    probes = 1, 20, 30
/
"""
OUTPUT = """&output
    file = '{out}'
    overwrite = .true.
    quiet = .true.
/
"""
#: The tiny scenes: name (the figure the stem stands for) -> (&scene group, T).
SCENES = {
    "fig2": ("""&scene
    kind = 'amplitude_sweep'
    potentials = 'sine-gordon', 'klein-gordon'
    vary = 'gamma'
    values = 0.0, 0.03
    amplitude_min = 1.0
    amplitude_max = 2.0
    amplitude_step = 0.5
/
""", 20.0),
    "fig3": ("""&scene
    kind = 'amplitude_sweep'
    potentials = 'sine-gordon'
    vary = 'm2'
    values = -0.01, 0.0, 0.01
    amplitude_min = 1.0
    amplitude_max = 2.0
    amplitude_step = 0.5
/
""", 20.0),
    "fig11": ("""&scene
    kind = 'map'
    potentials = 'sine-gordon', 'klein-gordon'
    amplitude_min = 1.0
    amplitude_max = 2.0
    amplitude_step = 0.5
    omega_min = 0.5
    omega_max = 0.9
    omega_step = 0.4
/
""", 20.0),
    "bif3": ("""&scene
    kind = 'bifurcation'
    vary = 'm2'
    values = -0.19, 0.0, 0.21
    amplitude_min = 1.0
    amplitude_max = 4.0
    coarse_step = 1.0
    resolution = 0.25
    omega_min = 0.7
    omega_max = 1.0
    omega_step = 0.3
/
""", 20.0),
}


@pytest.fixture(scope="module")
def exe():
    """The supratrans executable (debug profile, built by fpm in the repository)."""
    subprocess.run(["fpm", "build"], cwd=ROOT, check=True, capture_output=True)
    out = subprocess.run(["fpm", "run", "--runner", "echo"], cwd=ROOT, check=True, capture_output=True, text=True)
    return str(ROOT / out.stdout.strip().splitlines()[-1].split()[0])


@pytest.fixture(scope="module")
def data(exe, tmp_path_factory):
    """Run the program on the tiny namelists once; {name: path of its HDF5 file, or the reason it is missing}."""
    d = tmp_path_factory.mktemp("data")
    files = {}
    jobs = {}
    for p, pot in (("s", "sine-gordon"), ("k", "klein-gordon")):
        for a in (150, 250):
            name = f"fig1_{p}g_A{a}"
            jobs[name] = (SMALL.format(potential=pot, amplitude=a / 100, t_final=10.0), d / f"{name}.h5")
    for name, (scene, t_final) in SCENES.items():
        jobs[name] = (SMALL.format(potential="sine-gordon", amplitude=1.77, t_final=t_final).replace(
            "probes = 1, 20, 30", "probes = 1") + scene, d / f"{name}.h5")
    for name, (text, out) in jobs.items():
        nml = d / f"{name}.nml"
        nml.write_text(text + OUTPUT.format(out=out))
        proc = subprocess.run([exe, str(nml)], cwd=d, capture_output=True, text=True, timeout=120)
        files[name] = out if proc.returncode == 0 and out.is_file() else (proc.stderr.strip() or "no file")
    return files


def need(data, name):
    """The file of a tiny scene, or skip the test when the program does not know that scene (yet)."""
    f = data[name]
    if isinstance(f, Path):
        return f
    if "not implemented" in f or "&scene: kind" in f:
        pytest.skip(f"the program cannot write this scene yet: {f.splitlines()[-1]}")
    pytest.fail(f"the program failed on the tiny {name} namelist: {f}")


def plot(*args):
    return subprocess.run(PLOT + [str(a) for a in args], capture_output=True, text=True, env=ENV, timeout=120)


def assert_image(path):
    assert path.is_file(), path
    head = path.read_bytes()[:8]
    assert head == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 5000


def assert_one_line_error(proc, *words):
    assert proc.returncode == 2, (proc.returncode, proc.stderr)
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith("error: "), lines[0]
    for w in words:
        assert w in lines[0], (w, lines[0])
    return lines[0]


# ------------------------------------------------------------------------------------------------ drawing


def test_timeseries_one_file(data, tmp_path):
    f = need(data, "fig1_sg_A250")
    proc = plot(f, "-o", tmp_path / "one.png")
    assert proc.returncode == 0, proc.stderr
    assert_image(tmp_path / "one.png")
    assert "sine-gordon, A = 2.5" in proc.stdout


def test_fig1_grid_of_four_files(data, tmp_path):
    files = [need(data, n) for n in ("fig1_kg_A150", "fig1_kg_A250", "fig1_sg_A150", "fig1_sg_A250")]
    fig = sp.draw_timeseries([sp.open_scene(f) for f in files])
    axes = fig.get_axes()
    assert len(axes) == 4
    titles = [a.get_title() for a in axes]
    assert titles[0].startswith("(a) $A$ = 1.5") and "Sine-Gordon" in titles[0]  # the paper's first row
    assert titles[3].startswith("(b) $A$ = 2.5") and "Klein-Gordon" in titles[3]
    assert axes[0].get_ylabel().startswith("$u_{20}(t)$")  # no site 60 in a chain of 40: the middle probe
    proc = plot(*files, "-o", tmp_path / "fig1.png")
    assert proc.returncode == 0, proc.stderr
    assert_image(tmp_path / "fig1.png")


def test_sweep_gamma_family_two_potentials(data, tmp_path):
    f = need(data, "fig2")
    s = sp.open_scene(f)
    fig = sp.draw_sweep(s)
    axes = fig.get_axes()
    assert [a.get_title() for a in axes] == ["Sine-Gordon chain", "Klein-Gordon chain"]
    lines = [ln for ln in axes[0].get_lines() if ln.get_label().startswith("$\\gamma$")]
    assert [ln.get_linestyle() for ln in lines] == ["-", "--"]  # gamma = 0 solid, 0.03 dashed
    assert "$\\Omega$ = 0.9" in fig._suptitle.get_text() and "Fig. 2" in fig._suptitle.get_text()
    proc = plot(f, "-o", tmp_path / "fig2.png")
    assert proc.returncode == 0, proc.stderr
    assert_image(tmp_path / "fig2.png")
    assert "gamma = 0.03" in proc.stdout
    proc = plot(f, "--energy", "stored", "-o", tmp_path / "stored.png")  # the energy left in the chain at T
    assert proc.returncode == 0, proc.stderr
    assert_image(tmp_path / "stored.png")


def test_sweep_mass_family_has_imaginary_and_real_panels(data, tmp_path):
    f = need(data, "fig3")
    fig = sp.draw_sweep(sp.open_scene(f))
    axes = fig.get_axes()
    assert [a.get_title().split(" (")[0] for a in axes] == ["Pure-imaginary masses", "Real masses"]
    for ax in axes:  # m^2 = 0 in both, solid; the other magnitude dashed
        styled = {ln.get_label(): ln.get_linestyle() for ln in ax.get_lines() if ln.get_label().startswith("$m^2$")}
        assert styled.pop("$m^2$ = 0") == "-" and list(styled.values()) == ["--"]
    proc = plot(f, "-o", tmp_path / "fig3.png")
    assert proc.returncode == 0, proc.stderr
    assert_image(tmp_path / "fig3.png")


def test_map(data, tmp_path):
    f = need(data, "fig11")
    proc = plot(f, "-o", tmp_path / "fig11.png")
    assert proc.returncode == 0, proc.stderr
    assert_image(tmp_path / "fig11.png")
    fig = sp.draw_map(sp.open_scene(f))
    assert any("A_s" in ln.get_label() for ax in fig.get_axes() for ln in ax.get_lines())


def test_bifurcation(data, tmp_path):
    f = need(data, "bif3")
    fig = sp.draw_bifurcation(sp.open_scene(f))
    ax = fig.get_axes()[0]
    labels = [ln.get_label() for ln in ax.get_lines()]
    # sqrt(1 + m^2) = 1 + l/40 for l = -4 and 4
    assert any("\\ell$ = -4" in x for x in labels) and any("\\ell$ = 4" in x for x in labels)
    assert any(ln.get_marker() == "x" for ln in ax.get_lines())  # A_s as x-marks
    proc = plot(f)  # default output: next to the file
    assert proc.returncode == 0, proc.stderr
    assert_image(f.with_suffix(".png"))


# ------------------------------------------------------------------------------------------------ errors


def test_wrong_scene(data, tmp_path):
    f = need(data, "fig1_sg_A150")
    assert_one_line_error(plot("--scene", "amplitude_sweep", f), str(f), "scene is 'timeseries'")
    bogus = tmp_path / "bogus.h5"
    shutil.copy(f, bogus)
    with h5py.File(bogus, "r+") as h:
        h.attrs["scene"] = np.bytes_("hologram")
    assert_one_line_error(plot(bogus), str(bogus), "unknown scene 'hologram'")
    with h5py.File(bogus, "r+") as h:
        del h.attrs["scene"]
    assert_one_line_error(plot(bogus), "not a supratrans output file")
    assert not bogus.with_suffix(".png").exists()


def test_fig1_refuses_a_file_of_another_scene(data, tmp_path):
    f = need(data, "fig2")
    g = need(data, "fig1_sg_A150")
    assert_one_line_error(plot(g, f, "-o", tmp_path / "x.png"), str(f), "only timeseries files")


@pytest.mark.parametrize("name, dataset", [("fig1_sg_A150", "probes/u"), ("fig2", "energy/injected"),
                                           ("fig11", "threshold_As"), ("bif3", "threshold")])
def test_missing_dataset(data, tmp_path, name, dataset):
    f = need(data, name)
    broken = tmp_path / f.name
    shutil.copy(f, broken)
    with h5py.File(broken, "r+") as h:
        del h[dataset]
    assert_one_line_error(plot(broken), str(broken), f"dataset '/{dataset}' missing")


def test_dataset_of_the_wrong_shape(data, tmp_path):
    f = need(data, "fig2")
    broken = tmp_path / "fig2.h5"
    shutil.copy(f, broken)
    with h5py.File(broken, "r+") as h:
        e = h["energy/injected"][()]
        del h["energy/injected"]
        h["energy/injected"] = e[:, :-1]
    assert_one_line_error(plot(broken), "'/energy/injected' has shape")


def test_truncated_file(data, tmp_path):
    f = need(data, "fig1_sg_A150")
    cut = tmp_path / "cut.h5"
    raw = f.read_bytes()
    cut.write_bytes(raw[: len(raw) // 2])
    assert_one_line_error(plot(cut), str(cut), "truncated")


def test_not_hdf5_and_absent(tmp_path):
    text = tmp_path / "notes.h5"
    text.write_text("not an HDF5 file\n")
    assert_one_line_error(plot(text), str(text), "not an HDF5 file")
    assert_one_line_error(plot(tmp_path / "nowhere.h5"), "nowhere.h5", "no such file")


# ------------------------------------------------------------------------------------------------ partial files


def make_partial(complete, partial, keep):
    """A partial snapshot as the program writes it (complete = 0, runs not done NaN with status -1), made from a
    complete file by forgetting all runs but the first `keep`."""
    shutil.copy(complete, partial)
    with h5py.File(partial, "r+") as h:
        status_name = "runs/status" if h.attrs["scene"] != b"bifurcation" else "status"
        status = h[status_name][()]
        lost = np.arange(status.size).reshape(status.shape) >= keep
        for name, obj in list(h.items()) + list(h.get("energy", {}).items()) + list(h.get("runs", {}).items()):
            if isinstance(obj, h5py.Dataset) and obj.shape == status.shape and obj.dtype.kind == "f":
                v = obj[()]
                v[lost] = np.nan
                obj[...] = v
        status[lost] = -1
        h[status_name][...] = status
        h.attrs["complete"] = np.int32(0)
        if "runs_done" in h.attrs:
            h.attrs["runs_done"] = np.int32(keep)
        else:
            h.attrs["tasks_done"] = np.int32(keep)
    return status.size


@pytest.mark.parametrize("name", ["fig2", "fig11", "bif3"])
def test_partial_snapshot_is_drawn_and_marked(data, tmp_path, name):
    f = need(data, name)
    final = tmp_path / f.name  # does not exist: the scene is 'still running'
    total = make_partial(f, Path(str(final) + ".partial.h5"), keep=3)
    what = "threshold searches" if name.startswith("bif") else "runs"
    s = sp.open_scene(final)
    assert s.partial and s.partial_note() == f"partial: 3 of {total} {what}"
    fig = sp.draw(s)
    assert f"partial: 3 of {total} {what}" in fig._suptitle.get_text()
    proc = plot(final)
    assert proc.returncode == 0, proc.stderr
    assert "partial snapshot" in proc.stderr
    assert_image(tmp_path / f"{f.stem}.partial.png")


# ------------------------------------------------------------------------------------------------ make_figures


def test_namelist_reading():
    text = """! comment with / and &fake
&scene kind = 'map', omega_step = 0.05 / ! trailing
&output
    file = '/tmp/x/y.h5'   ! a path with slashes
    overwrite = .true.
/
"""
    g = make_figures._groups(text)
    assert make_figures._key(g["scene"], "kind") == "map"
    assert make_figures._key(g["output"], "file") == "/tmp/x/y.h5"
    assert make_figures._key(g["scene"], "omega_step") == "0.05"
    assert make_figures._key(g["output"], "profile") is None


def test_make_figures_runs_and_draws(tmp_path):
    """The whole command on a folder of two tiny namelists: progress line per scene, then the figures."""
    inp = tmp_path / "input"
    inp.mkdir()
    for a in (150, 250):
        out = tmp_path / "out" / f"fig1_sg_A{a}.h5"
        (inp / f"fig1_sg_A{a}.nml").write_text(SMALL.format(potential="sine-gordon", amplitude=a / 100, t_final=5.0)
                                               + OUTPUT.format(out=out))
    (inp / "broken.nml").write_text("&chain n = 1 /\n" + OUTPUT.format(out=tmp_path / "out" / "broken.h5"))
    (inp / "other.nml").write_text("&scene kind = 'timeseries' /\n")  # no &output file: listed and skipped
    cmd = [sys.executable, str(HERE / "make_figures.py"), "--input", inp, "--outdir", tmp_path / "figs",
           "--logs", tmp_path / "logs"]
    proc = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, env=ENV, timeout=300)
    lines = proc.stdout.splitlines()
    assert proc.returncode == 1, proc.stdout + proc.stderr  # broken.nml fails, the others go on
    assert any(x.startswith("[1/3] ") and x.endswith(" s") and "fig1_sg_A150.nml" in x for x in lines), lines
    assert any(x.startswith("[3/3] ") and "broken.nml" in x and "FAILED" in x for x in lines), lines
    assert any("other.nml" in x and "skipped" in x for x in lines), lines  # nothing to draw: not run
    assert_image(tmp_path / "figs" / "fig1.png")
    assert not (tmp_path / "figs" / "broken.png").exists()
    assert "n = 1" in (tmp_path / "logs" / "broken.log").read_text()  # the program's own message, kept


def test_quick_copy_coarsens_the_grid(tmp_path):
    nml = tmp_path / "fig2.nml"
    nml.write_text("&scene\n    kind = 'amplitude_sweep'\n    amplitude_step = 0.01  ! fine\n/\n"
                   "&output\n    file = 'out/fig2.h5'\n/\n")
    q = make_figures.quick_copy(make_figures.Job(nml), tmp_path / "quick")
    g = make_figures._groups(q.nml.read_text())
    assert float(make_figures._key(g["scene"], "amplitude_step")) == pytest.approx(0.05)
    assert q.output == tmp_path / "quick" / "fig2.h5" and q.figure == "fig2"
    assert make_figures._key(g["output"], "overwrite") == ".true."


def test_zoom_window_around_the_jumps():
    amp = np.round(np.arange(1.0, 3.0001, 0.01), 2)
    lo, hi = sp._zoom_window(amp, [1.78, 1.82, float("nan")])
    assert lo < 1.78 and hi > 1.82 and hi - lo < 0.3
    assert sp._zoom_window(amp, [1.2, 2.8]) is None  # the jumps already fill the plot
    assert sp._zoom_window(amp, [float("nan")]) is None  # no jump: nothing to zoom on


def test_unknown_image_type_is_one_line(data, tmp_path):
    f = need(data, "fig1_sg_A250")
    proc = plot(f, "-o", tmp_path / "x.xyz")
    assert_one_line_error(proc, "x.xyz", "unknown image type")
    assert not (tmp_path / "x.xyz").exists()
