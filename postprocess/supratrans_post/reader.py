"""The one reader of the HDF5 files written by supratrans: which datasets each scene has, their shapes, and the
one-line errors of a file that cannot be used.

`open_scene(path, expect=...)` reads, eagerly, everything the figures, charts and the SciPy peer need of one file
(root attributes, `/parameters`, the attributes of every top-level group, and the datasets of `SCHEMA` for its
scene, or of `SOLVER_SCHEMA` when its root attribute `solver` names another solver) and closes it again. A file
that cannot be used raises `PlotError`, which the command-line scripts print as the one line
`error: <file>: <what is wrong>` before they exit with status 2: missing, not HDF5, truncated, not a supratrans
file, of an unknown or another scene, a dataset missing, of the wrong rank, text where numbers belong, an axis
with a value that is not a finite number, or a length along an axis that disagrees with the axis (README,
"Output", has the layouts).

Which axis each dimension of a dataset runs over (`Scene.dims`, `Scene.coordinate`): the HDF5 dimension scale
attached to it when there is one (h5py: `ds.dims[i][0]`, as xarray and HDFView read it), else the name in the
dataset's attribute `dimensions` ('curve, amplitude'), else the schema's (`SCHEMA`). The datasets themselves are
read by their paths in `SCHEMA`.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable

import numpy as np

from . import layout

__all__ = ["PlotError", "Scene", "SCHEMA", "SOLVER_SCHEMA", "SCENES", "FIGURE_SCENES", "CHART_SCENES", "open_scene",
           "open_h5", "resolve", "output_path", "figure_name", "text", "value", "schema_of"]


class PlotError(Exception):
    """A file that cannot be used: its path and what is wrong with it, in one line."""

    def __init__(self, path: Any, what: Any) -> None:
        super().__init__(f"{path}: {what}")
        self.path = str(path)
        self.what = " ".join(str(what).split())

    def line(self) -> str:
        """The message the scripts print: `error: <file>: <what is wrong>`."""
        return f"error: {self.path}: {self.what}"


# ------------------------------------------------------------------------------------------------ the schema

#: The datasets of each scene that the scripts read, {scene: {h5py path: (dimensions, required)}}, in the order they
#: are checked; each dimension names the axis a dataset runs over: the first dataset (in this order) with that axis
#: sets its length and every later one must agree. Datasets not listed are not read. Generated from the output
#: tables, src/io/outputs/<scene>.toml (the rows with `read`), by src/io/generate_outputs.py (`layout.py`): the same
#: tables the Fortran writers' records and metadata follow.
SCHEMA: dict[str, dict[str, tuple[tuple[str, ...], bool]]] = layout.SCHEMA
#: The datasets of a scene whose file names another solver in its root attribute `solver`, {(scene, solver): as
#: SCHEMA}: the continuation scene by harmonic balance (src/io/outputs/continuation_harmonic_balance.toml) has
#: /fold_amplitude, /status and /branch as the shooting layout means them, its own convergence checks (the
#: harmonics K, the rk8 period from the fold's state, the absorber family, the continuum limit in c), and none of
#: shooting's stability and transmission datasets.
SOLVER_SCHEMA: dict[tuple[str, str], dict[str, tuple[tuple[str, ...], bool]]] = layout.SOLVER_SCHEMA
#: The datasets that hold text (names); every other dataset of SCHEMA holds numbers.
TEXT = layout.TEXT
#: The axes of the grids and records, {schema dimension: dataset}: each value of one must be a finite number (the
#: 2-D `dt` of work_precision, one row of time steps per method padded with NaN, needs one finite value at least).
AXES = {"amplitude": "amplitude", "omega": "omega", "c": "c", "dt": "dt", "probe": "probes/sites",
        "stair_length": "stair_time", "stair": "stair_amplitude",
        "probe_time": "probes/time", "ledger_time": "ledger/time"}
#: Every scene the program writes.
SCENES = tuple(SCHEMA)
#: Attributes of a dataset that the figures show, kept by `read` (`Scene.attr`): the thin verdicts' margin.
DATASET_ATTRS = ("thin_margin", "thin_verdicts", "flag_values", "flag_meanings")
#: Scenes drawn as figures of the paper (`figures`), and as the speed/accuracy charts (`charts`).
FIGURE_SCENES = ("timeseries", "amplitude_sweep", "map", "bifurcation", "continuation", "hysteresis")
CHART_SCENES = ("stability", "work_precision")


# ------------------------------------------------------------------------------------------------ values


def text(v: Any) -> Any:
    """An HDF5 string attribute or element (fixed-length bytes) as str; a bytes array as a list of str."""
    if isinstance(v, (bytes, np.bytes_)):
        return v.decode("utf-8", "replace").strip().rstrip("\x00").strip()
    if isinstance(v, np.ndarray) and v.dtype.kind == "S":
        return [text(x) for x in v.tolist()]
    return v


def value(v: Any) -> Any:
    """An HDF5 attribute as a plain Python value (str, int, float, or a list for arrays)."""
    v = text(v)
    if isinstance(v, np.ndarray):
        return v.tolist() if v.ndim > 0 else v.item()
    if isinstance(v, np.generic):
        return v.item()
    return v


# ------------------------------------------------------------------------------------------------ the scene


@dataclass
class Scene:
    """What the scripts need from one file, read eagerly (the file is closed again)."""

    #: Path of the file read.
    path: str
    #: Scene name (root attribute `scene`).
    scene: str
    #: Root attributes.
    attrs: dict
    #: Attributes of `/parameters`: the input parameters and derived linear theory.
    params: dict
    #: Datasets read, by path without the leading slash.
    data: dict = field(default_factory=dict)
    #: Attributes of the top-level groups (`/run`, `/runs`, `/curves`, `/scene`, ...), by name.
    groups: dict = field(default_factory=dict)
    #: Units of the datasets read (their attribute `units`).
    units: dict = field(default_factory=dict)
    #: The axis each dimension of a dataset read runs over, {dataset: (axis name, ...)}: the name of the dimension
    #: scale attached, else from the attribute `dimensions`, else the schema's (see `dimension_axes`).
    dims: dict = field(default_factory=dict)
    #: Values of the dimension scales attached to the datasets read, {(dataset, dimension index): array}.
    scales: dict = field(default_factory=dict)
    #: The attributes of DATASET_ATTRS of the datasets read, {dataset: {attribute: value}}.
    attributes: dict = field(default_factory=dict)

    def attr(self, name: str, key: str, default: Any = None) -> Any:
        """The attribute `key` of the dataset `name` read (one of DATASET_ATTRS), `default` when absent."""
        return self.attributes.get(name, {}).get(key, default)

    def coordinate(self, name: str, i: int = 0) -> np.ndarray | None:
        """The coordinates along dimension `i` of the dataset `name`: its dimension scale when one is attached,
        else the axis dataset of the schema (AXES) when the file has it, else None (e.g. the curves)."""
        if (name, i) in self.scales:
            return self.scales[name, i]
        dims = schema_of(self.scene, self.solver)[name][0]
        axis = AXES.get(dims[i]) if i < len(dims) else None
        return self.data.get(axis) if axis else None

    @property
    def name(self) -> str:
        """Figure name: the stem of the input file that made the file (`input/fig2.nml` -> 'fig2')."""
        return figure_name(self)

    @property
    def solver(self) -> str:
        """The solver that wrote the file (root attribute `solver`, 'harmonic_balance' for a continuation by
        harmonic balance); '' when the file names none (the scene's only solver, shooting for a continuation)."""
        return str(self.attrs.get("solver", ""))

    @property
    def quick(self) -> bool:
        """Whether the file is from a quick copy of its namelist (make_figures --quick: coarser grids): the input
        file it records (root attribute `input_file`) lies in a folder `quick/input/`."""
        parts = Path(str(text(self.attrs.get("input_file", "")))).parts
        return len(parts) >= 3 and parts[-3:-1] == ("quick", "input")

    @property
    def partial(self) -> bool:
        """Whether the file is a partial snapshot of a scene still running or killed (`complete` = 0)."""
        return int(self.attrs.get("complete", 1)) == 0

    def progress(self) -> tuple[int, int, str] | None:
        """(runs done, runs in all, what a run is) of a grid scene; None for the others."""
        if self.scene in ("amplitude_sweep", "map"):
            total = self.attrs.get("runs_total", self.data["runs/status"].size)
            done = self.attrs.get("runs_done", int(np.count_nonzero(self.data["runs/status"] != -1)))
            return int(done), int(total), "runs"
        if self.scene in ("bifurcation", "continuation", "hysteresis"):
            total = self.attrs.get("tasks_total", self.data["status"].size)
            done = self.attrs.get("tasks_done", int(np.count_nonzero(self.data["status"] != -1)))
            what = {"bifurcation": "threshold searches", "continuation": "continuations"}.get(self.scene, "stair runs")
            return int(done), int(total), what
        return None

    def partial_note(self) -> str:
        """'partial: k of n runs' for a partial file, '' otherwise."""
        progress = self.progress() if self.partial else None
        if progress is None:
            return ""
        done, total, what = progress
        return f"partial: {done} of {total} {what}"

    def unit(self, name: str, default: str = "") -> str:
        """Units of a dataset read, as an axis label suffix: ' [rad]'; ' (scaled)' for the model's
        dimensionless time, energy and frequency ('time', 'energy', '1/time'); '' for pure numbers."""
        u = self.units.get(name, default)
        if not u or u == "1":
            return ""
        if u in ("time", "energy", "1/time", "1/time^2", "time^-1"):
            return " (scaled)"
        return f" [{u}]"


# ------------------------------------------------------------------------------------------------ reading


def resolve(path: Any) -> Path:
    """The file to read for `path`: itself, or `<path>.partial.h5` when only the partial snapshot of a scene
    still running (or killed) exists. Raises PlotError when neither exists."""
    p = Path(path)
    if p.is_file():
        return p
    partial = Path(str(p) + ".partial.h5")
    if partial.is_file():
        return partial
    if p.exists():
        raise PlotError(path, "not a regular file")
    raise PlotError(path, "no such file" + (" (nor a partial snapshot " + partial.name + ")"
                                            if p.suffix == ".h5" else ""))


def open_h5(path: Any):
    """Open an HDF5 file for reading; a missing, truncated or non-HDF5 file is a one-line PlotError."""
    import h5py  # noqa: PLC0415 (only the readers need it)

    try:
        return h5py.File(path, "r")
    except OSError as exc:
        reason = str(exc).split("\n")[0]
        if "truncated" in reason:
            raise PlotError(path, f"truncated HDF5 file ({reason})") from None
        if "signature" in reason or "not an hdf5" in reason.lower():
            raise PlotError(path, "not an HDF5 file") from None
        raise PlotError(path, f"cannot open as HDF5 ({reason})") from None


def open_scene(path: Any, expect: str | Iterable[str] | None = None) -> Scene:
    """Read the file `path` (or its partial snapshot, see `resolve`).

    `expect`: a scene name or several the caller can use. Raises PlotError (one line) when the file is missing,
    not HDF5 or truncated, not a supratrans file, of an unknown or another scene, or lacks a dataset of `SCHEMA`.
    """
    p = resolve(path)
    f = open_h5(p)
    try:
        with f:
            return _read(f, p, expect)
    except PlotError:
        raise
    except (OSError, KeyError, ValueError, TypeError, RuntimeError) as exc:
        raise PlotError(p, f"cannot read ({str(exc).splitlines()[0] if str(exc) else type(exc).__name__}); "
                           "the file may be truncated or damaged") from None


def _read(f, p: Path, expect: str | Iterable[str] | None) -> Scene:
    """The Scene of an open file `f` (path `p`), checked against SCHEMA; PlotError for what is wrong."""
    import h5py  # noqa: PLC0415

    attrs = {k: value(v) for k, v in f.attrs.items()}
    if "scene" not in attrs:
        code = attrs.get("code")
        raise PlotError(p, "no root attribute 'scene': not a supratrans output file"
                        + (f" (code '{code}')" if code else ""))
    scene = str(attrs["scene"])
    if scene not in SCHEMA:
        raise PlotError(p, f"unknown scene '{scene}' (known: {', '.join(SCENES)})")
    if expect is not None:
        wanted = (expect,) if isinstance(expect, str) else tuple(expect)
        if scene not in wanted:
            raise PlotError(p, f"scene is '{scene}', expected '{' or '.join(wanted)}'")
    if "parameters" not in f or not isinstance(f["parameters"], h5py.Group):
        raise PlotError(p, f"group '/parameters' missing (scene {scene})")
    out = Scene(path=str(p), scene=scene, attrs=attrs, params={k: value(v) for k, v in f["parameters"].attrs.items()})
    for name, obj in f.items():
        if isinstance(obj, h5py.Group) and name != "parameters":
            out.groups[name] = {k: value(v) for k, v in obj.attrs.items()}
    schema = schema_of(scene, str(attrs.get("solver", "")))
    for name, (dims, required) in schema.items():
        obj = f.get(name)
        if obj is None or not isinstance(obj, h5py.Dataset):
            if required:
                raise PlotError(p, f"dataset '/{name}' missing (scene {scene})")
            continue
        data = obj[()]
        if data.dtype.kind in "SO":
            data = np.array([text(x) for x in np.atleast_1d(data).tolist()], dtype=object)
        if np.ndim(data) != len(dims):
            raise PlotError(p, f"dataset '/{name}' has shape {np.shape(data)}, expected rank {len(dims)}")
        _check_values(p, name, data, name in AXES.values())
        out.data[name] = data
        if "units" in obj.attrs:
            out.units[name] = text(obj.attrs["units"])
        out.attributes[name] = {k: value(v) for k, v in obj.attrs.items() if k in DATASET_ATTRS}
        out.dims[name] = dimension_axes(obj, dims)
        for i, scale in enumerate(_scales(obj)):
            if scale is None:
                continue
            values = scale[()]
            if values.shape != (data.shape[i],):
                raise PlotError(p, f"dataset '/{name}': its dimension scale '{scale.name}' along dimension {i} "
                                   f"has shape {values.shape}, expected ({data.shape[i]},)")
            if dims[i] in AXES:
                _check_values(p, scale.name.lstrip("/"), values, True)
            out.scales[name, i] = values
    _check_dimensions(p, out, schema)
    return out


def schema_of(scene: str, solver: str = "") -> dict[str, tuple[tuple[str, ...], bool]]:
    """The datasets read of a file of `scene` written by `solver` (its root attribute, '' when it has none):
    SOLVER_SCHEMA's when it lists the pair, else SCHEMA's for the scene."""
    return SOLVER_SCHEMA.get((scene, solver), SCHEMA[scene])


def _check_values(p: Path, name: str, data: np.ndarray, axis: bool) -> None:
    """Numbers where SCHEMA wants numbers (all but TEXT); for an `axis`, every value of a 1-D one a finite number,
    one at least of another (the NaN-padded 2-D `dt` of work_precision)."""
    if name in TEXT:
        return
    if data.dtype.kind not in "biuf":
        what = "text" if data.dtype.kind in "SUO" else f"values of type {data.dtype}"
        raise PlotError(p, f"dataset '/{name}' holds {what}, expected numbers")
    if not axis or data.size == 0:
        return
    bad = np.flatnonzero(~np.isfinite(data))
    if bad.size == data.size:
        raise PlotError(p, f"axis '/{name}' has no finite value (all {data.size} are {data.flat[0]})")
    if bad.size and data.ndim == 1:
        raise PlotError(p, f"axis '/{name}' has {bad.size} values that are not finite numbers "
                           f"(the first at index {bad[0]}: {data.flat[bad[0]]})")


def _scales(obj) -> list:
    """The dimension scale attached to each dimension of the dataset `obj` (h5py: `obj.dims[i][0]`), or None."""
    out = []
    for i in range(obj.ndim):
        try:
            out.append(obj.dims[i][0] if len(obj.dims[i]) else None)
        except (KeyError, ValueError, RuntimeError, OSError):  # a broken reference: as if none were attached
            out.append(None)
    return out


def dimension_axes(obj, dims: tuple[str, ...] = ()) -> tuple[str, ...]:
    """The name of the axis each dimension of the h5py dataset `obj` runs over: the dimension scale attached to
    it (its HDF5 dimension-scale name, else the last part of its path) when there is one; else the name at that
    place in the attribute `dimensions` ('curve, amplitude'), when it names one per dimension; else `dims` (the
    schema's); else 'dim<i>'."""
    listed = [x.strip() for x in str(text(obj.attrs.get("dimensions", b""))).split(",") if x.strip()]
    if len(listed) != obj.ndim:
        listed = []
    names = []
    for i, scale in enumerate(_scales(obj)):
        if scale is not None:
            name = text(scale.attrs.get("NAME", b""))
            name = name if isinstance(name, str) and name and not name.startswith("This is a netCDF") else ""
            names.append(name or scale.name.rsplit("/", 1)[-1])
        elif listed:
            names.append(listed[i])
        else:
            names.append(dims[i] if i < len(dims) else f"dim{i}")
    return tuple(names)


def _check_dimensions(p: Path, s: Scene, schema: dict) -> None:
    """Every dataset read agrees with the others on the length of each axis it runs over."""
    length: dict[str, int] = {}
    for name, (dims, _) in schema.items():
        if name not in s.data:
            continue
        shape = tuple(s.data[name].shape)
        for d, n in zip(dims, shape):
            length.setdefault(d, n)
        expected = tuple(length[d] for d in dims)
        if shape != expected:
            raise PlotError(p, f"dataset '/{name}' has shape {shape}, expected {expected}")


# ------------------------------------------------------------------------------------------------ names


def figure_name(scene: Scene) -> str:
    """Name of the figure a file belongs to: the stem of its input file (`input/fig3half.nml` -> 'fig3half'),
    'fig1' for the four Fig. 1 runs (`fig1_sg_A177` ...)."""
    stem = Path(str(scene.attrs.get("input_file", "") or Path(scene.path).name)).name
    stem = re.sub(r"(\.h5)?(\.partial\.h5)?$", "", stem)
    stem = re.sub(r"\.nml$", "", stem)
    if re.match(r"fig1_", stem):
        return "fig1"
    return stem


def output_path(path: Any, suffix: str = ".png") -> Path:
    """Default path of what is made from a data file: `out/fig2.h5` -> `out/fig2.png`, a partial snapshot
    `out/fig2.h5.partial.h5` -> `out/fig2.partial.png`."""
    p = Path(path)
    name = p.name
    if name.endswith(".h5.partial.h5"):
        name = name[: -len(".h5.partial.h5")] + ".partial"
    elif name.endswith(".h5"):
        name = name[:-3]
    return p.with_name(name + suffix)
