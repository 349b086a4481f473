"""`supratrans_post.load`: a file as labelled xarray data, on a tiny file of every scene made by the program (the
session's `tiny` files of conftest.py, plus a tiny continuation and hysteresis made here): every variable has its
axes as coordinates (the root's in every group), `curve` carries `potential` (str) and the varied parameter, status
variables carry CF `flag_values`/`flag_meanings` covering every code they hold, every variable `long_name` and
`units`, text is str, and the numbers are the file's. The codes' free text is parsed in each form the program writes
it. And what plain `xarray.open_datatree` gives: the axes in every group today; with the attributes docs/output.md
names for the Fortran side, str potentials, flags and curve labels too."""
from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from conftest import TinyFiles
from supratrans_post import load
from supratrans_post.dataset import flag_words, parse_codes
from supratrans_post.reader import PlotError

h5py = pytest.importorskip("h5py")
xr = pytest.importorskip("xarray")
pytest.importorskip("h5netcdf")

#: A tiny continuation (one fold, N = 20: about 1 s with the debug build) and hysteresis (three stairs of 40 up).
EXTRA = {
    "fold": """&chain n = 20, n0 = 14 /
&numerics dt = 0.1 /
&scene kind = 'continuation', omega_min = 0.8, omega_max = 0.8, omega_step = 0.1, amplitude_max = 4.0,
  fold_convergence = .false. /
""",
    "hyst": """&chain n = 30, n0 = 20 /
&drive ramp_time = 10 /
&numerics dt = 0.1 /
&scene kind = 'hysteresis', omega_min = 0.9, omega_max = 0.9, omega_step = 0.05, amplitude_min = 1.5,
  amplitude_max = 2.1, stair_height = 0.2, stair_times = 40, stair_ramp = 5, power_threshold = 0.1 /
""",
}
#: A tiny file of each scene: (name, scene); the varied parameter of the ones with curves ('none': none varied).
FILES = {"fig1_sg_A150": "timeseries", "fig2": "amplitude_sweep", "fig3": "amplitude_sweep", "fig11": "map",
         "bif3": "bifurcation", "wp_sg": "work_precision", "stab": "stability", "fold": "continuation",
         "hyst": "hysteresis"}
VARY = {"fig2": "gamma", "fig3": "m2", "fig11": "none", "bif3": "m2", "stab": "beta", "fold": "none", "hyst": "none"}
#: The status variables of each file, {path: (word of code 0, word of code -1 or None)}.
STATUS = {
    "fig2": {"/runs/status": ("ok", "not_run")}, "fig3": {"/runs/status": ("ok", "not_run")},
    "fig11": {"/runs/status": ("ok", "not_run")},
    "bif3": {"/status": ("found", "pending"), "/thin_verdict": ("clear", "no_margin")},
    "wp_sg": {"/status": ("ok", "not_run")},
    "stab": {f"/verdict/{m}": ("ok", None) for m in ("newton", "linearized", "rk4")},
    "fold": {"/status": ("fold_found", "pending"), "/fold_fate": ("none", None), "/instability_type": ("none", None),
             "/threshold_kind": ("none", None), "/branch_switch": ("none", None),
             "/transmission_status": ("found", "no_fold_on_the_first_branch")},
    "hyst": {"/status": ("found", "pending")},
    "fig1_sg_A150": {},
}


@pytest.fixture(scope="module")
def extra(debug_exe: Path, tmp_path_factory: pytest.TempPathFactory) -> TinyFiles:
    """The tiny continuation and hysteresis files (EXTRA), made by the program on first use."""
    files = TinyFiles(debug_exe, tmp_path_factory.mktemp("tiny_extra"))
    files.texts.update(EXTRA)
    return files


@pytest.fixture(scope="module")
def scene_file(tiny, extra):
    """`scene_file(name)`: the path of the tiny file `name` (FILES)."""
    return lambda name: (extra if name in EXTRA else tiny).file(name)


@pytest.fixture(scope="module")
def loaded(scene_file):
    """`loaded(name)`: `load` of the tiny file `name`, once per module (the tests only read it)."""
    trees: dict[str, object] = {}

    def get(name: str):
        if name not in trees:
            trees[name] = load(scene_file(name))
        return trees[name]

    return get


def nodes(tree) -> dict[str, object]:
    """Every group of a DataTree as a Dataset with its inherited coordinates, {path: Dataset}."""
    return {node.path: node.to_dataset() for node in tree.subtree}


def is_text_bytes(var) -> bool:
    return var.dtype.kind == "S" or (var.dtype.kind == "O" and var.size > 0 and isinstance(var.values.flat[0], bytes))


# ------------------------------------------------------------------------------------------------ the codes


#: The codes' texts as the program writes them (read from its files), and what each must give.
CODES = {
    "-2 outside_gap: not run, the driving frequency lies outside the band gap of the curve (Omega >= sqrt(1 + m^2)); "
    "-1 not_run: not computed yet (partial file); 0 ok: the run reached T; 1 diverged: blow-up, |u_n| above "
    "blowup_threshold or non-finite values; 2 newton_failed: Newton did not converge within newton_max_iter; "
    "3 solver_failed: the tridiagonal solver failed":
        [(-2, "outside_gap"), (-1, "not_run"), (0, "ok"), (1, "diverged"), (2, "newton_failed"),
         (3, "solver_failed")],
    "-2: outside gap (Omega >= sqrt(1 + m^2): not searched; NaN); -1: pending (not computed yet); 0: found (smallest "
    "transmitting amplitude in (a_min, a_max]); 1: at lower bound (a_min already transmits; the threshold may lie "
    "below it); 2: none transmits (nothing in [a_min, a_max] the coarse scan asked transmits; NaN); 3: run failed (a "
    "run diverged or its solver failed before a verdict; NaN); 4: bad arguments (invalid search range or steps; NaN)":
        [(-2, "outside_gap"), (-1, "pending"), (0, "found"), (1, "at_lower_bound"), (2, "none_transmits"),
         (3, "run_failed"), (4, "bad_arguments")],
    "-1 not_run, 0 ok, 1 diverged (blow-up, or ledger residual above drift_limit of the energy scale), "
    "2 newton_failed, 3 solver_failed":
        [(-1, "not_run"), (0, "ok"), (1, "diverged"), (2, "newton_failed"), (3, "solver_failed")],
    "stable means 0 ok; 0 ok: the run reached T; 1 diverged: blow-up, |u_n| above blowup_threshold or non-finite "
    "values; 2 newton_failed: Newton did not converge within newton_max_iter; 3 solver_failed: the tridiagonal "
    "solver failed":
        [(0, "ok"), (1, "diverged"), (2, "newton_failed"), (3, "solver_failed")],
    "-1: no fold on the first branch (see /status); 0: found; 1, 2, 3, 4: the last branch followed ended as /status "
    "says of the first (no fold below amplitude_max, Newton-shooting failed from the settled state, step too small, "
    "points exhausted); 6: the state found where the chain settled is unstable":
        [(-1, "no_fold_on_the_first_branch"), (0, "found")]
        + [(v, f"the_last_branch_followed_ended_as_status_says_of_the_first_{v}") for v in (1, 2, 3, 4)]
        + [(6, "the_state_found_where_the_chain_settled_is_unstable")],
    "0 none: no branch point below the fold; 1 supercritical: the other branch leaves above; 2 subcritical: it "
    "leaves below; driven 1% past the branch point, the chain transmits; 3 failed: the other branch was not found":
        [(0, "none"), (1, "supercritical"), (2, "subcritical"), (3, "failed")],
}


@pytest.mark.parametrize("text", CODES, ids=range(len(CODES)))
def test_codes_in_every_form_the_program_writes(text):
    assert [(v, w) for v, w, _ in parse_codes(text)] == CODES[text]


def test_a_meaning_goes_on_past_its_semicolon():
    """A ';' part that starts with no code belongs to the code before it (branch_switch's 2 subcritical)."""
    codes = dict((v, m) for v, _, m in parse_codes(list(CODES)[-1]))
    assert codes[2] == "subcritical: it leaves below; driven 1% past the branch point, the chain transmits"
    assert codes[3].startswith("failed")


@pytest.mark.parametrize("text", ["", "no codes at all", "0 ok; 0 again"])
def test_codes_not_understood_are_refused(text):
    with pytest.raises(ValueError):
        parse_codes(text)


def test_flag_words_are_single_words():
    assert flag_words("outside gap") == "outside_gap"
    assert flag_words("Newton-shooting failed / twice") == "newton_shooting_failed_twice"


# ------------------------------------------------------------------------------------------------ load


@pytest.mark.parametrize("name", FILES)
def test_every_variable_has_its_axes_long_name_and_units_and_text_is_str(scene_file, loaded, name):
    path = scene_file(name)
    tree = loaded(name)
    assert isinstance(tree, xr.DataTree) and tree.attrs["scene"] == FILES[name]
    with h5py.File(path, "r") as f:
        groups = {"/"}
        f.visititems(lambda n, o: groups.add("/" + n) if isinstance(o, h5py.Group) else None)
        for path_, ds in nodes(tree).items():
            for vname, var in ds.variables.items():
                where = f"{name}:{path_}/{vname}"
                assert var.attrs.get("long_name"), f"{where}: no long_name"
                assert "units" in var.attrs, f"{where}: no units"
                assert not is_text_bytes(var), f"{where} is bytes"
                for dim in var.dims:  # every axis is a coordinate, the root's too
                    assert dim in ds.indexes, f"{where}: dimension {dim} without coordinate"
                    h5 = f.get(f"{path_.rstrip('/')}/{dim}")
                    h5 = f.get(f"/{dim}") if h5 is None else h5
                    if isinstance(h5, h5py.Dataset) and h5.ndim == 1 and h5.dtype.kind in "if" and \
                            h5.shape[0] == ds.sizes[dim]:
                        np.testing.assert_array_equal(ds.indexes[dim].values, h5[()], err_msg=where)
    assert groups == {node.path for node in tree.subtree}


@pytest.mark.parametrize("name", FILES)
def test_numbers_are_the_files(scene_file, loaded, name):
    """Every numeric dataset of the file, read by h5py, is the loaded variable of the same path."""
    path = scene_file(name)
    tree = loaded(name)
    compared = 0
    with h5py.File(path, "r") as f:
        def check(h5name, obj):
            nonlocal compared
            if isinstance(obj, h5py.Dataset) and obj.dtype.kind in "iuf":
                np.testing.assert_array_equal(tree["/" + h5name].values, obj[()], err_msg=h5name)
                compared += 1
        f.visititems(check)
    assert compared > 3


@pytest.mark.parametrize("name", [n for n in FILES if n in VARY])
def test_curves_are_labelled_in_every_group(scene_file, loaded, name):
    path = scene_file(name)
    tree = loaded(name)
    with h5py.File(path, "r") as f:
        potentials = [p.decode().rstrip("\x00").strip() for p in f["/curves/potential"][()]]
        values = f["/curves/value"][()]
        vary = f["/curves"].attrs["vary"]
        vary = (vary.decode() if isinstance(vary, bytes) else str(vary)).strip()
    assert vary == VARY[name]
    labelled = 0
    for path_, ds in nodes(tree).items():
        if not any("curve" in v.dims for v in ds.data_vars.values()):
            continue  # (the root's index `curve` is inherited by every group)
        pot = ds.coords["potential"]
        assert pot.dims == ("curve",) and pot.dtype.kind == "U", f"{path_}: potential {pot.dtype}"
        assert pot.values.tolist() == potentials, path_
        assert set(pot.values) <= {"sine-gordon", "klein-gordon"}
        if vary != "none":
            np.testing.assert_array_equal(ds.coords[vary].values, values, err_msg=path_)
            assert ds.coords[vary].attrs["units"] != "", path_
        else:
            assert not {"gamma", "beta", "m2", "none"} & set(ds.coords), path_
        labelled += 1
    assert labelled >= 2
    # the labels select: every result of one potential
    for var in tree.to_dataset().data_vars.values():
        if "curve" in var.dims:
            first = var.where(var.potential == potentials[0], drop=True)
            assert first.sizes["curve"] == potentials.count(potentials[0])


@pytest.mark.parametrize("name", FILES)
def test_status_variables_carry_cf_flags_for_every_code_they_hold(loaded, name):
    tree = loaded(name)
    flagged = {}
    for path_, ds in nodes(tree).items():
        for vname, var in ds.data_vars.items():
            if "flag_values" in var.attrs:
                flagged[f"{path_.rstrip('/')}/{vname}"] = var
    assert set(flagged) == set(STATUS[name])
    for p, var in flagged.items():
        values, words = var.attrs["flag_values"], var.attrs["flag_meanings"].split()
        assert len(values) == len(words) == len(set(values.tolist())), p
        assert values.dtype == var.dtype, p
        held = set(np.unique(var.values[np.isfinite(var.values)]).astype(int).tolist())
        assert held <= set(values.tolist()), f"{p}: codes {held - set(values.tolist())} held but not flagged"
        meaning = dict(zip(values.tolist(), words))
        zero, pending = STATUS[name][p]
        assert meaning[0] == zero, p
        if pending is not None:
            assert meaning[-1] == pending, p


def test_timeseries_probes_are_labelled_by_their_sites(loaded):
    tree = loaded("fig1_sg_A150")
    u = tree["probes/u"]
    assert u.dims[0] == "probe" and u.coords["sites"].values.tolist() == [1, 20, 30]
    assert u.attrs["units"] == "rad" and u.attrs["long_name"]


def test_hysteresis_stairs_and_work_precision_steps_are_coordinates(loaded):
    hyst = loaded("hyst")
    power = hyst["power"]
    assert {"stair_time", "stair_amplitude", "stair_direction"} <= set(power.coords)
    assert hyst["cost/steps"].coords["stair_time"].values.tolist() == [40.0]
    wp = loaded("wp_sg")
    err = wp["error_u"]
    assert err.coords["dt"].dims == ("methods", "dt_index")
    assert err.coords["methods"].values.tolist() == ["linearized", "rk4", "rk8"]


def test_a_partial_snapshot_is_found_and_a_bad_file_is_one_line(scene_file, tmp_path):
    partial = tmp_path / "x.h5.partial.h5"
    shutil.copy(scene_file("fig2"), partial)
    assert load(tmp_path / "x.h5").attrs["scene"] == "amplitude_sweep"
    with pytest.raises(PlotError, match="no such file"):
        load(tmp_path / "absent.h5")
    bad = tmp_path / "bad.h5"
    bad.write_text("not HDF5")
    with pytest.raises(PlotError, match="bad.h5"):
        load(bad)


def test_codes_it_cannot_read_leave_the_variable_without_flags_and_say_so(scene_file, tmp_path):
    path = tmp_path / "odd.h5"
    shutil.copy(scene_file("bif3"), path)
    with h5py.File(path, "a") as f:
        f["/status"].attrs["codes"] = "whatever the program says one day"
    with pytest.warns(UserWarning, match="/status: no CF flags"):
        tree = load(path)
    assert "flag_values" not in tree["status"].attrs and tree["status"].attrs["codes"].startswith("whatever")


# ------------------------------------------------------------------------------------------------ plain xarray


@pytest.mark.parametrize("name", FILES)
def test_plain_open_datatree_gives_every_variable_its_coordinates_today(scene_file, name):
    """Without the loader: every group opens and every dimension of every variable has its coordinate (the root's
    axes inherited); a group opened alone has none (docs/output.md)."""
    path = scene_file(name)
    with xr.open_datatree(path, engine="h5netcdf") as tree:
        assert tree.children
        for node in tree.subtree:
            ds = node.to_dataset()
            for vname, var in ds.data_vars.items():
                missing = [d for d in var.dims if d not in ds.indexes]
                assert not missing, f"{name}:{node.path}/{vname}: no coordinate for {missing}"


def test_plain_xarray_today_bytes_no_flags_and_a_group_alone_without_axes(scene_file):
    path = scene_file("fig2")
    with xr.open_datatree(path, engine="h5netcdf") as tree:
        assert sorted(tree["energy/injected"].coords) == ["amplitude", "curve"]
        assert tree["curves/potential"].dtype.kind == "S"
        assert "flag_values" not in tree["runs/status"].attrs
    with xr.open_dataset(path, engine="h5netcdf", group="energy") as alone:
        assert not alone["injected"].coords


def test_the_attributes_docs_name_label_a_plain_open_datatree(scene_file, tmp_path):
    """The attributes docs/output.md says the program would have to write, written here into a copy with h5py: then
    plain `open_datatree` gives str potentials, flags, long_name and the curve labels in a group."""
    path = tmp_path / "cf.h5"
    shutil.copy(scene_file("fig2"), path)
    with h5py.File(path, "a") as f:
        f["/curves/potential"].attrs["_Encoding"] = "utf-8"
        status = f["/runs/status"]
        status.attrs["flag_values"] = np.array([-2, -1, 0, 1, 2, 3], dtype=status.dtype)
        status.attrs["flag_meanings"] = "outside_gap not_run ok diverged newton_failed solver_failed"
        f["/energy/injected"].attrs["long_name"] = f["/energy/injected"].attrs["description"]
        g = f["/energy"]
        g["potential"] = f["/curves/potential"][()]
        g["potential"].attrs["_Encoding"] = "utf-8"
        g["gamma"] = f["/curves/value"][()]
        for name in ("potential", "gamma"):
            g[name].dims[0].attach_scale(f["/curve"])
        g["injected"].attrs["coordinates"] = "potential gamma"
    with xr.open_datatree(path, engine="h5netcdf") as tree:
        injected = tree["energy/injected"]
        assert injected.coords["potential"].values.tolist()[0] == "sine-gordon"
        np.testing.assert_array_equal(injected.coords["gamma"].values, tree["curves/value"].values)
        assert tree["runs/status"].attrs["flag_meanings"].split()[2] == "ok"
        assert injected.attrs["long_name"].startswith("Energy injected")
