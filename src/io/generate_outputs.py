#!/usr/bin/env python3
"""Write what follows from the output tables, src/io/outputs/<scene>.toml: the layout the Python reader reads, the
rows the writers write by (each dataset's and group's metadata), and the packing of the per-task records whose table
names their fields.

    python3 src/io/generate_outputs.py           # (re)write the generated files
    python3 src/io/generate_outputs.py --check   # exit 1 if a generated file is stale (or a table is wrong)

A table is one scene's file (one per solver where a solver writes another layout): its root attributes `scene` and
`solver` ('' for the scene's only or first solver, which writes no root attribute `solver`), optionally `prefix`
(of its rows' constants; else the file's stem), then

  [[dataset]]  one per dataset the scene writes: `path` (without the leading '/'), `dims` (the names of its
               dimensions, h5py's order, as its attribute `dimensions`; '' for none), `units`, `type` (real,
               integer, text), `description` (its attribute `description`; `{name}` stands for a value the writer
               gives, e.g. a protocol constant), and optionally
               `read`   'required' or 'optional': the Python reader reads it (postprocess/supratrans_post/reader.py);
               `axes`   the reader's names of its dimensions where they differ from `dims` (the reader checks every
                        dimension of one name against one axis in a file: the probes' and the ledger's `time`);
               `field`  the scalar field of the per-task record it holds, one value per task, (curve, omega);
               `when`   the condition (a name in [conditions]) under which it is written; else always;
               `attributes`  the attributes the writer adds (codes, totals) beside units, description, dimensions;
  [[group]]    one per group: `path`, `description` ('' for one made by its datasets' paths), optionally `when`
               and `attributes` (as a dataset's);
  [conditions] name = "what the condition means";
  [names]      name = "what `{name}` in a dataset's path stands for" (one dataset per method: `verdict/{method}`);
  record       the name of the per-task record (`fold` -> `fold_scalars`, module supratrans_fold_scalars), and
  field        its scalar fields in the order of its values in the journal: `name`, `type` (real, integer),
               optionally `empty` ("nan": NaN in a record with nothing computed; an integer, for an integer field:
               that value, also read from a NaN value; else 0), `initial` (the component's default, else 0) and
               `journal_only` (true: no dataset holds it; then a `description`). A table with a `record` and no
               `field` shares the record of the one table that lists its fields (its own datasets hold them);
  record_dims  the tasks' dimensions, the `dims` of each field's dataset (default "curve, omega");
  record_writer  false: the scene writes the fields' datasets itself, by their rows (default true: the generated
               `write_<record>_scalars` writes them, over (curve, omega); false for a shared record).

Generated (never edit them by hand):
  postprocess/supratrans_post/layout.py   SCHEMA, SOLVER_SCHEMA, TEXT: the datasets the reader reads
  src/io/supratrans_output_rows.f90       every dataset and group of every table as a named constant
                                          (`<prefix>_<path>`), its metadata, and `write_row`, `write_row_group`,
                                          `write_row_attr`, which write a dataset, group or attribute by its row;
                                          the rows of /curves every curve table has once more, `shared_<path>`
                                          (one writer, `write_curves`, writes them for every scene)
  src/scenes/supratrans_<record>_scalars.f90   per record: the type of its scalar fields, their names in the journal,
                                          the record as values and back, the empty record, and (record_writer) the
                                          writer of their datasets and of the scene's groups (by their rows)

Checked: the keys of every entry, unique paths, known types, read and when values, every field (but a journal-only
one) in exactly one dataset of its type over the record's dimensions, every group of a dataset in the table, every
row's constant a Fortran name and unique, every shared row of /curves the same in each table that has it.
"""
import argparse
import re
import sys
import tomllib
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from generate_schema import comment, continued, fstring, shown  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
TABLES = ROOT / "src" / "io" / "outputs"
SCHEMA = ROOT / "src" / "io" / "schema.toml"
LAYOUT = ROOT / "postprocess" / "supratrans_post" / "layout.py"
SCENES = ROOT / "src" / "scenes"
ROWS = ROOT / "src" / "io" / "supratrans_output_rows.f90"
TYPES = ("real", "integer", "text")
DATASET_KEYS = {"path", "dims", "units", "type", "description", "read", "axes", "field", "when", "attributes"}
FIELD_KEYS = {"name", "type", "empty", "initial", "journal_only", "description"}
WIDTH = 132
HEADER = ("! Generated by src/io/generate_outputs.py from src/io/outputs/{table}: do not edit.\n"
          "! Edit the table, then run `python3 src/io/generate_outputs.py` (`--check` tells whether this file is up to\n"
          "! date).\n")


class TableError(Exception):
    """A mistake in an output table."""


def placeholders(text):
    """The names `{name}` in a description, in order of first appearance."""
    seen = []
    for name in re.findall(r"\{([a-z_][a-z0-9_]*)\}", text):
        if name not in seen:
            seen.append(name)
    return seen


def dims_of(text):
    """The dimension names of a `dims` text ('curve, omega' -> ('curve', 'omega'))."""
    return tuple(x.strip() for x in text.split(",")) if text.strip() else ()


def load_table(path):
    """One table, checked."""
    with open(path, "rb") as f:
        t = tomllib.load(f)
    where = path.name
    for key in ("scene", "solver"):
        if not isinstance(t.get(key), str):
            raise TableError(f"{where}: '{key}' missing")
    t.setdefault("dataset", [])
    t.setdefault("group", [])
    t.setdefault("field", [])
    t.setdefault("conditions", {})
    t.setdefault("names", {})
    t["file"] = path.name
    paths = set()
    for d in t["dataset"]:
        w = f"{where}: dataset '{d.get('path')}'"
        for key in ("path", "dims", "units", "type", "description"):
            if not isinstance(d.get(key), str) or (key not in ("dims",) and not d[key].strip()):
                raise TableError(f"{w}: '{key}' missing")
        unknown = set(d) - DATASET_KEYS
        if unknown:
            raise TableError(f"{w}: unknown key(s) {', '.join(sorted(unknown))}")
        if d["path"] in paths:
            raise TableError(f"{w}: given twice")
        paths.add(d["path"])
        if d["type"] not in TYPES:
            raise TableError(f"{w}: type '{d['type']}' is not one of {', '.join(TYPES)}")
        if d.get("read", "required") not in ("required", "optional"):
            raise TableError(f"{w}: read must be 'required' or 'optional'")
        if "axes" in d and len(dims_of(d["axes"])) != len(dims_of(d["dims"])):
            raise TableError(f"{w}: axes has not the rank of dims")
        if "when" in d and d["when"] not in t["conditions"]:
            raise TableError(f"{w}: when = '{d['when']}' is not in [conditions]")
        for name in placeholders(d["path"]):
            if name not in t["names"]:
                raise TableError(f"{w}: {{{name}}} is not in [names]")
            if "read" in d or "field" in d:
                raise TableError(f"{w}: a dataset of many names is neither read nor a field")
        group = d["path"].rpartition("/")[0]
        if group and group not in {g["path"] for g in t["group"]}:
            raise TableError(f"{w}: its group '{group}' is not a [[group]] of the table")
    for g in t["group"]:
        if not g.get("path") or not isinstance(g.get("description"), str):
            raise TableError(f"{where}: a group needs a path and a description ('' for one made by its datasets)")
        if "when" in g and g["when"] not in t["conditions"]:
            raise TableError(f"{where}: group '{g['path']}': when = '{g['when']}' is not in [conditions]")
    names = [f.get("name") for f in t["field"]]
    if len(set(names)) != len(names):
        raise TableError(f"{where}: a field is given twice")
    if t["field"] and not t.get("record"):
        raise TableError(f"{where}: fields without a record name")
    t.setdefault("record_dims", "curve, omega")
    t.setdefault("record_writer", True)
    if t.get("record") and (not dims_of(t["record_dims"]) or not isinstance(t["record_writer"], bool)):
        raise TableError(f"{where}: record_dims must name the tasks' dimensions and record_writer be true or false")
    for f in t["field"]:
        if f.get("type") not in ("real", "integer"):
            raise TableError(f"{where}: field '{f.get('name')}': type must be real or integer")
        empty = f.get("empty", "0")
        if empty not in ("nan", "0") and not (f["type"] == "integer" and type(empty) is int):
            raise TableError(f"{where}: field '{f['name']}': empty must be 'nan', an integer (an integer field's) "
                             "or absent (0)")
        unknown = set(f) - FIELD_KEYS
        if unknown:
            raise TableError(f"{where}: field '{f['name']}': unknown key(s) {', '.join(sorted(unknown))}")
        if f.get("journal_only", False) and (not isinstance(f.get("description"), str)
                                             or not f["description"].strip()):
            raise TableError(f"{where}: field '{f['name']}' is journal_only: it needs a description")
    if t["field"]:
        hold_fields(t, t["field"])
    return t


def hold_fields(t, fields):
    """Check that the datasets of table `t` hold the record's `fields` (its own, or those of the table it shares
    its record with): each field but a journal-only one in exactly one dataset of its type over the record's
    dimensions, and every dataset's `field` a field; remember each field's dataset (`dataset`)."""
    where = t["file"]
    tasks = dims_of(t["record_dims"])
    names = [f["name"] for f in fields]
    for f in fields:
        holders = [d for d in t["dataset"] if d.get("field") == f["name"]]
        if f.get("journal_only", False):
            if holders:
                raise TableError(f"{where}: field '{f['name']}' is journal_only but dataset '{holders[0]['path']}' "
                                 "holds it")
            continue
        if len(holders) != 1:
            raise TableError(f"{where}: field '{f['name']}' is in {len(holders)} datasets, not one")
        if holders[0]["type"] != f["type"] or dims_of(holders[0]["dims"]) != tasks:
            raise TableError(f"{where}: field '{f['name']}': its dataset is not of its type over "
                             f"({t['record_dims']})")
        f["dataset"] = holders[0]
    for d in t["dataset"]:
        if "field" in d and d["field"] not in names:
            raise TableError(f"{where}: dataset '{d['path']}': field '{d['field']}' is not a [[field]]")
    if t["record_writer"] and (any(f.get("journal_only") for f in fields) or tasks != ("curve", "omega")):
        raise TableError(f"{where}: a record with a writer (record_writer) has every field in a dataset over "
                         "(curve, omega)")


def share_records(tables):
    """A table with a `record` and no `field` list shares the record of the one table that lists its fields (the
    sweep's and the map's runs: one record, two layouts): check its datasets against those fields."""
    for t in tables:
        if not t.get("record") or t["field"]:
            continue
        owners = [o for o in tables if o.get("record") == t["record"] and o["field"]]
        if len(owners) != 1:
            raise TableError(f"{t['file']}: record '{t['record']}' has its fields in {len(owners)} tables, not one")
        if t["record_writer"] or owners[0]["record_writer"]:
            raise TableError(f"{t['file']}: a record shared by tables has no writer (record_writer = false)")
        t["shares"] = owners[0]["file"]
        hold_fields(t, [{k: v for k, v in f.items() if k != "dataset"} for f in owners[0]["field"]])
    for t in tables:
        if t["field"] and len([o for o in tables if o.get("record") == t["record"] and o["field"]]) != 1:
            raise TableError(f"{t['file']}: record '{t['record']}' has its fields in more than one table")


def load(folder=TABLES, schema=SCHEMA):
    """Every table of `folder`, checked, in the order of the scene choices of the input schema (`schema`), the
    first solver first; one table a scene and solver, and one a scene at least."""
    with open(schema, "rb") as f:
        kinds = next(c["values"] for c in tomllib.load(f)["choices"] if c["name"] == "scene")
    tables = [load_table(p) for p in sorted(folder.glob("*.toml"))]
    for t in tables:
        if t["scene"] not in kinds:
            raise TableError(f"{t['file']}: scene '{t['scene']}' is not a scene of {shown(schema)}")
    missing = set(kinds) - {t["scene"] for t in tables}
    if missing:
        raise TableError(f"no table for the scene(s) {', '.join(sorted(missing))}")
    tables.sort(key=lambda t: (kinds.index(t["scene"]), t["solver"]))
    share_records(tables)
    seen = set()
    for t in tables:
        if (t["scene"], t["solver"]) in seen:
            raise TableError(f"{t['file']}: scene '{t['scene']}' solver '{t['solver']}' has another table")
        seen.add((t["scene"], t["solver"]))
    return tables


# ------------------------------------------------------------------------------------------------ python


def layout_module(tables):
    """postprocess/supratrans_post/layout.py: the datasets the reader reads, per scene and per (scene, solver)."""
    out = ['"""The datasets the reader reads of each scene\'s file (generated by src/io/generate_outputs.py from',
           "src/io/outputs/*.toml: do not edit; edit the tables and run it).", "",
           "SCHEMA: {scene: {h5py path: (dimensions, required)}} of each scene's first solver, in the order they",
           "are checked; SOLVER_SCHEMA: the same by (scene, solver) for a file whose root attribute `solver` names",
           'another; TEXT: the datasets read that hold text."""', "", "SCHEMA = {"]

    def rows(t):
        lines = []
        for d in t["dataset"]:
            if "read" not in d:
                continue
            axes = dims_of(d.get("axes", d["dims"]))
            lines.append(f"        {d['path']!r}: ({axes!r}, {d['read'] == 'required'}),")
        return lines

    for t in tables:
        if not t["solver"]:
            out += [f"    {t['scene']!r}: {{"] + rows(t) + ["    },"]
    out += ["}", "SOLVER_SCHEMA = {"]
    for t in tables:
        if t["solver"]:
            out += [f"    ({t['scene']!r}, {t['solver']!r}): {{"] + rows(t) + ["    },"]
    out += ["}"]
    text = sorted({d["path"] for t in tables for d in t["dataset"] if "read" in d and d["type"] == "text"})
    out += [f"TEXT = {tuple(text)!r}", ""]
    return "\n".join(out)


# ------------------------------------------------------------------------------------------------ fortran


def split_literal(text, indent):
    """A string literal split at blanks into `"..." // &` pieces that fit the line width."""
    room = WIDTH - len(indent) - 8
    pieces, piece = [], ""
    for word in re.split(r"(?<= )", text):
        if piece and len(fstring(piece + word)) > room:
            pieces.append(piece)
            piece = ""
        piece += word
    pieces.append(piece)
    return (" // &\n" + indent).join(fstring(p) for p in pieces)


def fortran_description(text, indent):
    """A description as a Fortran expression: its literal pieces joined with the arguments `{name}` names."""
    parts = re.split(r"\{([a-z_][a-z0-9_]*)\}", text)
    pieces = []
    for i, part in enumerate(parts):
        if i % 2:
            pieces.append(part)
        elif part:
            pieces.append(split_literal(part, indent))
    return (" // &\n" + indent).join(pieces) if pieces else '""'


def own_groups(t):
    """The groups the record's writer creates: those that hold a dataset of a field (the scene writes the others)."""
    held = {f["dataset"]["path"].rpartition("/")[0] for f in t["field"] if "dataset" in f}
    return [g for g in t["group"] if g["path"] in held]


def record_module(t):
    """src/scenes/supratrans_<record>_scalars.f90 of a table with a record."""
    rec = t["record"]
    name = f"{rec}_scalars"
    fields = t["field"]
    writer = t["record_writer"]
    held = [f["dataset"] for f in fields if "dataset" in f]
    conds = [c for c in t["conditions"] if any(x.get("when") == c for x in held + own_groups(t))]
    args = []
    for x in [g["description"] for g in own_groups(t)] + [d["description"] for d in held]:
        for p in placeholders(x):
            if p not in args:
                args.append(p)
    ind = "    "
    out = [HEADER.format(table=t["file"])]
    scene = t["scene"] + (f" (solver '{t['solver']}')" if t["solver"] else "")
    what = ("and the writer of their datasets (one value per task, over (curve, omega)) and of the scene's groups."
            if writer else f"and the empty record (the scene writes their datasets, one value per task over "
            f"({t['record_dims']}), row by row: supratrans_output_rows).")
    out.append(comment(f"The scalar fields of the per-task record `{rec}` of the scene {scene}, as its output table "
                       f"src/io/outputs/{t['file']} declares them: their type, their names and order among the "
                       "record's values in the journal and the part files, the record as values and back, " + what,
                       ""))
    out.append(f"module supratrans_{name}\n")
    guarded_ints = [f for f in fields if f["type"] == "integer" and type(f.get("empty")) is int]
    out.append(f"{ind}use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan"
               + (", ieee_is_nan" if guarded_ints else "") + "\n")
    out.append(f"{ind}use supratrans_kinds, only: wp\n")
    if writer:
        consts = {(r["path"], kind): const for const, tt, kind, r in table_rows([t])}
        used = [consts[(g["path"], "group")] for g in own_groups(t)] + [consts[(f["dataset"]["path"], "dataset")]
                                                                         for f in fields if "dataset" in f]
        out.append(f"{ind}use supratrans_hdf5, only: h5_file\n")
        out.append(continued(f"{ind}use supratrans_output_rows, only: ", ["write_row", "write_row_group"] + used,
                             ind * 2))
    out.append(f"{ind}implicit none\n{ind}private\n\n")
    out.append(f"{ind}public :: {name}_values, {name}_from_values, empty_{name}"
               + (f", write_{name}" if writer else "") + "\n\n")
    width = max(len(f["name"]) for f in fields)
    out.append(comment(f"The names of the scalar fields among a record's values, in their order.", ind))
    out.append(continued(f"{ind}character(len=*), parameter, public :: {name}_names(*) = [character(len={width}) :: ",
                         [fstring(f["name"]) for f in fields], ind, tail="]"))
    out.append("\n" + comment(f"The scalar fields of a `{rec}` record (src/io/outputs/{t['file']}).", ind))
    out.append(f"{ind}type, public :: {name}\n")
    for f in fields:
        if f.get("journal_only"):
            out.append(comment(f"(in the journal only) {f['description']}", ind * 2))
        else:
            d = f["dataset"]
            doc = re.sub(r"\{([a-z_0-9]*)\}", r"\1", d["description"])
            out.append(comment(f"`/{d['path']}` [{d['units']}]: {doc}", ind * 2))
        init = f.get("initial", 0)
        if f["type"] == "real":
            out.append(f"{ind * 2}real(wp) :: {f['name']} = {float(init)!r}_wp\n")
        else:
            out.append(f"{ind * 2}integer :: {f['name']} = {int(init)}\n")
    out.append(f"{ind}end type {name}\n\ncontains\n\n")

    out.append(comment("The scalar fields as values, in the order of their names.", ind))
    out.append(f"{ind}pure function {name}_values(s) result(v)\n")
    out.append(f"{ind * 2}!> The fields.\n{ind * 2}type({name}), intent(in) :: s\n")
    out.append(f"{ind * 2}real(wp) :: v(size({name}_names))\n\n")
    items = [f"s%{f['name']}" if f["type"] == "real" else f"real(s%{f['name']}, wp)" for f in fields]
    out.append(continued(f"{ind * 2}v = [", items, ind * 2, tail="]"))
    out.append(f"{ind}end function {name}_values\n\n")

    out.append(comment("The scalar fields of values in the order of their names" + (
        " (an integer field whose empty value the table gives takes it from a NaN value)." if guarded_ints else "."),
        ind))
    out.append(f"{ind}pure function {name}_from_values(v) result(s)\n")
    out.append(f"{ind * 2}!> The values (the first `size({name}_names)` are read).\n")
    out.append(f"{ind * 2}real(wp), intent(in) :: v(:)\n{ind * 2}type({name}) :: s\n\n")
    for i, f in enumerate(fields, start=1):
        if f in guarded_ints:
            out.append(f"{ind * 2}s%{f['name']} = {f['empty']}\n")
            out.append(f"{ind * 2}if (.not. ieee_is_nan(v({i}))) s%{f['name']} = nint(v({i}))\n")
            continue
        rhs = f"v({i})" if f["type"] == "real" else f"nint(v({i}))"
        out.append(f"{ind * 2}s%{f['name']} = {rhs}\n")
    out.append(f"{ind}end function {name}_from_values\n\n")

    out.append(comment("The scalar fields with nothing computed: NaN where the table says so, else their default.",
                       ind))
    out.append(f"{ind}pure function empty_{name}() result(s)\n{ind * 2}type({name}) :: s\n")
    out.append(f"{ind * 2}real(wp) :: nan\n\n{ind * 2}nan = ieee_value(nan, ieee_quiet_nan)\n")
    for f in fields:
        if f.get("empty") == "nan":
            out.append(f"{ind * 2}s%{f['name']} = nan\n")
        elif f in guarded_ints:
            out.append(f"{ind * 2}s%{f['name']} = {f['empty']}\n")
    out.append(f"{ind}end function empty_{name}\n\n")
    if not writer:
        out.append(f"end module supratrans_{name}\n")
        return "".join(out)

    sig = ["file", "s", "nomega"] + conds + args
    out.append(comment("Write the scene's groups and the datasets of the scalar fields, one value per task (task = "
                       "(curve - 1) nomega + omega), with their units, descriptions and dimensions.", ind))
    out.append(continued(f"{ind}subroutine write_{name}(", sig, ind, tail=")"))
    out.append(f"{ind * 2}!> Open output file (a failure sticks in it).\n{ind * 2}type(h5_file), intent(inout) :: file\n")
    out.append(f"{ind * 2}!> The fields of each task.\n{ind * 2}type({name}), intent(in) :: s(:)\n")
    out.append(f"{ind * 2}!> Frequencies per curve.\n{ind * 2}integer, intent(in) :: nomega\n")
    for c in conds:
        out.append(comment(t["conditions"][c], ind * 2))
        out.append(f"{ind * 2}logical, intent(in) :: {c}\n")
    for a in args:
        out.append(f"{ind * 2}!> The text of `{{{a}}}` in the descriptions.\n")
        out.append(f"{ind * 2}character(len=*), intent(in) :: {a}\n")

    def guarded(x, lines):
        if "when" in x:
            return [f"{ind * 2}if ({x['when']}) then\n"] + [ind + line for line in lines] + [f"{ind * 2}end if\n"]
        return lines

    def fill(x):
        """(lines before the call, `, fill=...`): the arguments of the `{name}`s of a description, each time it
        names one, in order (more than one: in `texts`, of the longest one's length)."""
        names = re.findall(r"\{([a-z_][a-z0-9_]*)\}", x["description"])
        if not names:
            return [], ""
        if len(set(names)) == 1:
            return [], f", fill=[{names[0]}]"
        width = ", ".join(f"len({n})" for n in dict.fromkeys(names))
        lines = [f"{ind * 2}if (allocated(texts)) deallocate (texts)\n",
                 f"{ind * 2}allocate (character(len=max({width})) :: texts({len(names)}))\n"]
        lines += [f"{ind * 2}texts({i}) = {n}\n" for i, n in enumerate(names, start=1)]
        return lines, ", fill=texts"

    calls = []
    for g in own_groups(t):
        before, arg = fill(g)
        calls += guarded(g, before + [f"{ind * 2}call write_row_group(file, {consts[(g['path'], 'group')]}{arg})\n"])
    for f in fields:
        if "dataset" not in f:
            continue
        d = f["dataset"]
        before, arg = fill(d)
        head = f"{ind * 2}call write_row(file, {consts[(d['path'], 'dataset')]}, "
        data = f"reshape([s%{f['name']}], [nomega, ncurve])"   # [ ]: no temporary of the strided component
        if len(ind + head + data + arg) + 1 > WIDTH:
            head += f"&\n{ind * 3}"
        calls += guarded(d, before + [f"{head}{data}{arg})\n"])
    if any("texts(" in line for line in calls):
        out.append(comment("The texts of the `{name}`s of a description naming more than one.", ind * 2))
        out.append(f"{ind * 2}character(len=:), allocatable :: texts(:)\n")
    out.append(f"{ind * 2}integer :: ncurve\n\n{ind * 2}ncurve = size(s)/max(nomega, 1)\n")
    out += calls
    out.append(f"{ind}end subroutine write_{name}\n\nend module supratrans_{name}\n")
    return "".join(out)


def row_prefix(t):
    """The prefix of a table's row constants: its `prefix`, else the table's file stem."""
    return t.get("prefix", t["file"].removesuffix(".toml"))


def table_rows(tables):
    """[(constant, table, kind, row)] of every dataset and group of every table, in table order (datasets first):
    the constant is `<prefix>_<path>` ('/' -> '_', `{name}` -> name); checked unique and a Fortran name."""
    rows, seen = [], {}
    for t in tables:
        for kind in ("dataset", "group"):
            for r in t[kind]:
                const = (row_prefix(t) + "_" + re.sub(r"[{}]", "", r["path"]).replace("/", "_")).lower()
                if not re.fullmatch(r"[a-z][a-z0-9_]{0,62}", const):
                    raise TableError(f"{t['file']}: {kind} '{r['path']}': its constant '{const}' is not a Fortran "
                                     "name of at most 63 characters (set the table's `prefix`)")
                if const in seen:
                    raise TableError(f"{t['file']}: {kind} '{r['path']}': its constant '{const}' is also that of "
                                     f"{seen[const]}")
                seen[const] = f"{t['file']} '{r['path']}'"
                rows.append((const, t, kind, r))
    return rows


# The groups whose rows one writer writes for every table that has them (`write_curves` of supratrans_curves):
# each row the tables with the group share is the same in each, and has one constant more, `shared_<path>`.
SHARED_GROUPS = ("curves",)
# The keys of a row that may differ between the tables sharing it (what the reader does with it).
SHARED_MAY_DIFFER = {"read", "axes"}


def shared_rows(tables):
    """[(constant, constant of the first table's row, path)] of the rows of SHARED_GROUPS shared by every table
    that has the group (the group and the datasets under it that every such table has); refused unless each is the
    same in every table."""
    rows = table_rows(tables)
    out = []
    for group in SHARED_GROUPS:
        having = [t for t in tables if any(r["path"] == group for r in t["group"])]
        if not having:
            continue
        paths = [group] + [r["path"] for r in having[0]["dataset"] if r["path"].startswith(group + "/")]
        paths = [p for p in paths if all(any(r["path"] == p for r in t["dataset"] + t["group"]) for t in having)]
        for path in paths:
            first = None
            for const, t, kind, r in rows:
                if t not in having or r["path"] != path:
                    continue
                same = {k: v for k, v in r.items() if k not in SHARED_MAY_DIFFER}
                if first is None:
                    first = (const, t, kind, same)
                elif (kind, same) != (first[2], first[3]):
                    raise TableError(f"{t['file']}: {kind} '{path}' differs from that of {first[1]['file']}: the "
                                     f"rows of /{group} that every table with it has are written by one writer, "
                                     "the same in each")
            const = "shared_" + path.replace("/", "_").lower()
            if any(const == c for c, *_ in rows):
                raise TableError(f"the shared row '{path}': its constant '{const}' is also a table's row's")
            out.append((const, first[0], path))
    return out


# The specifics of `write_row`: (suffix, declaration of the data, the table's type).
ROW_WRITERS = (("real", "real(wp), intent(in), target, contiguous :: data(..)", "real"),
               ("int", "integer, intent(in), target, contiguous :: data(..)", "integer"),
               ("i8", "integer(i8), intent(in), target, contiguous :: data(..)", "integer"),
               ("text", "character(len=*), intent(in) :: data(:)", "text"))
# The specifics of `write_row_attr`: (suffix, declaration of the value).
ATTR_WRITERS = (("text", "character(len=*), intent(in) :: value"),
                ("real", "real(wp), intent(in), target, contiguous :: value(..)"),
                ("int", "integer, intent(in), target, contiguous :: value(..)"),
                ("i8", "integer(i8), intent(in), target, contiguous :: value(..)"),
                ("logical", "logical, intent(in) :: value"))

ROWS_HELPERS = """\
    !> The path of a row's object from the root group, with the leading '/' and `{name}` (if any) replaced by
    !> `name`.
    pure function row_path(row, name) result(path)
        !> The row.
        type(output_row), intent(in) :: row
        !> The text of `{name}` in the path.
        character(len=*), intent(in), optional :: name
        character(len=:), allocatable :: path
        type(row_meta) :: m

        m = output_row_meta(row)
        path = "/" // filled(m%path, name)
    end function row_path

    !> The last part of a row's path (`ledger/stored` -> `stored`).
    pure function row_name(row) result(name)
        !> The row.
        type(output_row), intent(in) :: row
        character(len=:), allocatable :: name
        type(row_meta) :: m

        m = output_row_meta(row)
        name = m%path(index(m%path, "/", back=.true.) + 1:)
    end function row_name

    !> The type of a row's dataset: real, integer or text ('' for a group).
    pure function row_type(row) result(type)
        !> The row.
        type(output_row), intent(in) :: row
        character(len=:), allocatable :: type
        type(row_meta) :: m

        m = output_row_meta(row)
        type = m%type
    end function row_type

    !> `text` with its `{name}`s (a name of lower-case letters, digits and '_') replaced: each by `value`, or by the
    !> next of `values` (trimmed); kept as they are without either, or when `values` runs out.
    pure function filled(text, value, values) result(out)
        !> A path or description.
        character(len=*), intent(in) :: text
        !> The text of every `{name}` (a path's).
        character(len=*), intent(in), optional :: value
        !> The texts of the `{name}`s in order (a description's).
        character(len=*), intent(in), optional :: values(:)
        character(len=:), allocatable :: out
        character(len=*), parameter :: name_chars = "abcdefghijklmnopqrstuvwxyz0123456789_"
        integer :: rest, first, last, k

        out = ""
        k = 0
        rest = 1
        do
            first = index(text(rest:), "{")
            if (first == 0) exit
            first = rest + first - 1
            last = index(text(first:), "}")
            if (last == 0) exit
            last = first + last - 1
            out = out // text(rest:first - 1)
            rest = last + 1
            if (last - first < 2 .or. verify(text(first + 1:last - 1), name_chars) /= 0) then
                out = out // text(first:last)
                cycle
            end if
            k = k + 1
            if (present(value)) then
                out = out // value
            else if (present(values)) then
                if (k <= size(values)) then
                    out = out // trim(values(k))
                else
                    out = out // text(first:last)
                end if
            else
                out = out // text(first:last)
            end if
        end do
        out = out // text(rest:)
    end function filled

    !> Whether the row is a dataset of type `type`, and one whose units are the writer's if it gives them (else the
    !> file's error, which sticks).
    function checked(file, row, m, type, units) result(ok)
        !> The file.
        type(h5_file), intent(inout) :: file
        !> The row.
        type(output_row), intent(in) :: row
        !> Its metadata.
        type(row_meta), intent(in) :: m
        !> The type of the data written.
        character(len=*), intent(in) :: type
        !> The units the writer gives.
        character(len=*), intent(in), optional :: units
        logical :: ok

        ok = row%id > 0 .and. .not. m%group .and. m%type == type
        if (.not. ok) then
            call fail(file, "the output table's row '" // m%path // "' is not a dataset of type " // type)
        else if (present(units) .and. index(m%units, "(") /= 1) then
            ok = .false.
            call fail(file, "the output table's row '" // m%path // "' has its units, " // m%units // ": the writer " &
                      // "gives none")
        end if
    end function checked

"""

ROW_WRITER = """\
    !> `write_row` of {typ} data.
    subroutine write_row_{k}(file, row, data, name, fill, units)
        !> The file (a failure sticks in it).
        type(h5_file), intent(inout) :: file
        !> The dataset's row.
        type(output_row), intent(in) :: row
        !> The data.
        {decl}
        !> The text of `{{name}}` in the path.
        character(len=*), intent(in), optional :: name
        !> The texts of the `{{name}}`s in the description, in order.
        character(len=*), intent(in), optional :: fill(:)
        !> The units, where the row's are the writer's to give (in parentheses: `(vary)`, the varied key's).
        character(len=*), intent(in), optional :: units
        type(row_meta) :: m

        m = output_row_meta(row)
        if (.not. checked(file, row, m, "{typ}", units)) return
        if (present(units)) m%units = units
        if (len(m%dims) > 0) then
            call h5_write(file, "/" // filled(m%path, name), data, m%units, filled(m%description, values=fill), &
                          dims=m%dims)
        else
            call h5_write(file, "/" // filled(m%path, name), data, m%units, filled(m%description, values=fill))
        end if
    end subroutine write_row_{k}

"""

GROUP_WRITER = """\
    !> Create a row's group with its description (`h5_create_group`).
    subroutine write_row_group(file, row, fill)
        !> The file (a failure sticks in it).
        type(h5_file), intent(inout) :: file
        !> The group's row.
        type(output_row), intent(in) :: row
        !> The texts of the `{name}`s in the description, in order.
        character(len=*), intent(in), optional :: fill(:)
        type(row_meta) :: m

        m = output_row_meta(row)
        if (.not. m%group) then
            call fail(file, "the output table's row '" // m%path // "' is not a group")
            return
        end if
        call h5_create_group(file, "/" // m%path, filled(m%description, values=fill))
    end subroutine write_row_group

    !> Whether `attribute` is one of the row's attributes (else the file's error, which sticks).
    function listed(file, m, attribute) result(ok)
        !> The file.
        type(h5_file), intent(inout) :: file
        !> The row's metadata.
        type(row_meta), intent(in) :: m
        !> The attribute's name.
        character(len=*), intent(in) :: attribute
        logical :: ok

        ok = index(", " // m%attributes // ",", ", " // attribute // ",") > 0
        if (.not. ok) call fail(file, "the output table's row '" // m%path // "' has no attribute '" // attribute &
                                // "'")
    end function listed

"""

ATTR_WRITER = """\
    !> `write_row_attr` of a {k} value.
    subroutine write_row_attr_{k}(file, row, attribute, value, name)
        !> The file (a failure sticks in it).
        type(h5_file), intent(inout) :: file
        !> The row of the dataset or group.
        type(output_row), intent(in) :: row
        !> The attribute's name, one of the row's attributes.
        character(len=*), intent(in) :: attribute
        !> Its value.
        {decl}
        !> The text of `{{name}}` in the path.
        character(len=*), intent(in), optional :: name
        type(row_meta) :: m

        m = output_row_meta(row)
        if (listed(file, m, attribute)) call h5_write_attr(file, "/" // filled(m%path, name), attribute, value)
    end subroutine write_row_attr_{k}

"""

ROW_META = (("path", "Path from the root group, without the leading '/' (`{name}` where the writer puts a name)."),
            ("dims", "The attribute `dimensions`: the names of its dimensions in h5py's order ('' for none, and "
                     "for a group)."),
            ("units", "The attribute `units` ('' for a group)."),
            ("type", "real, integer or text ('' for a group)."),
            ("description", "The attribute `description` (`{name}` where the writer puts a value)."),
            ("attributes", "The attributes the writer adds, comma-separated ('' for none)."),
            ("field", "The scalar field of the per-task record it holds ('' for none): a writer of a record's "
                      "datasets may loop over their rows."))


def rows_module(tables):
    """src/io/supratrans_output_rows.f90: every row of every table as a named constant, its metadata, and the
    writers that take a dataset's, group's or attribute's metadata from its row."""
    rows = table_rows(tables)
    ind = "    "
    out = [HEADER.format(table="<scene>.toml, every table")]
    out.append(comment(
        "The rows of the output tables (src/io/outputs/<scene>.toml): one named constant of type `output_row` per "
        "dataset and group of each scene's file, `<table>_<path>` (the table's file stem, or its `prefix`; '/' "
        "as '_', `{name}` as name: `hysteresis_cost_wall_time`, `stability_verdict_method`), its metadata "
        "(`output_row_meta`: path, dimensions, units, type, description, attributes), and the writers that take "
        "the metadata from the row: `write_row` (a dataset: its units, description and, unless it has none, "
        "dimensions), `write_row_group` (a group and its description) and `write_row_attr` (an attribute the row "
        "lists). A writer names no unit, description or dimension: a typo in a row's name fails to compile; a "
        "dataset written with data of another type than its row's, or an attribute its row does not list, is the "
        "file's error (it sticks: `h5_commit` returns it).", ""))
    out.append("module supratrans_output_rows\n")
    out.append(f"{ind}use supratrans_kinds, only: wp, i8\n")
    out.append(f"{ind}use supratrans_h5_file, only: fail\n")
    out.append(f"{ind}use supratrans_hdf5, only: h5_file, h5_write, h5_write_attr, h5_create_group\n")
    out.append(f"{ind}implicit none\n{ind}private\n\n")
    out.append(f"{ind}public :: output_row_meta, row_path, row_name, row_type, write_row, write_row_group, "
               "write_row_attr\n\n")
    out.append(comment("A row of an output table: one dataset or group of a scene's file (the named constants "
                       "below; no other can be made).", ind))
    out.append(f"{ind}type, public :: output_row\n{ind * 2}private\n")
    out.append(comment("Its index among every table's rows (0: none).", ind * 2))
    out.append(f"{ind * 2}integer :: id = 0\n{ind}end type output_row\n\n")
    out.append(comment("What a row of an output table says of its dataset or group.", ind))
    out.append(f"{ind}type, public :: row_meta\n")
    for comp, doc in ROW_META:
        out.append(comment(doc, ind * 2))
        out.append(f"{ind * 2}character(len=:), allocatable :: {comp}\n")
    out.append(comment("A group (else a dataset).", ind * 2))
    out.append(f"{ind * 2}logical :: group = .false.\n{ind}end type row_meta\n\n")
    for i, (const, t, kind, r) in enumerate(rows, start=1):
        units = f" [{r['units']}]" if kind == "dataset" else ""
        out.append(comment(f"The {kind} `/{r['path']}`{units} of src/io/outputs/{t['file']}.", ind))
        out.append(f"{ind}type(output_row), parameter, public :: {const} = output_row({i})\n")
    out.append("\n")
    for const, first, path in shared_rows(tables):
        out.append(comment(f"`/{path}`, the same row in every table that has it (one writer writes it for each: "
                           f"`write_curves`).", ind))
        out.append(f"{ind}type(output_row), parameter, public :: {const} = {first}\n")
    out.append("\n")
    out.append(comment("Write a dataset with its row's metadata: `call write_row(file, row, data [, name] [, fill] "
                       "[, units])`; `data` of the row's type (real(wp), default or 8-byte integer of any rank, text "
                       "of rank 1); `name` the text of `{name}` in its path (`verdict/{method}`), `fill` those of the "
                       "`{name}`s in its description, in order (each trimmed); `units` only where the row's units "
                       "are in parentheses, the writer's to give (`(vary)`: the varied key's).", ind))
    out.append(f"{ind}interface write_row\n")
    out.append(continued(f"{ind * 2}module procedure :: ", [f"write_row_{k}" for k, _, _ in ROW_WRITERS], ind * 2))
    out.append(f"{ind}end interface write_row\n\n")
    out.append(comment("Write an attribute its row lists: `call write_row_attr(file, row, attribute, value "
                       "[, name])` (value: text, real(wp), integer, integer(i8) or logical).", ind))
    out.append(f"{ind}interface write_row_attr\n")
    out.append(continued(f"{ind * 2}module procedure :: ", [f"write_row_attr_{k}" for k, _ in ATTR_WRITERS],
                         ind * 2))
    out.append(f"{ind}end interface write_row_attr\n\ncontains\n\n")

    out.append(comment("The metadata of a row (empty for none).", ind))
    out.append(f"{ind}pure function output_row_meta(row) result(m)\n")
    out.append(f"{ind * 2}!> The row.\n{ind * 2}type(output_row), intent(in) :: row\n{ind * 2}type(row_meta) :: m\n\n")
    out.append(f"{ind * 2}select case (row%id)\n")
    for i, (const, t, kind, r) in enumerate(rows, start=1):
        dataset = kind == "dataset"
        out.append(f"{ind * 2}case ({i})   ! {const}\n")
        head = ", ".join(fstring(x) for x in (r["path"], r["dims"] if dataset else "", r["units"] if dataset else "",
                                              r["type"] if dataset else ""))
        out.append(f"{ind * 3}m = row_meta({head}, &\n{ind * 4}{split_literal(r['description'], ind * 4)}, &\n"
                   f"{ind * 4}{split_literal(', '.join(r.get('attributes', [])), ind * 4)}, "
                   f"{fstring(r.get('field', ''))}, {'.false.' if dataset else '.true.'})\n")
    out.append(f'{ind * 2}case default\n{ind * 3}m = row_meta("", "", "", "", "", "", "", .false.)\n')
    out.append(f"{ind * 2}end select\n{ind}end function output_row_meta\n\n")
    out.append(ROWS_HELPERS)
    for k, decl, typ in ROW_WRITERS:
        out.append(ROW_WRITER.format(k=k, decl=decl, typ=typ))
    out.append(GROUP_WRITER)
    for k, decl in ATTR_WRITERS:
        out.append(ATTR_WRITER.format(k=k, decl=decl))
    out.append("end module supratrans_output_rows\n")
    return "".join(out)


def outputs(tables):
    """{path: text} of every generated file."""
    files = {LAYOUT: layout_module(tables), ROWS: rows_module(tables)}
    for t in tables:
        if t["field"]:
            files[SCENES / f"supratrans_{t['record']}_scalars.f90"] = record_module(t)
    return files


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="fail if a generated file is stale")
    args = parser.parse_args(argv)
    try:
        files = outputs(load())
    except (TableError, KeyError, OSError, tomllib.TOMLDecodeError) as e:
        print(f"generate_outputs: {e}", file=sys.stderr)
        return 1
    stale = []
    for path, text in files.items():
        if not path.exists() or path.read_text(encoding="utf-8") != text:
            stale.append(path)
            if not args.check:
                path.write_text(text, encoding="utf-8")
                print(f"generate_outputs: wrote {shown(path)}")
    if args.check and stale:
        for path in stale:
            print(f"generate_outputs: {shown(path)} is stale: run python3 src/io/generate_outputs.py", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
