"""The one reader of the program's HDF5 files (supratrans_post.reader), on tiny files made by the program: every
dataset its schema names is written by the program; a file of the wrong scene, with a dataset missing or of the
wrong shape, truncated, not HDF5 or absent gives one line `error: <file>: ...` on stderr and exit status 2 (through
plot.py); a partial snapshot is read, drawn and marked as such."""
from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from supratrans_post import figures, reader
from supratrans_post.charts.stability import main as chart_stability_main
from supratrans_post.plot import main as plot_main

h5py = pytest.importorskip("h5py")
pytest.importorskip("matplotlib")

#: A tiny file of each scene (conftest.tiny_namelists).
EACH_SCENE = {"timeseries": "fig1_sg_A150", "amplitude_sweep": "fig2", "map": "fig11", "bifurcation": "bif3",
              "work_precision": "wp_sg", "stability": "stab"}


def assert_one_line_error(proc, *words: str) -> str:
    assert proc.returncode == 2, (proc.returncode, proc.stderr)
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith("error: "), lines[0]
    for w in words:
        assert w in lines[0], (w, lines[0])
    return lines[0]


def assert_image(path: Path) -> None:
    assert path.is_file(), path
    head = path.read_bytes()[:8]
    assert head == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 5000


# ------------------------------------------------------------------------------------------------ the schema


@pytest.mark.parametrize("scene", sorted(EACH_SCENE))
def test_schema_names_only_what_the_program_writes(tiny, scene):
    """Every dataset of the scene's schema, optional ones too, is in the program's file, with the schema's rank."""
    f = tiny.file(EACH_SCENE[scene])
    s = reader.open_scene(f, expect=scene)
    assert s.scene == scene and s.params
    assert sorted(s.data) == sorted(reader.SCHEMA[scene])
    for name, (dims, _) in reader.SCHEMA[scene].items():
        assert s.data[name].ndim == len(dims), name


# ------------------------------------------------------------------------------------------------ errors


def test_wrong_scene(tiny, tmp_path, call_main):
    f = tiny.file("fig1_sg_A150")
    assert_one_line_error(call_main(plot_main, "--scene", "amplitude_sweep", f), str(f), "scene is 'timeseries'")
    bogus = tmp_path / "bogus.h5"
    shutil.copy(f, bogus)
    with h5py.File(bogus, "r+") as h:
        h.attrs["scene"] = np.bytes_("hologram")
    assert_one_line_error(call_main(plot_main, bogus), str(bogus), "unknown scene 'hologram'")
    with h5py.File(bogus, "r+") as h:
        del h.attrs["scene"]
    assert_one_line_error(call_main(plot_main, bogus), "not a supratrans output file")
    assert not bogus.with_suffix(".png").exists()


def test_chart_scene_is_not_a_figure(tiny, call_main):
    f = tiny.file("stab")
    assert_one_line_error(call_main(plot_main, f), str(f), "scene is 'stability', expected")


def test_fig1_refuses_a_file_of_another_scene(tiny, tmp_path, call_main):
    f = tiny.file("fig2")
    g = tiny.file("fig1_sg_A150")
    assert_one_line_error(call_main(plot_main, g, f, "-o", tmp_path / "x.png"), str(f), "only timeseries files")


@pytest.mark.parametrize("name, dataset", [("fig1_sg_A150", "probes/u"), ("fig2", "energy/injected"),
                                           ("fig11", "threshold_As"), ("bif3", "threshold")])
def test_missing_dataset(tiny, tmp_path, call_main, name, dataset):
    f = tiny.file(name)
    broken = tmp_path / f.name
    shutil.copy(f, broken)
    with h5py.File(broken, "r+") as h:
        del h[dataset]
    assert_one_line_error(call_main(plot_main, broken), str(broken), f"dataset '/{dataset}' missing")


def test_dataset_of_the_wrong_shape(tiny, tmp_path, call_main):
    f = tiny.file("fig2")
    broken = tmp_path / "fig2.h5"
    shutil.copy(f, broken)
    with h5py.File(broken, "r+") as h:
        e = h["energy/injected"][()]
        del h["energy/injected"]
        h["energy/injected"] = e[:, :-1]
    assert_one_line_error(call_main(plot_main, broken), "'/energy/injected' has shape")


def test_dataset_of_the_wrong_rank(tiny, tmp_path):
    f = tiny.file("fig11")
    broken = tmp_path / "fig11.h5"
    shutil.copy(f, broken)
    with h5py.File(broken, "r+") as h:
        a = h["threshold_As"][()]
        del h["threshold_As"]
        h["threshold_As"] = a.ravel()
    with pytest.raises(reader.PlotError, match=r"'/threshold_As' has shape \(\d+,\), expected rank 2"):
        reader.open_scene(broken)


def test_truncated_file(tiny, tmp_path, call_main):
    f = tiny.file("fig1_sg_A150")
    cut = tmp_path / "cut.h5"
    raw = f.read_bytes()
    cut.write_bytes(raw[: len(raw) // 2])
    assert_one_line_error(call_main(plot_main, cut), str(cut), "truncated")


def test_not_hdf5_and_absent(tmp_path, call_main):
    text = tmp_path / "notes.h5"
    text.write_text("not an HDF5 file\n")
    assert_one_line_error(call_main(plot_main, text), str(text), "not an HDF5 file")
    assert_one_line_error(call_main(plot_main, tmp_path / "nowhere.h5"), "nowhere.h5", "no such file")


def replace_dataset(path: Path, name: str, data) -> None:
    """Write `data` in place of the dataset `name` of the file `path`, its attributes kept."""
    with h5py.File(path, "r+") as h:
        attrs = dict(h[name].attrs)
        del h[name]
        h[name] = data
        h[name].attrs.update(attrs)


#: An axis of each scene drawn, and the command that draws it.
AXIS_OF = [("fig2", "amplitude", "plot"), ("fig11", "omega", "plot"), ("bif3", "omega", "plot"),
           ("fig1_sg_A150", "probes/time", "plot"), ("stab", "c", "chart")]


@pytest.mark.parametrize("name, axis, how", AXIS_OF)
def test_axis_of_text_is_one_line(tiny, tmp_path, call_main, name, axis, how):
    """Issue 22: an axis holding text was a ValueError traceback (could not convert string to float)."""
    broken = tmp_path / f"{name}.h5"
    shutil.copy(tiny.file(name), broken)
    n = reader.open_scene(broken).data[axis].size
    replace_dataset(broken, axis, np.array([b"x%d" % i for i in range(n)]))
    main = plot_main if how == "plot" else chart_stability_main
    assert_one_line_error(call_main(main, broken, "-o", tmp_path / "x.png"), str(broken),
                          f"dataset '/{axis}' holds text, expected numbers")
    assert not (tmp_path / "x.png").exists()


@pytest.mark.parametrize("name, axis, how", AXIS_OF)
def test_axis_of_nan_is_one_line(tiny, tmp_path, call_main, name, axis, how):
    """Issue 22: an all-NaN axis was a traceback (axis limits cannot be NaN, pcolormesh) or a figure of nothing;
    one NaN in a grid axis is refused as well."""
    broken = tmp_path / f"{name}.h5"
    shutil.copy(tiny.file(name), broken)
    values = np.asarray(reader.open_scene(broken).data[axis], dtype=float)
    replace_dataset(broken, axis, np.full(values.shape, np.nan))
    main = plot_main if how == "plot" else chart_stability_main
    assert_one_line_error(call_main(main, broken, "-o", tmp_path / "x.png"), str(broken),
                          f"axis '/{axis}' has no finite value")
    values[-1] = np.inf
    replace_dataset(broken, axis, values)
    assert_one_line_error(call_main(main, broken, "-o", tmp_path / "x.png"), "not finite", f"index {values.size - 1}")
    assert not (tmp_path / "x.png").exists()


# ------------------------------------------------------------------------------------------------ dimension scales


def small_sweep(path: Path, attribute: str | None = "curve, amplitude") -> Path:
    """A minimal amplitude_sweep file written by h5py (2 curves x 3 amplitudes), without dimension scales;
    `attribute`: the attribute `dimensions` of /energy/injected (as the program writes today), or none."""
    with h5py.File(path, "w") as h:
        h.attrs["scene"] = np.bytes_("amplitude_sweep")
        h.create_group("parameters").attrs["omega"] = 0.9
        h["amplitude"] = np.array([1.0, 1.5, 2.0])
        h["amplitude_doubled"] = np.array([2.0, 3.0, 4.0])
        h["curves/potential"] = np.array([b"sine-gordon", b"klein-gordon"])
        h["curves/value"] = np.array([np.nan, np.nan])
        h["energy/injected"] = np.arange(6.0).reshape(2, 3)
        if attribute is not None:
            h["energy/injected"].attrs["dimensions"] = np.bytes_(attribute)
        h["runs/status"] = np.zeros((2, 3), dtype=np.int32)
        h["runs/transmitting"] = np.zeros((2, 3), dtype=np.int32)
    return path


def test_dimensions_without_scales_come_from_the_attribute_then_the_schema(tmp_path):
    s = reader.open_scene(small_sweep(tmp_path / "a.h5", "curve, drive amplitude"))
    assert s.dims["energy/injected"] == ("curve", "drive amplitude")  # today's attribute
    assert s.dims["runs/status"] == ("curve", "amplitude")  # no attribute: the schema
    assert s.scales == {}
    assert list(s.coordinate("energy/injected", 1)) == [1.0, 1.5, 2.0]  # the schema's axis dataset /amplitude
    assert s.coordinate("energy/injected", 0) is None  # the curves have no axis dataset
    s = reader.open_scene(small_sweep(tmp_path / "b.h5", "only one name"))  # not one name per dimension
    assert s.dims["energy/injected"] == ("curve", "amplitude")


def test_dimension_scales_are_preferred(tmp_path):
    """A dimension scale attached (`ds.dims[i][0]`) names the axis and gives its values, before the attribute
    `dimensions` and the schema: here a scale other than /amplitude, so that the two cannot be confused."""
    path = small_sweep(tmp_path / "scaled.h5")
    with h5py.File(path, "r+") as h:
        h["amplitude_doubled"].make_scale("twice A")
        h["energy/injected"].dims[1].attach_scale(h["amplitude_doubled"])
        h["amplitude"].make_scale("")  # a scale without a name: named by its path
        h["runs/status"].dims[1].attach_scale(h["amplitude"])
        assert h["energy/injected"].dims[1][0].name == "/amplitude_doubled"
    s = reader.open_scene(path)
    assert s.dims["energy/injected"] == ("curve", "twice A")
    assert s.dims["runs/status"] == ("curve", "amplitude")
    assert list(s.coordinate("energy/injected", 1)) == [2.0, 3.0, 4.0]
    assert list(s.coordinate("runs/status", 1)) == [1.0, 1.5, 2.0]
    assert list(s.data["amplitude"]) == [1.0, 1.5, 2.0]  # the data read as before


@pytest.mark.parametrize("bad, words", [(np.array([1.0, 2.0]), "has shape (2,), expected (3,)"),
                                        (np.array([1.0, np.nan, 2.0]), "not finite"),
                                        (np.array([b"a", b"b", b"c"]), "holds text")])
def test_a_bad_dimension_scale_is_one_line(tmp_path, bad, words):
    path = small_sweep(tmp_path / "bad.h5")
    with h5py.File(path, "r+") as h:
        h["axis"] = bad
        h["axis"].make_scale("A")
        h["energy/injected"].dims[1].attach_scale(h["axis"])
    with pytest.raises(reader.PlotError) as err:
        reader.open_scene(path)
    line = err.value.line()
    assert line.startswith(f"error: {path}: ") and "\n" not in line and words in line and "/axis" in line, line


# ------------------------------------------------------------------------------------------------ partial files


def make_partial(complete: Path, partial: Path, keep: int) -> int:
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
def test_partial_snapshot_is_drawn_and_marked(tiny, tmp_path, call_main, name):
    f = tiny.file(name)
    final = tmp_path / f.name  # does not exist: the scene is 'still running'
    total = make_partial(f, Path(str(final) + ".partial.h5"), keep=3)
    what = "threshold searches" if name.startswith("bif") else "runs"
    s = reader.open_scene(final)
    assert s.partial and s.partial_note() == f"partial: 3 of {total} {what}"
    fig = figures.draw(s)
    assert f"partial: 3 of {total} {what}" in fig._suptitle.get_text()
    proc = call_main(plot_main, final)
    assert proc.returncode == 0, proc.stderr
    assert "partial snapshot" in proc.stderr
    assert_image(tmp_path / f"{f.stem}.partial.png")
