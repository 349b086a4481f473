"""The output tables (src/io/outputs/<scene>.toml) against the files the program writes (issue 40): every dataset and
group of a file of each scene and solver is a row of its table, with the table's dimensions, units, type, description
and attributes, and every row of the table whose condition (`when`) holds for the file's input is in the file, and
none whose condition does not. A writer that changes a dataset without its table, or a table edited without the
writer, fails here. The reader's layout (postprocess/supratrans_post/layout.py) and the records' packing are
generated from the same tables (`generate_outputs.py --check`, and a mistake in a table is refused)."""
from __future__ import annotations

import importlib.util
import re
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

h5py = pytest.importorskip("h5py")

ROOT = Path(__file__).resolve().parents[1]
GENERATOR = ROOT / "src" / "io" / "generate_outputs.py"
#: Attributes of the HDF5 layer on every dataset or group (its metadata and dimension scales), not a table's.
LAYER = {"units", "description", "dimensions", "DIMENSION_LIST", "REFERENCE_LIST", "DIMENSION_LABELS", "CLASS", "NAME"}

#: Files of the scenes that conftest's tiny set has not: a bifurcation with the check at dt/2 and no screening, the
#: hysteresis stairs (test_hysteresis_scene's), a continuation by shooting and one by harmonic balance with the
#: continuum limit and the absorber family. {name: (namelist without &output, release build?)}
OWN = {
    "bif_certify": (None, False),
    "hysteresis": ("""&chain n = 40, n0 = 30 /
&drive ramp_time = 20 /
&numerics dt = 0.1 /
&scene kind = 'hysteresis', omega_min = 0.85, omega_max = 0.9, omega_step = 0.05, amplitude_min = 1.5,
  amplitude_max = 2.1, stair_height = 0.05, stair_times = 100, 200, stair_ramp = 10, power_threshold = 0.1 /
""", False),
    "fold": ("""&chain n = 30, n0 = 22 /
&numerics dt = 0.1 /
&scene kind = 'continuation', omega_min = 0.7, omega_max = 0.8, omega_step = 0.1, amplitude_max = 4.0,
  fold_convergence = .true., potentials = 'sine-gordon', 'klein-gordon' /
""", True),
    "fold_hb": ("""&chain potential = 'sine-gordon', c = 4.0, n = 40, n0 = 30, sigma = 3.0 /
&numerics method = 'rk8', dt = 0.05 /
&scene kind = 'continuation', solver = 'harmonic_balance', omega_min = 0.9, omega_max = 0.9,
  omega_step = 0.2, amplitude_max = 7.0, floquet_every = 1, beyond_fold = 0, continuation_step_max = 1.0,
  c_values = 4.0, 5.0, absorber_family = 1 /
""", True),
}
#: Each file checked: (conftest tiny name or OWN name, the conditions of its table that hold for its input).
FILES = {
    "fig1_sg_A150": set(), "fig2": set(), "fig3": set(), "fig11": set(), "bif3": {"screening"},
    "bif_certify": {"certify"}, "wp_sg": set(), "stab": set(), "hysteresis": set(), "fold": set(),
    "fold_hb": {"c_values", "absorber_family"},
}


def generator():
    """The generator script as a module."""
    sys.path.insert(0, str(GENERATOR.parent))
    spec = importlib.util.spec_from_file_location("generate_outputs", GENERATOR)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def tables():
    """{(scene, solver): table} of every table."""
    return {(t["scene"], t["solver"]): t for t in generator().load()}


def text(value) -> str:
    """An attribute as str (h5py gives fixed-length strings as bytes)."""
    return value.decode() if isinstance(value, bytes) else str(value)


def pattern(template: str, wildcard: str) -> re.Pattern:
    """A table's path or description as a regular expression: each `{name}` stands for `wildcard`."""
    parts = re.split(r"\{[a-z_][a-z0-9_]*\}", template)
    return re.compile(wildcard.join(re.escape(p) for p in parts) + r"\Z", re.S)


def vary_units(f) -> str:
    """Units of /curves/value: those of the varied key in the input schema, '1' when nothing varies."""
    vary = text(f["curves"].attrs["vary"])
    if vary == "none":
        return "1"
    with open(ROOT / "src" / "io" / "schema.toml", "rb") as s:
        keys = [k for k in tomllib.load(s)["key"] if k["name"] == vary and k["group"] != "scene"]
    assert len(keys) == 1, vary
    return keys[0]["units"]


@pytest.fixture(scope="module")
def files(tiny, release_exe, tmp_path_factory):
    """{name: path} of every file of FILES, made on first use."""
    folder = tmp_path_factory.mktemp("tables")
    made = {}

    def get(name):
        if name not in made:
            if name not in OWN:
                made[name] = tiny.file(name)
            else:
                nml, release = OWN[name]
                if nml is None:     # the tiny bifurcation with the dt/2 check and without screening
                    nml = tiny.texts["bif3"].replace("kind = 'bifurcation'", "kind = 'bifurcation'\n    certify = .true."
                                                     "\n    screen_method = 'none'")
                out = folder / f"{name}.h5"
                (folder / f"{name}.nml").write_text(nml + f"&output file = '{out}', quiet = .true. /\n")
                exe = release_exe if release else tiny.exe
                proc = subprocess.run([str(exe), f"{name}.nml"], cwd=folder, capture_output=True, text=True,
                                      timeout=600)
                assert proc.returncode == 0, proc.stderr[-2000:]
                made[name] = out
        return made[name]

    return get


def contents(f):
    """{path: object} of every dataset and group of a file outside /parameters and /provenance (the input schema's),
    without the index scales the HDF5 layer adds for a dimension without a coordinate (docs/output.md)."""
    found = {}

    def visit(name, obj):
        if name.split("/")[0] in ("parameters", "provenance"):
            return
        if isinstance(obj, h5py.Dataset) and text(obj.attrs.get("description", "")).startswith("Index of the "):
            return
        found[name] = obj

    f.visititems(visit)
    return found


@pytest.mark.parametrize("name", sorted(FILES))
def test_the_file_is_its_table(files, name):
    path = files(name)
    with h5py.File(path, "r") as f:
        key = (text(f.attrs["scene"]), text(f.attrs.get("solver", "")))
        table = tables()[key]
        holds = FILES[name]
        unknown = holds - set(table["conditions"])
        assert not unknown, f"{name}: conditions {unknown} are not in {table['file']}"
        rows = [("dataset", d) for d in table["dataset"]] + [("group", g) for g in table["group"]]
        matched = {id(r): 0 for _, r in rows}
        problems = []
        for p, obj in contents(f).items():
            kind = "dataset" if isinstance(obj, h5py.Dataset) else "group"
            row = next((r for k, r in rows if k == kind and pattern(r["path"], "[A-Za-z0-9_]+").match(p)), None)
            if row is None:
                problems.append(f"/{p}: a {kind} not in {table['file']}")
                continue
            matched[id(row)] += 1
            if row.get("when") and row["when"] not in holds:
                problems.append(f"/{p}: written though its condition '{row['when']}' does not hold")
            description = text(obj.attrs.get("description", ""))
            if not pattern(row["description"], ".+?").match(description):
                problems.append(f"/{p}: description {description!r}, the table's {row['description']!r}")
            attrs = set(obj.attrs) - LAYER
            if kind == "group":
                if attrs != set(row.get("attributes", [])) - {"scene_wall_time_s"} and attrs != set(
                        row.get("attributes", [])):
                    problems.append(f"/{p}: attributes {sorted(attrs)}, the table's {row.get('attributes', [])}")
                continue
            if attrs != set(row.get("attributes", [])):
                problems.append(f"/{p}: attributes {sorted(attrs)}, the table's {row.get('attributes', [])}")
            dims = text(obj.attrs.get("dimensions", ""))
            if dims != row["dims"]:
                problems.append(f"/{p}: dimensions {dims!r}, the table's {row['dims']!r}")
            if obj.ndim != len([d for d in row["dims"].split(",") if d.strip()]):
                problems.append(f"/{p}: rank {obj.ndim} for the table's dimensions {row['dims']!r}")
            units = row["units"] if row["units"] != "(vary)" else vary_units(f)
            if text(obj.attrs.get("units", "")) != units:
                problems.append(f"/{p}: units {text(obj.attrs.get('units', ''))!r}, the table's {units!r}")
            kind_of = {"f": "real", "i": "integer", "S": "text"}.get(obj.dtype.kind, obj.dtype.kind)
            if kind_of != row["type"]:
                problems.append(f"/{p}: of type {kind_of}, the table's {row['type']}")
        for k, r in rows:
            expected = not r.get("when") or r["when"] in holds
            if expected and not matched[id(r)]:
                problems.append(f"/{r['path']}: a {k} of {table['file']} not in the file")
        assert not problems, f"{path} against {table['file']}:\n" + "\n".join(problems)


def test_every_table_and_condition_is_checked_against_a_file(files):
    """Each table has a file above, and each of its conditions holds for one of them."""
    seen = {}
    for name, holds in FILES.items():
        with h5py.File(files(name), "r") as f:
            key = (text(f.attrs["scene"]), text(f.attrs.get("solver", "")))
        seen.setdefault(key, set()).update(holds)
    for key, table in tables().items():
        assert key in seen, f"no file checks {table['file']}"
        assert set(table["conditions"]) <= seen[key], f"{table['file']}: a condition no file checks"


def test_the_reader_reads_the_tables_layout():
    """reader.SCHEMA and SOLVER_SCHEMA are the tables' rows with `read`, with their dimensions (or reader axes)."""
    sys.path.insert(0, str(ROOT / "postprocess"))
    from supratrans_post import reader

    for (scene, solver), t in tables().items():
        want = {d["path"]: (tuple(x.strip() for x in d.get("axes", d["dims"]).split(",") if x.strip()),
                            d["read"] == "required") for d in t["dataset"] if "read" in d}
        assert reader.schema_of(scene, solver) == want, (scene, solver)
    assert set(reader.SCENES) == {scene for scene, _ in tables()}


def test_generated_files_are_up_to_date():
    proc = subprocess.run([sys.executable, str(GENERATOR), "--check"], cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr


@pytest.mark.parametrize("old,new,words", [
    ('field = "fold_amplitude"\n', "", "field 'fold_amplitude' is in 0 datasets"),
    ('path = "fold_residual"\ndims = "curve, omega"', 'path = "fold_residual"\ndims = "curve"', "fold_residual"),
    ('units = "rad"\n', 'units = "rad"\nunit = "rad"\n', "unknown key(s) unit"),
    ('path = "cost/wall_time"\n', 'path = "costs/wall_time"\n', "group 'costs' is not a [[group]]"),
    ('record = "fold"\n', 'record = "fold"\n[[dataset]]\npath = "omega"\ndims = "omega"\nunits = "1"\n'
     'type = "real"\ndescription = "again"\n', "given twice"),
])
def test_a_mistake_in_a_table_is_refused(tmp_path, old, new, words):
    g = generator()
    folder = tmp_path / "outputs"
    shutil.copytree(ROOT / "src" / "io" / "outputs", folder)
    table = folder / "continuation.toml"
    source = table.read_text(encoding="utf-8")
    assert old in source
    changed = source.replace(old, new, 1)
    if "again" in new:      # a dataset given twice must come after the fields and conditions: append it
        changed = source + "\n" + new.replace('record = "fold"\n', "")
    table.write_text(changed, encoding="utf-8")
    with pytest.raises(g.TableError, match=re.escape(words)):
        g.load(folder)


def test_a_stale_generated_file_is_detected(tmp_path, monkeypatch):
    g = generator()
    layout = tmp_path / "layout.py"
    layout.write_text(g.LAYOUT.read_text(encoding="utf-8").replace("'fold_amplitude'", "'fold_amp'", 1))
    monkeypatch.setattr(g, "LAYOUT", layout)
    assert g.main(["--check"]) == 1
    assert g.main([]) == 0 and g.main(["--check"]) == 0
    assert "'fold_amplitude'" in layout.read_text(encoding="utf-8")


#: The writers that take every dataset's and group's metadata from their table's rows (supratrans_output_rows):
#: they name no unit, description or dimensions, so call neither `h5_write` nor `h5_create_group`, and write
#: attributes with `h5_write_attr` only on the root and /parameters (which no table describes).
ROW_WRITERS = ("supratrans_scene_timeseries.f90", "supratrans_scene_bifurcation_output.f90",
               "supratrans_scene_stability.f90", "supratrans_scene_workprec.f90", "supratrans_scene_hysteresis.f90",
               "supratrans_scene_sweep_output.f90", "supratrans_scene_map.f90", "supratrans_curves.f90",
               "supratrans_fold_hb.f90", "supratrans_scene_continuation_output.f90")


@pytest.mark.parametrize("name", ROW_WRITERS)
def test_a_writer_takes_its_metadata_from_its_table(name):
    source = (ROOT / "src" / "scenes" / name).read_text(encoding="utf-8")
    code = "\n".join(line.split("!")[0] for line in source.splitlines())
    assert not re.search(r"\bcall\s+h5_write\s*\(", code), f"{name}: h5_write: write the dataset with write_row"
    assert not re.search(r"\bcall\s+h5_create_group\s*\(", code), f"{name}: h5_create_group: use write_row_group"
    for obj in re.findall(r"\bcall\s+h5_write_attr\s*\(\s*file\s*,\s*([^,]+),", code):
        assert obj.strip() in ('"/"', "g") or "parameters" in obj, f"{name}: h5_write_attr on {obj}: write_row_attr"


def test_every_row_is_a_constant_of_the_rows_module():
    """Each dataset and group of each table has its named constant, its metadata in `output_row_meta`."""
    g = generator()
    text = g.ROWS.read_text(encoding="utf-8")
    rows = g.table_rows(g.load())
    for i, (const, t, kind, r) in enumerate(rows, start=1):
        assert f":: {const} = output_row({i})\n" in text, const
        assert f"case ({i})   ! {const}\n" in text, const
    assert len({const for const, *_ in rows}) == len(rows)


def test_the_hysteresis_journal_keeps_its_names():
    """The hysteresis record's scalar fields (its table's `field`) in the order of main's journal: a journal written
    before they came from the table still resumes; power_0 .. follow them."""
    t = tables()[("hysteresis", "")]
    assert [f["name"] for f in t["field"]] == ["status", "upward", "downward", "window", "downward_gaps",
                                               "detector_site", "steps", "wall_time"]
    text = (ROOT / "src" / "scenes" / "supratrans_hysteresis_scalars.f90").read_text(encoding="utf-8")
    assert '"status", "upward", "downward", &\n        "window", "downward_gaps", "detector_site", "steps", "wall_time"]' in text


@pytest.mark.parametrize("table,old,new,words", [
    ("hysteresis.toml", 'journal_only = true, description = "Detector site n_d of the run (/detector_site holds it '
     'per curve and Omega)"', 'journal_only = true', "needs a description"),
    ("hysteresis.toml", 'path = "upward_spread"\n', 'path = "upward_spread"\nfield = "detector_site"\n',
     "is journal_only but dataset 'upward_spread' holds it"),
    ("hysteresis.toml", "record_writer = false\n", "", "a record with a writer (record_writer)"),
    ("hysteresis.toml", 'path = "stair_time"\n', 'path = "stair/time"\n', "group 'stair' is not a [[group]]"),
    ("map.toml", 'units = "1/time^2"\n', 'units = "1/time2"\n', "dataset 'curves/m2' differs from that of"),
    ("stability.toml", 'description = "On-site potential of each curve"', 'description = "Potential of each curve"',
     "dataset 'curves/potential' differs from that of"),
])
def test_a_mistake_in_a_record_or_a_row_is_refused(tmp_path, table, old, new, words):
    g = generator()
    folder = tmp_path / "outputs"
    shutil.copytree(ROOT / "src" / "io" / "outputs", folder)
    source = (folder / table).read_text(encoding="utf-8")
    assert old in source
    (folder / table).write_text(source.replace(old, new, 1), encoding="utf-8")
    with pytest.raises(g.TableError, match=re.escape(words)):
        g.outputs(g.load(folder))


def test_a_row_that_makes_no_fortran_name_is_refused(tmp_path):
    g = generator()
    folder = tmp_path / "outputs"
    shutil.copytree(ROOT / "src" / "io" / "outputs", folder)
    table = folder / "map.toml"
    source = table.read_text(encoding="utf-8")
    assert 'path = "omega"\n' in source
    table.write_text(source.replace('path = "omega"\n', 'path = "Omega-axis"\n', 1), encoding="utf-8")
    with pytest.raises(g.TableError, match="is not a Fortran name"):
        g.outputs(g.load(folder))


def test_two_rows_of_one_constant_are_refused(tmp_path):
    g = generator()
    folder = tmp_path / "outputs"
    shutil.copytree(ROOT / "src" / "io" / "outputs", folder)
    table = folder / "hysteresis.toml"
    table.write_text(table.read_text(encoding="utf-8") + '\n[[group]]\npath = "stair_time_x"\ndescription = ""\n'
                     '\n[[dataset]]\npath = "stair_time_x/y"\ndims = ""\nunits = "1"\ntype = "real"\n'
                     'description = "one"\n\n[[dataset]]\npath = "stair_time_x_y"\ndims = ""\nunits = "1"\n'
                     'type = "real"\ndescription = "two"\n', encoding="utf-8")
    with pytest.raises(g.TableError, match="is also that of"):
        g.outputs(g.load(folder))


def test_the_sweep_and_the_map_share_the_run_record():
    """The map's table holds the fields of the sweep's run record, each over (curve, omega, amplitude), in the order
    of the journal before the record came from the table (a journal of that time still resumes): one record, two
    layouts."""
    t = tables()
    sweep, grid = t[("amplitude_sweep", "")], t[("map", "")]
    assert grid.get("shares") == "amplitude_sweep.toml" and not grid["field"]
    assert [f["name"] for f in sweep["field"]] == [
        "injected", "stored", "dissipated_gamma", "dissipated_beta", "dissipated_absorber", "residual", "status",
        "transmitting", "t_decided", "steps", "newton_iterations", "wall_time", "t_end", "max_abs_u",
        "injected_after_ramp", "u_beyond_max", "detect_site", "tridiagonal_solves", "rhs_evaluations",
        "verdict_margin", "thin_verdict"]
    held = {d["field"]: d["dims"] for d in grid["dataset"] if "field" in d}
    assert set(held) == {f["name"] for f in sweep["field"]}
    assert set(held.values()) == {"curve, omega, amplitude"}
