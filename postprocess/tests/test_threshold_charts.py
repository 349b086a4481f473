"""The charts of the model's threshold against the protocols' (supratrans_post.figures.threshold) on small
synthetic files of the three scenes (continuation, bifurcation, hysteresis) with known numbers: what is drawn is
what the files hold (the shaded windows span the edges, the fold line is the fold), and make_figures.py finds the
charts' files (`--only threshold_sg` and `--only ramp090` take their companions along)."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from supratrans_post import figures, namelist, reader, runner
from supratrans_post.figures import threshold

h5py = pytest.importorskip("h5py")
pytest.importorskip("matplotlib")
pytest.importorskip("f90nml")

OMEGA = np.array([0.5, 0.7, 0.9])
FOLD = np.array([[4.6835, 3.3021, 1.8342]])
INSTABILITY = np.array([[3.3439, np.nan, 1.8266]])
AS = np.array([[4.1854, 3.1819, 1.8032]])
SCAN = np.array([[4.60, 3.31, 1.78]])


def _write(path: Path, scene: str, params: dict, data: dict) -> Path:
    """A file of `scene` with the root attribute, /parameters and the datasets `data` (units 'rad' on all)."""
    with h5py.File(path, "w") as h:
        h.attrs["scene"] = scene
        g = h.create_group("parameters")
        for k, v in params.items():
            g.attrs[k] = v
        h.create_group("curves").attrs["vary"] = "none"
        for name, value in data.items():
            d = h.create_dataset(name, data=value)
            d.attrs["units"] = "rad"
    return path


def fold_file(path: Path, omega=OMEGA, fold=FOLD, inst=INSTABILITY, a_s=AS) -> Path:
    n = len(omega)
    pts = 4
    branch = {f"branch/{k}": np.zeros((1, n, pts)) for k in ("amplitude", "umax", "stable", "multiplier_max")}
    return _write(path, "continuation", {"c": 4.0, "n": 200, "method": "newton", "dt": 0.05, "gamma": 0.0,
                                         "beta": 0.0, "m2": 0.0},
                  {"omega": np.asarray(omega, dtype=float), "curves/potential": np.array([b"sine-gordon"]),
                   "curves/value": np.zeros(1), "fold_amplitude": fold, "threshold": np.fmin(fold, inst),
                   "threshold_kind": np.zeros((1, n), dtype=np.int32), "instability_amplitude": inst,
                   "instability_type": np.full((1, n), 3, dtype=np.int32), "threshold_As": a_s,
                   "status": np.zeros((1, n), dtype=np.int32), "branch/points": np.full((1, n), pts, dtype=np.int32),
                   **branch})


def scan_file(path: Path, omega=OMEGA, thr=SCAN, ramp=50.0, resolution=0.01) -> Path:
    n = len(omega)
    return _write(path, "bifurcation", {"c": 4.0, "n": 200, "dt": 0.05, "t_final": ramp + 200.0, "ramp_time": ramp,
                                        "resolution": resolution, "gamma": 0.0, "beta": 0.0, "m2": 0.0},
                  {"omega": np.asarray(omega, dtype=float), "curves/potential": np.array([b"sine-gordon"]),
                   "curves/value": np.zeros(1), "threshold": np.asarray(thr, dtype=float),
                   "threshold_As": AS[:, :n], "status": np.zeros((1, n), dtype=np.int32)})


def hysteresis_file(path: Path, omega, up, down) -> Path:
    """Stairs of lengths 200 and 400 at the frequencies `omega`; up and down: (omega, length) edges."""
    up, down = np.asarray(up, dtype=float)[None], np.asarray(down, dtype=float)[None]
    n, k = up.shape[1], up.shape[2]
    levels = np.array([1.0, 1.5, 2.0, 1.5, 1.0])
    return _write(path, "hysteresis", {"c": 4.0, "n": 200, "dt": 0.05, "stair_height": 0.5, "stair_ramp": 10.0,
                                       "gamma": 0.0, "beta": 0.0, "m2": 0.0},
                  {"omega": np.asarray(omega, dtype=float), "stair_time": np.array([200.0, 400.0])[:k],
                   "stair_amplitude": levels, "stair_direction": np.array([1, 1, 1, -1, -1], dtype=np.int32),
                   "curves/potential": np.array([b"sine-gordon"]), "curves/value": np.zeros(1),
                   "upward_threshold": up, "downward_threshold": down, "window": up - down,
                   "status": np.zeros(up.shape, dtype=np.int32), "upward_spread": np.zeros((1, n)),
                   "downward_spread": np.zeros((1, n)), "power": np.zeros((1, n, k, levels.size))})


def windows(fig) -> dict[str, list[np.ndarray]]:
    """The shaded hysteresis windows of the main axes: {gid: [vertices of each polygon]}."""
    out: dict[str, list[np.ndarray]] = {}
    for coll in fig.get_axes()[0].collections:
        gid = coll.get_gid()
        if gid and gid.startswith("window:"):
            out[gid] = [p.vertices for p in coll.get_paths()]
    return out


def test_threshold_chart_at_one_hysteresis_frequency(tmp_path):
    """At the one frequency of the hysteresis file (0.9) the main axes carry one bar at Omega = 0.9 itself from the
    lowest downward to the highest upward edge; the inset draws each stair length's window at its true stair length
    (T_s = 200, 400: no made-up abscissae) spanning exactly the file's downward .. upward edge; the fold line, the
    scan and A_s are the files' numbers; the legend is one, below the axes, of fewer than 12 entries."""
    up, down = [[1.84, 1.86]], [[1.52, 1.46]]
    fold = reader.open_scene(fold_file(tmp_path / "fold.h5"))
    scan = reader.open_scene(scan_file(tmp_path / "scan.h5"))
    hyst = reader.open_scene(hysteresis_file(tmp_path / "hyst.h5", [0.9], up, down))
    fig = figures.draw_thresholds(fold, scan, hyst)
    main = fig.get_axes()[0]
    (bar,) = [ln for ln in main.get_lines() if ln.get_gid() == "window"]
    np.testing.assert_array_equal(bar.get_xdata(), [0.9, 0.9])
    np.testing.assert_allclose(bar.get_ydata(), [1.46, 1.86])
    (inset,) = main.child_axes
    got = {ln.get_gid(): ln for ln in inset.get_lines() if (ln.get_gid() or "").startswith("window:")}
    assert sorted(got) == ["window:200", "window:400"]
    for i, (gid, ts) in enumerate((("window:200", 200.0), ("window:400", 400.0))):
        np.testing.assert_array_equal(got[gid].get_xdata(), [ts, ts])
        np.testing.assert_allclose(got[gid].get_ydata(), [down[0][i], up[0][i]])
    assert inset.get_xscale() == "log"
    assert not windows(fig)  # no shaded areas at invented frequencies
    (legend,) = fig.legends
    assert len(legend.get_texts()) < 12
    assert main.get_legend() is None  # off the data
    ax = fig.get_axes()[0]
    lines = {ln.get_label(): ln for ln in ax.get_lines()}
    fold_line = next(ln for lab, ln in lines.items() if lab.startswith("fold $A_f$"))
    np.testing.assert_array_equal(fold_line.get_ydata(), FOLD[0])
    scan_line = next(ln for lab, ln in lines.items() if lab.startswith("ramped scan"))
    np.testing.assert_array_equal(scan_line.get_ydata(), SCAN[0])
    assert "ramp 50" in scan_line.get_label()
    a_s = next(ln for lab, ln in lines.items() if lab.startswith("$A_s"))
    np.testing.assert_array_equal(a_s.get_ydata(), AS[0])
    lost = next(ln for lab, ln in lines.items() if lab.startswith("first loss"))
    np.testing.assert_array_equal(lost.get_ydata(), [3.3439, 1.8266])  # only where it comes before the fold
    text = " ".join(threshold.summary_thresholds(fold, scan, hyst))
    assert "A_f = 1.8342" in text and "T_s 400: up 1.86 down 1.46" in text and "scan 1.78" in text


def test_threshold_chart_over_frequencies(tmp_path):
    """A hysteresis file over several frequencies: one window per stair length spanning, at each frequency, the
    edges of the file; a frequency without a downward edge leaves a gap; no zoom."""
    om = [0.7, 0.8, 0.9]
    up = [[3.4, 3.5], [2.7, 2.75], [1.84, 1.84]]
    down = [[2.9, 2.8], [np.nan, 2.3], [1.52, 1.46]]
    fold = reader.open_scene(fold_file(tmp_path / "fold.h5"))
    hyst = reader.open_scene(hysteresis_file(tmp_path / "hyst.h5", om, up, down))
    fig = figures.draw_thresholds(fold, None, hyst)
    got = windows(fig)
    for i, gid in enumerate(("window:200", "window:400")):
        verts = np.concatenate(got[gid])
        for w, (u, d) in enumerate(zip(np.array(up)[:, i], np.array(down)[:, i])):
            at = verts[np.isclose(verts[:, 0], om[w])]
            if np.isnan(d):
                assert at.size == 0, (gid, om[w])
            else:
                assert at[:, 1].min() == pytest.approx(d) and at[:, 1].max() == pytest.approx(u)
    assert not fig.get_axes()[0].child_axes


def test_threshold_chart_refuses_swapped_files(tmp_path):
    fold = reader.open_scene(fold_file(tmp_path / "fold.h5"))
    scan = reader.open_scene(scan_file(tmp_path / "scan.h5"))
    with pytest.raises(reader.PlotError, match="not 'continuation'"):
        figures.draw_thresholds(scan, fold)
    with pytest.raises(reader.PlotError, match="not 'bifurcation'"):
        figures.draw_thresholds(fold, fold)


def test_ramp_chart(tmp_path):
    """The scans sorted by ramp time, each threshold with its bracket below it (the resolution), the fold of the
    continuation file at the scans' frequency as a line; scans at two frequencies are refused."""
    ramps = {400.0: 1.82, 20.0: 1.68, 100.0: 1.795}
    scans = [reader.open_scene(scan_file(tmp_path / f"r{int(r)}.h5", [0.9], [[a]], ramp=r, resolution=0.005))
             for r, a in ramps.items()]
    fold = reader.open_scene(fold_file(tmp_path / "fold.h5"))
    fig = figures.draw_ramp(scans, fold)
    ax = fig.get_axes()[0]
    pts = next(ln for ln in ax.get_lines() if ln.get_marker() == "s")
    np.testing.assert_array_equal(pts.get_xdata(), [20.0, 100.0, 400.0])
    np.testing.assert_array_equal(pts.get_ydata(), [1.68, 1.795, 1.82])
    bars = ax.collections[0].get_segments()
    assert [tuple(np.round(s[:, 1], 6)) for s in bars] == [(1.675, 1.68), (1.79, 1.795), (1.815, 1.82)]
    (fold_line,) = [ln for ln in ax.get_lines() if ln.get_gid() == "fold"]
    assert fold_line.get_ydata()[0] == pytest.approx(1.8342)
    assert "T$ = ramp + 200" in fig._suptitle.get_text()
    line = figures.summary_ramp(scans, fold)[0]
    assert "ramp 20: 1.68 (-0.1542)" in line and "ramp 400: 1.82 (-0.0142)" in line
    other = reader.open_scene(scan_file(tmp_path / "w.h5", [0.7], [[3.3]], ramp=50.0))
    with pytest.raises(reader.PlotError, match="several frequencies"):
        figures.draw_ramp(scans + [other], fold)
    far = reader.open_scene(fold_file(tmp_path / "far.h5", [0.5], FOLD[:, :1], INSTABILITY[:, :1], AS[:, :1]))
    with pytest.raises(reader.PlotError, match="no fold at Omega = 0.9"):
        figures.draw_ramp(scans, far)


NML = "&scene kind = '{kind}', omega_step = 0.01 /\n&output file = '{out}' /\n"


def _inputs(tmp_path: Path) -> Path:
    """A folder of namelists whose outputs are synthetic files: the fold line, its scan and hysteresis, the fold at
    0.9 and two ramp scans, and an unrelated one."""
    inp, out = tmp_path / "input", tmp_path / "out"
    inp.mkdir()
    out.mkdir()
    kinds = {"fold_sg": "continuation", "bif_undamped_sg": "bifurcation", "hysteresis": "hysteresis",
             "fold_sg_090": "continuation", "ramp090_t0020": "bifurcation", "ramp090_t0400": "bifurcation",
             "bif2": "bifurcation"}
    for stem, kind in kinds.items():
        (inp / f"{stem}.nml").write_text(NML.format(kind=kind, out=out / f"{stem}.h5"))
    fold_file(out / "fold_sg.h5")
    scan_file(out / "bif_undamped_sg.h5")
    scan_file(out / "bif2.h5")
    hysteresis_file(out / "hysteresis.h5", [0.9], [[1.84, 1.86]], [[1.52, 1.46]])
    fold_file(out / "fold_sg_090.h5", [0.9], FOLD[:, 2:], INSTABILITY[:, 2:], AS[:, 2:])
    scan_file(out / "ramp090_t0020.h5", [0.9], [[1.68]], ramp=20.0)
    scan_file(out / "ramp090_t0400.h5", [0.9], [[1.82]], ramp=400.0)
    return inp


@pytest.mark.parametrize("only, drawn, not_drawn", [
    ("threshold_sg", ["threshold_sg", "fold_sg", "bif_undamped_sg", "hysteresis"], ["ramp090", "bif2"]),
    ("ramp090", ["ramp090", "fold_sg_090"], ["threshold_sg", "fold_sg", "bif2"]),
])
def test_make_figures_draws_the_charts_with_their_companions(tmp_path, call_main, only, drawn, not_drawn):
    inp = _inputs(tmp_path)
    figs = tmp_path / "figs"
    proc = call_main(runner.main, "--no-run", "--input", inp, "--outdir", figs, "--only", only)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    for name in drawn:
        assert (figs / f"{name}.png").is_file(), (name, proc.stdout)
    for name in not_drawn:
        assert not (figs / f"{name}.png").exists(), name
    if only == "ramp090":
        assert "ramp 20: 1.68 (-0.1542), ramp 400: 1.82 (-0.0142)" in proc.stdout
    else:
        assert "T_s 200: up 1.84 down 1.52" in proc.stdout


def test_ramp_namelists_belong_to_one_figure(tmp_path):
    p = tmp_path / "ramp090_t0800.nml"
    p.write_text(NML.format(kind="bifurcation", out="out/x.h5"))
    assert runner.Job(p).figure == "ramp090"


def test_quick_copy_of_a_fold_line_takes_every_tenth_frequency(tmp_path):
    """A continuation scene's frequency step is scaled by 10 in --quick (a fold costs seconds to minutes), a
    bifurcation scene's still by 2."""
    for kind, factor in (("continuation", 10.0), ("bifurcation", 2.0)):
        src = tmp_path / f"{kind}.nml"
        src.write_text(NML.format(kind=kind, out="out/x.h5"))
        copy = namelist.quick_copy(src, tmp_path / "q" / src.name, tmp_path / "q" / "x.h5")
        assert namelist.read(copy)["scene"]["omega_step"] == pytest.approx(0.01 * factor)


def test_fold_line_over_the_scan(tmp_path):
    """The fold line of a continuation file over several frequencies, with a scan (make_figures' fold_sg.png):
    the curve's style (which names a marker) and the fold line's own marker do not clash."""
    fold = reader.open_scene(fold_file(tmp_path / "fold.h5"))
    scan = reader.open_scene(scan_file(tmp_path / "scan.h5"))
    ax = figures.draw_continuation(fold, scan).get_axes()[0]
    (line,) = [ln for ln in ax.get_lines() if ln.get_label().startswith("fold $A_f$")]
    np.testing.assert_array_equal(line.get_ydata(), FOLD[0])
    assert line.get_marker() == "."


def test_branch_points_without_multipliers_take_their_neighbours_verdict():
    """With floquet_every > 1 most branch points have no verdict (-1 in /branch/stable): they are drawn as the
    computed points on both sides when these agree (the branch at Omega = 0.5 was all dashed before), unknown
    between a stable and an unstable one, as the nearest computed point at the ends."""
    from supratrans_post.figures.continuation import verdicts

    got = verdicts(np.array([-1, 1, -1, -1, 1, -1, 0, -1, -1, 0, -1], dtype=float))
    np.testing.assert_array_equal(got, [1, 1, 1, 1, 1, -1, 0, 0, 0, 0, 0])
    np.testing.assert_array_equal(verdicts(np.array([-1.0, -1.0])), [-1, -1])


def test_folds_past_which_the_chain_stays_localized_are_marked(tmp_path):
    """A fold line with /fold_fate: the folds of fate 2 (the chain stays localized past them) get their own marker,
    at their fold amplitudes, on both fold-line charts; a file without /fold_fate marks none."""
    path = fold_file(tmp_path / "fold.h5")
    plain = reader.open_scene(path)
    lines = figures.draw_thresholds(plain).get_axes()[0].get_lines()
    assert not any("stays localized" in ln.get_label() for ln in lines)
    with h5py.File(path, "a") as h:
        h.create_dataset("fold_fate", data=np.array([[1, 2, 1]], dtype=np.int32))
        h.create_dataset("transmission_fold", data=np.array([[FOLD[0, 0], 3.9, FOLD[0, 2]]]))
        h.create_dataset("branches", data=np.array([[1, 2, 1]], dtype=np.int32))
    fold = reader.open_scene(path)
    for fig in (figures.draw_thresholds(fold), figures.draw_continuation(fold, None)):
        (line,) = [ln for ln in fig.get_axes()[0].get_lines() if "stays localized" in ln.get_label()]
        np.testing.assert_array_equal(line.get_xdata(), [OMEGA[1]])
        np.testing.assert_array_equal(line.get_ydata(), [FOLD[0, 1]])
    # the fold of the later branch past which the chain transmits, only where it is not the first fold (both charts)
    for fig in (figures.draw_thresholds(fold), figures.draw_continuation(fold, None)):
        (star,) = [ln for ln in fig.get_axes()[0].get_lines() if "later branch" in ln.get_label()]
        np.testing.assert_array_equal(star.get_ydata(), [np.nan, 3.9, np.nan])


def test_transmission_past_a_loss_of_stability_is_marked(tmp_path):
    """A fold line with /branch_switch: where the chain transmits past a loss of stability below the fold (switch >
    0: past a branch point, or on stairs past a torus) is marked at /transmission_fold on both fold-line charts,
    and not taken for a later branch's fold; a file without /branch_switch marks none."""
    path = fold_file(tmp_path / "fold.h5")
    assert not any("past a loss of stability" in ln.get_label()
                   for ln in figures.draw_thresholds(reader.open_scene(path)).get_axes()[0].get_lines())
    with h5py.File(path, "a") as h:
        h.create_dataset("fold_fate", data=np.array([[1, 2, 1]], dtype=np.int32))
        h.create_dataset("transmission_fold", data=np.array([[3.5, 3.9, FOLD[0, 2] - 0.3]]))
        h.create_dataset("branches", data=np.array([[3, 2, 1]], dtype=np.int32))
        h.create_dataset("branch_switch", data=np.array([[2, 0, 4]], dtype=np.int32))
    fold = reader.open_scene(path)
    for fig in (figures.draw_thresholds(fold), figures.draw_continuation(fold, None)):
        (line,) = [ln for ln in fig.get_axes()[0].get_lines() if "past a loss of stability" in ln.get_label()]
        np.testing.assert_array_equal(line.get_ydata(), [3.5, np.nan, FOLD[0, 2] - 0.3])
    (star,) = [ln for ln in figures.draw_thresholds(fold).get_axes()[0].get_lines() if "later branch" in ln.get_label()]
    np.testing.assert_array_equal(star.get_ydata(), [np.nan, 3.9, np.nan])
    text = "\n".join(figures.summary(fold, full=True))
    assert "transmits at 3.5 past the branch point (subcritical)" in text
    assert text.count("past the branch point") == 1
    assert text.count("on stairs past the loss") == 1
    with h5py.File(path, "a") as h:
        h["branch_switch"][0, 0] = 5    # a branch point known only to its bracket, the other branch inside it
    fold = reader.open_scene(path)
    (line,) = [ln for ln in figures.draw_thresholds(fold).get_axes()[0].get_lines()
               if "past a loss of stability" in ln.get_label()]
    np.testing.assert_array_equal(line.get_ydata(), [3.5, np.nan, FOLD[0, 2] - 0.3])
    assert "transmits at 3.5 past the branch point (side unknown: only bracketed)" in "\n".join(
        figures.summary(fold, full=True))


def test_a_stair_from_where_the_chain_settled_is_marked_apart(tmp_path):
    """/transmission_stairs 1 with no loss below the fold (/branch_switch 0): the chain settled past a localized fold
    on no stable periodic state and transmitted on a stair from there. That is marked as a stair, not as a later
    branch's fold, and the summary says so."""
    path = fold_file(tmp_path / "fold.h5")
    with h5py.File(path, "a") as h:
        h.create_dataset("fold_fate", data=np.array([[2, 2, 1]], dtype=np.int32))
        h.create_dataset("transmission_fold", data=np.array([[4.2, 3.9, FOLD[0, 2]]]))
        h.create_dataset("branches", data=np.array([[2, 2, 1]], dtype=np.int32))
        h.create_dataset("branch_switch", data=np.array([[0, 0, 0]], dtype=np.int32))
        h.create_dataset("transmission_stairs", data=np.array([[1, 0, 0]], dtype=np.int32))
    fold = reader.open_scene(path)
    for fig in (figures.draw_thresholds(fold), figures.draw_continuation(fold, None)):
        lines = fig.get_axes()[0].get_lines()
        (stair,) = [ln for ln in lines if "stair on which" in ln.get_label()]
        np.testing.assert_array_equal(stair.get_ydata(), [4.2, np.nan, np.nan])
        (star,) = [ln for ln in lines if "later branch" in ln.get_label()]
        np.testing.assert_array_equal(star.get_ydata(), [np.nan, 3.9, np.nan])
    text = "\n".join(figures.summary(fold, full=True))
    assert text.count("transmits at 4.2 on stairs from where the chain settled") == 1


def test_a_stair_is_drawn_with_the_spread_of_its_climbs(tmp_path):
    """/transmission_spread where /transmission_fold is a stair: an error bar of that half-height at the stair, none
    elsewhere, on both fold-line charts, and the summary gives the spread beside the stair."""
    path = fold_file(tmp_path / "fold.h5")
    with h5py.File(path, "a") as h:
        h.create_dataset("fold_fate", data=np.array([[2, 1, 1]], dtype=np.int32))
        h.create_dataset("transmission_fold", data=np.array([[4.2, FOLD[0, 1], FOLD[0, 2]]]))
        h.create_dataset("branches", data=np.array([[2, 1, 1]], dtype=np.int32))
        h.create_dataset("branch_switch", data=np.array([[0, 0, 0]], dtype=np.int32))
        h.create_dataset("transmission_stairs", data=np.array([[1, 0, 0]], dtype=np.int32))
        h.create_dataset("transmission_spread", data=np.array([[0.03, np.nan, np.nan]]))
    fold = reader.open_scene(path)
    for fig in (figures.draw_thresholds(fold), figures.draw_continuation(fold, None)):
        (bars,) = [c for c in fig.get_axes()[0].containers if "spread of the climbs" in str(c.get_label())]
        (segment,) = [s for s in bars.lines[2][0].get_segments() if s.size and np.all(np.isfinite(s))]
        np.testing.assert_allclose(segment[:, 1], [4.17, 4.23])
    text = "\n".join(figures.summary(fold, full=True))
    assert text.count("transmits at 4.2 (climbs spread by 0.03) on stairs from where the chain settled") == 1


def test_past_a_torus_where_no_stair_transmits_the_summary_names_the_fold(tmp_path):
    """/branch_switch 4 with /transmission_stairs 0: the stairs from the loss reached the fold without transmitting
    and the number is the fold's (input/fold_sg_050.nml); the summary says so and does not call it a stair."""
    path = fold_file(tmp_path / "fold.h5")
    with h5py.File(path, "a") as h:
        h.create_dataset("fold_fate", data=np.array([[1, 1, 1]], dtype=np.int32))
        h.create_dataset("transmission_fold", data=FOLD)
        h.create_dataset("branches", data=np.array([[1, 1, 1]], dtype=np.int32))
        h.create_dataset("branch_switch", data=np.array([[4, 0, 0]], dtype=np.int32))
        h.create_dataset("transmission_stairs", data=np.array([[0, 0, 0]], dtype=np.int32))
    text = "\n".join(figures.summary(reader.open_scene(path), full=True))
    assert text.count("past the fold (the stairs from the loss did not transmit below it)") == 1
    assert "on stairs" not in text
