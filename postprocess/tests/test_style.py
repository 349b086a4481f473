"""The house style of the figures (issue 42, "figures fit to publish") and the thin verdicts on them, on tiny files
made by the program itself: PNGs at 200 dpi with a vector PDF beside them when asked, the colour-blind-safe
palette, titles in words (never a file stem), files of `make_figures --quick` marked quick; the bifurcation file's
`/verdict_margin` and `/thin_verdict` written with CF flags, read by the reader and the loader, and marked on the
diagrams (bifurcation, sweep, threshold chart)."""
from __future__ import annotations

import dataclasses
import struct
from pathlib import Path

import numpy as np
import pytest

from supratrans_post import figures, reader, style
from supratrans_post.figures import bifurcation, common, sweep

h5py = pytest.importorskip("h5py")
pytest.importorskip("matplotlib")


def png_dpi(path: Path) -> float:
    """The resolution a PNG records (its pHYs chunk, pixels per metre), in dots per inch."""
    data = path.read_bytes()
    i = data.index(b"pHYs")
    ppm_x, _, unit = struct.unpack(">IIB", data[i + 4:i + 13])
    assert unit == 1  # metres
    return ppm_x * 0.0254


def with_input(s: reader.Scene, input_file: str) -> reader.Scene:
    """The same file's Scene as if made from another namelist (the root attribute `input_file`)."""
    return dataclasses.replace(s, attrs={**s.attrs, "input_file": input_file})


def suptitle(fig) -> str:
    return fig._suptitle.get_text() if fig._suptitle is not None else ""


def test_png_at_200_dpi_with_a_vector_pdf_beside_it(tiny, tmp_path):
    s = reader.open_scene(tiny.file("bif3"))
    assert style.DPI == 200
    style.vector_copies(True)
    try:
        path = style.save(figures.draw_bifurcation(s), tmp_path / "b.png")
    finally:
        style.vector_copies(False)
    assert round(png_dpi(path)) == 200
    assert (tmp_path / "b.pdf").read_bytes()[:5] == b"%PDF-"
    # off (plot.py, the charts alone): the PNG only
    style.save(figures.draw_bifurcation(s), tmp_path / "c.png")
    assert (tmp_path / "c.png").is_file() and not (tmp_path / "c.pdf").exists()


def test_palette_is_the_colour_blind_safe_one(tiny):
    okabe_ito = {"#000000", "#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#F0E442"}
    assert set(style.PALETTE.values()) == okabe_ito
    assert set(common.COLOURS[:7]) <= okabe_ito
    fig = figures.draw_sweep(reader.open_scene(tiny.file("fig2")))
    import matplotlib.colors as mc  # noqa: PLC0415

    used = {mc.to_hex(ln.get_color()).upper() for ax in fig.get_axes() for ln in ax.get_lines()
            if ln.get_label() and not ln.get_label().startswith("_")}
    assert used <= {c.upper() for c in okabe_ito} | {"#999999", "#666666"}, used


@pytest.mark.parametrize("stem, words", [("fold_sg_090", "Sine-Gordon chain"), ("my_study_17", "Bifurcation diagram"),
                                         ("bif3", "Bif3")])
def test_titles_are_words_not_file_stems(tiny, stem, words):
    s = with_input(reader.open_scene(tiny.file("bif3")), f"input/{stem}.nml")
    title = suptitle(figures.draw_bifurcation(s))
    assert title.startswith(words + ":"), title
    if stem != "bif3":
        assert stem not in title


@pytest.mark.parametrize("name", ["fig2", "fig11", "bif3", "fig1_sg_A150"])
def test_quick_files_are_drawn_and_marked_quick(tiny, name):
    """A file of `make_figures --quick` (its namelist copied to out/quick/input/) is drawn like any other, its
    title marked quick; the same file from input/ is not."""
    s = reader.open_scene(tiny.file(name))
    quick = with_input(s, f"out/quick/input/{name}.nml")
    full = with_input(s, f"input/{name}.nml")
    assert quick.quick and not full.quick
    assert "quick" in suptitle(figures.draw(quick))
    assert "quick" not in suptitle(figures.draw(full))


def test_thin_verdicts_written_with_cf_flags(tiny):
    """/verdict_margin: the margin of the quiet run just below each threshold (in [0, 1]) where the search found
    one above amplitude_min, NaN elsewhere; /thin_verdict: 1 where it is below the attribute thin_margin, 0
    where not, -1 where there is no margin, with CF flag_values / flag_meanings."""
    with h5py.File(tiny.file("bif3"), "r") as f:
        margin = f["verdict_margin"][()]
        thin = f["thin_verdict"][()]
        status = f["status"][()]
        attrs = dict(f["thin_verdict"].attrs)
        assert f["verdict_margin"].attrs["units"] in (b"1", "1")
    assert margin.shape == thin.shape == status.shape
    np.testing.assert_array_equal(attrs["flag_values"], [-1, 0, 1])
    meanings = attrs["flag_meanings"]
    assert (meanings.decode() if isinstance(meanings, bytes) else meanings) == "no_margin clear thin"
    limit = float(attrs["thin_margin"])
    assert limit == pytest.approx(0.2)
    found = status == 0
    assert found.any()
    assert np.isfinite(margin[found]).all() and (margin[found] >= 0).all() and (margin[found] <= 1).all()
    assert np.isnan(margin[~found]).all() and (thin[~found] == -1).all()
    np.testing.assert_array_equal(thin[found], (margin[found] < limit).astype(int))
    assert int(attrs["thin_verdicts"]) == int((thin == 1).sum())


def test_thin_verdicts_read_and_loaded(tiny):
    path = tiny.file("bif3")
    s = reader.open_scene(path)
    with h5py.File(path, "r") as f:
        np.testing.assert_array_equal(s.data["thin_verdict"], f["thin_verdict"][()])
    assert s.attr("thin_verdict", "thin_margin") == pytest.approx(0.2)
    pytest.importorskip("xarray")
    from supratrans_post import load  # noqa: PLC0415

    ds = load(path)
    ds = ds.to_dataset() if hasattr(ds, "to_dataset") else ds
    var = ds["thin_verdict"]
    assert var.attrs["flag_meanings"].split() == ["no_margin", "clear", "thin"]
    assert "potential" in var.coords


def test_thin_verdicts_marked_on_the_bifurcation_diagram(tiny):
    """Every threshold flagged thin gets an open circle at its (Omega, A); none where nothing is flagged."""
    s = reader.open_scene(tiny.file("bif3"))
    status = np.asarray(s.data["status"])
    thin = np.where(status == 0, 0, -1)
    c, w = np.argwhere(status == 0)[0]
    thin[c, w] = 1
    marked = dataclasses.replace(s, data={**s.data, "thin_verdict": thin})
    circles = [ln for ln in figures.draw_bifurcation(marked).get_axes()[0].get_lines() if ln.get_gid() == "thin"]
    assert len(circles) == 1
    np.testing.assert_allclose(circles[0].get_xdata(), [s.data["omega"][w]])
    np.testing.assert_allclose(circles[0].get_ydata(), [s.data["threshold"][c, w]])
    clear = dataclasses.replace(s, data={**s.data, "thin_verdict": np.where(status == 0, 0, -1)})
    assert not [ln for ln in figures.draw_bifurcation(clear).get_axes()[0].get_lines() if ln.get_gid() == "thin"]


def test_thin_threshold_marked_on_a_sweep(tiny):
    """A sweep's threshold whose run has a thin verdict gets an open circle and its reason."""
    s = reader.open_scene(tiny.file("fig2"))
    amp = np.asarray(s.data["amplitude"], dtype=float)
    status = np.asarray(s.data["runs/status"])
    k = int(np.flatnonzero(status[0] == 0)[-1])  # curve 0 transmits from its last run on (whatever the file says)
    trans = np.zeros_like(np.asarray(s.data["runs/transmitting"]))
    trans[0, k:] = 1
    a = common.first_transmitting(amp, trans[0], status[0])
    assert a == amp[k]
    thin = np.zeros_like(status)
    thin[0, k] = 1
    marked = dataclasses.replace(s, data={**s.data, "runs/thin_verdict": thin, "runs/transmitting": trans})
    assert [(c, x) for c, x, _ in sweep.thin_thresholds(marked)] == [(0, a)]
    fig = figures.draw_sweep(marked)
    assert any(ln.get_gid() == "thin" and ln.get_xdata()[0] == a for ax in fig.get_axes() for ln in ax.get_lines())


def test_energy_jump_of_a_sweep_judged_by_the_files_min_energy_jump(tiny):
    """A threshold whose energy grows by 2x there is thin by the file's `min_energy_jump` (its /parameters attribute):
    at 3 (the default, written by the program) it is, at 1.5 it is not; a file written before the key (no
    attribute) falls back to 3."""
    s = reader.open_scene(tiny.file("fig2"))
    assert s.params["min_energy_jump"] == 3.0
    amp = np.asarray(s.data["amplitude"], dtype=float)
    status = np.asarray(s.data["runs/status"])
    k = int(np.flatnonzero(status[0] == 0)[-1])
    assert k > 0
    trans = np.zeros_like(np.asarray(s.data["runs/transmitting"]))
    trans[0, k:] = 1
    jump = np.full(np.shape(s.data["runs/transmitting"]), np.nan)
    jump[0, k] = 2.0
    data = {**s.data, "runs/transmitting": trans, "runs/energy_jump": jump,
            "runs/thin_verdict": np.zeros_like(status)}
    marked = dataclasses.replace(s, data=data)
    assert sweep.thin_thresholds(marked) == [(0, amp[k], "energy x2 only")]
    lower = dataclasses.replace(marked, params={**s.params, "min_energy_jump": 1.5})
    assert sweep.thin_thresholds(lower) == []
    legacy = dataclasses.replace(marked, params={key: v for key, v in s.params.items() if key != "min_energy_jump"})
    assert sweep.min_energy_jump(legacy) == 3.0
    assert sweep.thin_thresholds(legacy) == [(0, amp[k], "energy x2 only")]


def test_fold_beside_the_curve_of_its_chain(tiny):
    """With a fold-line file, the fold is drawn beside the curves of the same chain only (here the m^2 = 0 curve
    of Bif3's tiny file against a fold file of the massless chain), and the caption says what each curve is."""
    s = reader.open_scene(tiny.file("bif3"))
    values = np.asarray(s.data["curves/value"], dtype=float)
    assert (values == 0).sum() == 1
    z = int(np.argmax(values == 0))
    fold = dataclasses.replace(s, scene="continuation", attrs={**s.attrs, "solver": "harmonic_balance"},
                               data={**s.data, "curves/potential": s.data["curves/potential"][z:z + 1],
                                     "curves/value": values[z:z + 1],
                                     "fold_amplitude": np.asarray(s.data["threshold_As"])[z:z + 1] + 0.1})
    assert [bifurcation._fold_curve(s, c, fold) for c in range(values.size)] == [
        0 if c == z else None for c in range(values.size)]
    fig = figures.draw_bifurcation(s, fold)
    folds = [ln for ln in fig.get_axes()[0].get_lines() if ln.get_gid() == "fold"]
    assert len(folds) == 1 and "harmonic balance" in folds[0].get_label()
    caption = next(t.get_text() for t in fig.texts if t.get_gid() == "caption")
    assert "detector's threshold" in caption and "fold of the driven periodic state" in caption
