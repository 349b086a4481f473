"""Every dataset's axes as HDF5 dimension scales (issue 21): for each scene's tiny file (conftest's `tiny`), every
dataset with a `dimensions` attribute has each dimension labelled with its name and its scale attached, so that
h5py's `ds.dims[i][0]` is the axis.

The scale of a dimension named `d` of a dataset in group `G` (docs/output.md, supratrans_h5_scales): an axis written
with its own name (`/amplitude`, `/probes/time`, `/methods`) is the scale itself; else the coordinate dataset, the
first of `G/d`, `d` in each parent group up to the root, then the same with the plural `ds`, that is
one-dimensional and of the dimension's length; else the index scale `/d` (0, 1, ..., n - 1), or `/d_index` where
`/d` is something else. Found here independently of the program, from the file's contents.
Also: `/curves` is the same in every scene, `/curves/value` in the units of the varied parameter; and xarray (through
h5netcdf, where installed) opens every group of every file with named dimensions.
"""
from __future__ import annotations

import h5py
import numpy as np
import pytest

#: The tiny files of every scene (conftest.tiny_namelists): one timeseries, the grid scenes, work_precision, stability.
FILES = ["fig1_sg_A150", "fig2", "fig3", "fig11", "bif3", "wp_sg", "stab"]


def text(value) -> str:
    """An attribute as str (h5py gives fixed-length strings as bytes)."""
    return value.decode() if isinstance(value, bytes) else str(value)


def coordinate(f: h5py.File, ds: h5py.Dataset, name: str, length: int) -> str | None:
    """The path of the coordinate dataset of dimension `name` (of `length`) of `ds`, None if there is none."""
    for plural in ("", "s"):
        group = ds.name.rsplit("/", 1)[0]
        while True:
            path = f"{group}/{name}{plural}"
            obj = f.get(path)
            if (path != ds.name and isinstance(obj, h5py.Dataset) and obj.ndim == 1 and obj.shape[0] == length):
                return path
            if not group:
                break
            group = group.rsplit("/", 1)[0]
    return None


def with_dimensions(f: h5py.File) -> list[h5py.Dataset]:
    """Every dataset of the file that has a `dimensions` attribute."""
    found = []
    f.visititems(lambda _, obj: found.append(obj)
                 if isinstance(obj, h5py.Dataset) and "dimensions" in obj.attrs else None)
    return found


@pytest.mark.parametrize("name", FILES)
def test_every_named_dimension_has_its_scale(tiny, name):
    attached = 0
    with h5py.File(tiny.file(name), "r") as f:
        datasets = with_dimensions(f)
        assert datasets, "no dataset names its dimensions"
        for ds in datasets:
            names = [n.strip() for n in text(ds.attrs["dimensions"]).split(",")]
            assert len(names) == ds.ndim, f"{ds.name}: dimensions {names} for shape {ds.shape}"
            for i, dim in enumerate(names):
                assert ds.dims[i].label == dim, f"{ds.name}: dimension {i} labelled {ds.dims[i].label!r}, not {dim!r}"
                scales = [s.name for s in ds.dims[i].values()]
                if ds.ndim == 1 and ds.name.rsplit("/", 1)[-1] in (dim, dim + "s"):
                    assert h5py.h5ds.is_scale(ds.id) and scales == [], f"{ds.name} is not its own scale"
                    continue
                coord = coordinate(f, ds, dim, ds.shape[i])
                if coord is None:
                    coord = f"/{dim}" if not isinstance(f.get(f"/{dim}"), h5py.Dataset) or \
                        h5py.h5ds.is_scale(f[f"/{dim}"].id) and f[f"/{dim}"].ndim == 1 else f"/{dim}_index"
                    assert (f[coord][()] == np.arange(ds.shape[i])).all(), f"{coord} is not an index"
                assert scales == [coord], f"{ds.name}: dimension {dim!r} has scales {scales}, not [{coord}]"
                assert ds.dims[i][0].name == coord
                assert h5py.h5ds.is_scale(f[coord].id), f"{coord} is not a dimension scale"
                attached += 1
    assert attached > 0, "no dimension scale attached in the whole file"


@pytest.mark.parametrize("name,axes", [
    ("fig2", {"/energy/injected": ["/curve", "/amplitude"]}),
    ("fig11", {"/energy/injected": ["/curve", "/omega", "/amplitude"], "/threshold_As": ["/curve", "/omega"]}),
    ("bif3", {"/threshold": ["/curve", "/omega"], "/curves/value": ["/curve"]}),
    ("stab", {"/verdict/newton": ["/curve", "/c", "/dt"]}),
    ("wp_sg", {"/error_u": ["/amplitude", "/methods", "/dt_index"], "/dt": ["/methods", "/dt_index"]}),
    ("fig1_sg_A150", {"/probes/u": ["/probe", "/probes/time"], "/ledger/stored": ["/ledger/time"]}),
])
def test_the_axes_of_a_few_results(tiny, name, axes):
    """A few results' axes named outright (the rule above could agree with a wrong attachment)."""
    with h5py.File(tiny.file(name), "r") as f:
        for path, expected in axes.items():
            ds = f[path]
            got = [ds.dims[i][0].name if len(ds.dims[i]) else None for i in range(ds.ndim)]
            assert got == expected, f"{name}{path}: axes {got}"


#: The units of `/curves/value` for each value of the /curves attribute `vary`.
VALUE_UNITS = {"gamma": "1/time", "beta": "1/time", "m2": "1/time^2", "none": "1"}


@pytest.mark.parametrize("name", ["fig2", "fig3", "fig11", "bif3", "stab"])
def test_curves_written_once_with_one_set_of_units(tiny, name):
    with h5py.File(tiny.file(name), "r") as f:
        curves = f["/curves"]
        vary = text(curves.attrs["vary"])
        assert text(curves["value"].attrs["units"]) == VALUE_UNITS[vary], f"{name}: vary = {vary}"
        assert {"potential", "value", "gamma", "beta", "m2", "band_gap_edge"} <= set(curves), sorted(curves)
        assert text(curves["gamma"].attrs["units"]) == "1/time"
        assert text(curves["m2"].attrs["units"]) == "1/time^2"
        if vary != "none":
            assert (curves["value"][()] == curves[vary][()]).all(), f"{name}: /curves/value is not /curves/{vary}"


@pytest.mark.parametrize("name", FILES)
def test_xarray_opens_every_group(tiny, name):
    """xarray (engine h5netcdf) refuses a dataset with scales on some dimensions only: every group opens, and its
    dimensions are named."""
    xr = pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    path = tiny.file(name)
    with h5py.File(path, "r") as f:
        groups = [""]
        f.visititems(lambda n, o: groups.append(n) if isinstance(o, h5py.Group) else None)
    for group in groups:
        with xr.open_dataset(path, engine="h5netcdf", group=group or None) as ds:
            assert not [d for d in ds.sizes if str(d).startswith("phony_dim")], f"{name}/{group}: {dict(ds.sizes)}"
