"""The paper's figures (supratrans_post.figures) and plot.py on tiny files made by the program itself: every scene
is drawn into a non-empty image with the paper's styles and labels; an image name of an unknown format is one line
and exit status 2. Scenes the program does not know yet are skipped."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from supratrans_post import figures, reader
from supratrans_post.plot import main as plot_main

pytest.importorskip("h5py")
pytest.importorskip("matplotlib")

POSTPROCESS = Path(__file__).resolve().parents[1]


def assert_image(path: Path) -> None:
    assert path.is_file(), path
    head = path.read_bytes()[:8]
    assert head == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 5000


def test_timeseries_one_file(tiny, tmp_path, call_main):
    f = tiny.file("fig1_sg_A250")
    proc = call_main(plot_main, f, "-o", tmp_path / "one.png")
    assert proc.returncode == 0, proc.stderr
    assert_image(tmp_path / "one.png")
    assert "sine-gordon, A = 2.5" in proc.stdout


def test_fig1_grid_of_four_files(tiny, tmp_path, call_main):
    files = [tiny.file(n) for n in ("fig1_kg_A150", "fig1_kg_A250", "fig1_sg_A150", "fig1_sg_A250")]
    fig = figures.draw_timeseries([reader.open_scene(f) for f in files])
    axes = fig.get_axes()
    assert len(axes) == 4
    titles = [a.get_title() for a in axes]
    assert titles[0].startswith("(a) $A$ = 1.5") and "Sine-Gordon" in titles[0]  # the paper's first row
    assert titles[3].startswith("(b) $A$ = 2.5") and "Klein-Gordon" in titles[3]
    assert axes[0].get_ylabel().startswith("$u_{20}(t)$")  # no site 60 in a chain of 40: the middle probe
    proc = call_main(plot_main, *files, "-o", tmp_path / "fig1.png")
    assert proc.returncode == 0, proc.stderr
    assert_image(tmp_path / "fig1.png")


def test_sweep_gamma_family_two_potentials(tiny, tmp_path, call_main):
    f = tiny.file("fig2")
    s = reader.open_scene(f)
    fig = figures.draw_sweep(s)
    axes = fig.get_axes()
    assert [a.get_title() for a in axes] == ["Sine-Gordon chain", "Klein-Gordon chain"]
    lines = [ln for ln in axes[0].get_lines() if ln.get_label().startswith("$\\gamma$")]
    assert [ln.get_linestyle() for ln in lines] == ["-", "--"]  # gamma = 0 solid, 0.03 dashed
    assert "$\\Omega$ = 0.9" in fig._suptitle.get_text() and "Fig. 2" in fig._suptitle.get_text()
    proc = call_main(plot_main, f, "-o", tmp_path / "fig2.png")
    assert proc.returncode == 0, proc.stderr
    assert_image(tmp_path / "fig2.png")
    assert "gamma = 0.03" in proc.stdout
    proc = call_main(plot_main, f, "--energy", "stored", "-o", tmp_path / "stored.png")  # the energy left at T
    assert proc.returncode == 0, proc.stderr
    assert_image(tmp_path / "stored.png")


def test_sweep_mass_family_has_imaginary_and_real_panels(tiny, tmp_path, call_main):
    f = tiny.file("fig3")
    fig = figures.draw_sweep(reader.open_scene(f))
    axes = fig.get_axes()
    assert [a.get_title().split(" (")[0] for a in axes] == ["Pure-imaginary masses", "Real masses"]
    for ax in axes:  # m^2 = 0 in both, solid; the other magnitude dashed
        styled = {ln.get_label(): ln.get_linestyle() for ln in ax.get_lines() if ln.get_label().startswith("$m^2$")}
        assert styled.pop("$m^2$ = 0") == "-" and list(styled.values()) == ["--"]
    proc = call_main(plot_main, f, "-o", tmp_path / "fig3.png")
    assert proc.returncode == 0, proc.stderr
    assert_image(tmp_path / "fig3.png")


def test_map(tiny, tmp_path, call_main):
    f = tiny.file("fig11")
    proc = call_main(plot_main, f, "-o", tmp_path / "fig11.png")
    assert proc.returncode == 0, proc.stderr
    assert_image(tmp_path / "fig11.png")
    fig = figures.draw_map(reader.open_scene(f))
    assert any("A_s" in ln.get_label() for ax in fig.get_axes() for ln in ax.get_lines())
    proc = call_main(plot_main, f, "--surface", "-o", tmp_path / "surface.png")  # the paper's 3-D surfaces
    assert proc.returncode == 0, proc.stderr
    assert_image(tmp_path / "surface.png")


def test_bifurcation(tiny, call_main):
    f = tiny.file("bif3")
    fig = figures.draw_bifurcation(reader.open_scene(f))
    ax = fig.get_axes()[0]
    labels = [ln.get_label() for ln in ax.get_lines()]
    # sqrt(1 + m^2) = 1 + l/40 for l = -4 and 4
    assert any("\\ell$ = -4" in x for x in labels) and any("\\ell$ = 4" in x for x in labels)
    assert any(ln.get_marker() == "x" for ln in ax.get_lines())  # A_s as x-marks
    proc = call_main(plot_main, f)  # default output: next to the file
    assert proc.returncode == 0, proc.stderr
    assert_image(f.with_suffix(".png"))


def test_unknown_image_format_is_one_line(tiny, tmp_path):
    """`plot.py -o x.xyz`: one line and exit status 2 (not a matplotlib traceback), nothing written; the real
    script, as a user runs it."""
    f = tiny.file("fig2")
    out = tmp_path / "x.xyz"
    proc = subprocess.run([sys.executable, str(POSTPROCESS / "plot.py"), str(f), "-o", str(out)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"error: {out}: unknown image format '.xyz'"), proc.stderr
    assert ".png" in lines[0] and ".pdf" in lines[0]  # what would do
    assert proc.stdout == "" and not out.exists()


def test_pdf(tiny, tmp_path, call_main):
    f = tiny.file("fig1_sg_A150")
    proc = call_main(plot_main, f, "-o", tmp_path / "x.pdf", "-q")
    assert proc.returncode == 0 and proc.stderr == "" and proc.stdout == "", proc.stderr
    assert (tmp_path / "x.pdf").read_bytes()[:5] == b"%PDF-"


def test_zoom_window_around_the_jumps():
    amp = np.round(np.arange(1.0, 3.0001, 0.01), 2)
    lo, hi = figures.zoom_window(amp, [1.78, 1.82, float("nan")])
    assert lo < 1.78 and hi > 1.82 and hi - lo < 0.3
    assert figures.zoom_window(amp, [1.2, 2.8]) is None  # the jumps already fill the plot
    assert figures.zoom_window(amp, [float("nan")]) is None  # no jump: nothing to zoom on
