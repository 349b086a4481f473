"""The input schema (src/io/schema.toml) and what follows from it: the generated files are up to date and a stale one
is detected; the program's output stores every key of the table in /parameters with the schema beside it, and
/provenance says which commit, compiler and namelist made the file."""
import importlib.util
import shutil
import subprocess
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
GENERATOR = ROOT / "src" / "io" / "generate_schema.py"


def generator():
    """The generator script as a module."""
    spec = importlib.util.spec_from_file_location("generate_schema", GENERATOR)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def schema():
    with open(ROOT / "src" / "io" / "schema.toml", "rb") as f:
        return tomllib.load(f)


def test_generated_files_are_up_to_date():
    proc = subprocess.run(["python3", str(GENERATOR), "--check"], cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr


def test_a_stale_file_is_detected(tmp_path, monkeypatch):
    g = generator()
    doc = tmp_path / "input.md"
    text = (ROOT / "docs" / "input.md").read_text(encoding="utf-8")
    doc.write_text(text.replace("| `c` | real | 4 |", "| `c` | real | 5 |"), encoding="utf-8")
    assert doc.read_text(encoding="utf-8") != text
    monkeypatch.setattr(g, "INPUT_DOC", doc)
    for name in ("CONFIG", "MODULE"):                # never rewrite the real files from a test
        copy = tmp_path / getattr(g, name).name
        shutil.copy(getattr(g, name), copy)
        monkeypatch.setattr(g, name, copy)
    assert g.main(["--check"]) == 1
    assert g.main([]) == 0                        # rewrites the copy
    assert doc.read_text(encoding="utf-8") == text
    assert g.main(["--check"]) == 0


def test_a_wrong_table_is_refused(tmp_path, monkeypatch):
    g = generator()
    bad = tmp_path / "schema.toml"
    text = (ROOT / "src" / "io" / "schema.toml").read_text(encoding="utf-8")
    bad.write_text(text.replace("default = 4.0\nmin = 0\nmin_strict = true", "default = -4.0\nmin = 0\nmin_strict = true"),
                   encoding="utf-8")
    with pytest.raises(g.SchemaError, match="default -4.0 below min"):
        g.load(bad)


def test_every_key_has_units_and_a_description():
    s = schema()
    assert len(s["key"]) > 40
    for k in s["key"]:
        assert k["units"] and k["description"], k["name"]


def test_output_holds_every_key(exe, tmp_path):
    h5py = pytest.importorskip("h5py")
    text = ("&chain n = 40, n0 = 30 /\n&record probes = 5, 7 /\n"
            "&numerics t_final = 2.0 /\n&detect amplitude = 2.5 /\n&output file = 'r.h5', quiet = .true. /\n")
    (tmp_path / "case.nml").write_text(text)
    proc = subprocess.run([exe, "case.nml"], cwd=tmp_path, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    s = schema()
    with h5py.File(tmp_path / "r.h5") as f:
        p = f["parameters"].attrs
        for k in s["key"]:
            assert k.get("attribute", k["name"]) in p, k["name"]
        for d in s["derived"]:
            assert d["name"] in p, d["name"]
        assert list(p["probes"]) == [5, 7]
        assert p["detect_amplitude"] == 2.5
        assert p["n"] == 40 and p["method"] == b"newton" and p["potentials"] == b"sine-gordon"
        # the fold protocol's and the short chain's numbers, once constants in the code, are recorded with the rest
        assert p["fate_push"] == 0.01 and p["fate_watch_time"] == 1000.0 and p["fold_stair_height"] == 0.01
        assert p["chain"] == b"input" and p["short_decay"] == 7.0 and p["continuation_tol"] == 1e-10
        names = [x.decode() for x in f["parameters/schema/name"][()]]
        assert names == [k.get("attribute", k["name"]) for k in s["key"]] + [d["name"] for d in s["derived"]]
        units = [x.decode() for x in f["parameters/schema/units"][()]]
        assert units[names.index("dt")] == "time"


def test_output_says_where_it_comes_from(exe, tmp_path):
    h5py = pytest.importorskip("h5py")
    text = "! a comment that provenance keeps\n&chain n = 40, n0 = 30 /\n&numerics t_final = 2.0 /\n" \
           "&output file = 'r.h5', quiet = .true. /\n"
    (tmp_path / "case.nml").write_text(text)
    proc = subprocess.run([exe, "case.nml"], cwd=tmp_path, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    with h5py.File(tmp_path / "r.h5") as f:
        prov = f["provenance"].attrs
        assert f["provenance/namelist"][()].decode() == text
        assert prov["input_file"] == b"case.nml"
        assert prov["compiler"].decode().startswith("GCC")
        assert prov["omp_max_threads"] >= 1
        assert prov["host"] and prov["started"]
        assert Path(prov["working_directory"].decode()) == tmp_path.resolve()
        commit = prov["git_commit"].decode()
    if shutil.which("git"):
        head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True)
        if head.returncode == 0:
            assert commit == head.stdout.strip()
