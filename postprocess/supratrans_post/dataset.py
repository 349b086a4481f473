"""The HDF5 files of supratrans as labelled xarray objects: `load(path)`.

The files already carry what xarray needs to name every axis (each dataset's dimensions have HDF5 dimension scales,
docs/output.md), so `xarray.open_datatree(path, engine="h5netcdf")` opens them, and the root's axes (`/curve`,
`/amplitude`, `/omega`, ...) reach every group by DataTree's inheritance of indexed coordinates. What the files do
not say in CF terms, `load` adds:

- text as str: fixed-length strings (`/curves/potential`, `/methods`, the schema, the namelist) come from h5netcdf
  as bytes (`b'sine-gordon'`); `load` gives str (`'sine-gordon'`);
- labels of the curves: in every group with a `curve` dimension, the coordinates `potential` (str) and, when the
  scene varies a parameter (the `/curves` attribute `vary`, e.g. 'gamma'), that parameter under its own name, with
  each curve's value (`/curves/value`); `curve` stays the 0-based index it is in the file (non-indexed coordinates
  are not inherited by DataTree groups, so each group gets its own copy); likewise the datasets of AXIS_LABELS
  that label other index axes (`sites` on `probe`, the stairs of hysteresis, work_precision's 2-D `dt`);
- CF flags: each status dataset gets `flag_values` and `flag_meanings`, parsed from the free text of its codes (its
  attribute `codes`; for `/runs/status` the `/runs` attribute `status_codes`; for `/status` of `work_precision` and
  `/verdict/<method>` of `stability` the `/scene` attribute `status_codes`), see `parse_codes`;
- `long_name` from each dataset's `description` (the file's `units` are kept as they are: 'rad', 'energy', '1', ...).

The attribute `DIMENSION_LABELS` (HDF5's dimension labels, the same names as the attribute `dimensions`) is dropped.
The file is read eagerly and closed again. xarray and h5netcdf are needed only here (imported on first use).
"""
from __future__ import annotations

import re
import warnings
from typing import Any

import numpy as np

from .reader import PlotError, resolve

__all__ = ["load", "parse_codes", "flag_words"]

#: Where the codes of a status dataset live when it has no attribute `codes` of its own: {dataset path pattern:
#: (group, attribute)}; the first pattern that matches the dataset's path (re.fullmatch) applies.
SHARED_CODES: dict[str, tuple[str, str]] = {
    r"/runs/status": ("/runs", "status_codes"),  # amplitude_sweep, map
    r"/status": ("/scene", "status_codes"),  # work_precision
    r"/verdict/[^/]+": ("/scene", "status_codes"),  # stability: one dataset per method
}

_CODE = re.compile(r"\s*(-?\d+(?:\s*,\s*-?\d+)*)(?:\s*:\s*|\s+)(\S.*)?$", re.DOTALL)


def _split_top(text: str, sep: str) -> list[str]:
    """`text` cut at each `sep` outside parentheses (and brackets: "(a_min, a_max]" closes)."""
    parts, depth, start = [], 0, 0
    for i, ch in enumerate(text):
        if ch in "([":
            depth += 1
        elif ch in ")]":
            depth = max(depth - 1, 0)
        elif ch == sep and depth == 0:
            parts.append(text[start:i])
            start = i + 1
    parts.append(text[start:])
    return [p.strip() for p in parts if p.strip()]


def _cut_name(rest: str) -> str:
    """The name of a code: its text up to the first ':', ',', ';' or '(' outside parentheses."""
    depth = 0
    for i, ch in enumerate(rest):
        if ch in "([":
            if depth == 0 and i > 0:
                return rest[:i].strip()
            depth += 1
        elif ch in ")]":
            depth = max(depth - 1, 0)
        elif ch in ":,;" and depth == 0:
            return rest[:i].strip()
    return rest.strip()


def flag_words(name: str) -> str:
    """A code's name as one CF flag_meanings word: 'outside gap' -> 'outside_gap' (letters, digits and '_' only,
    lower case)."""
    return re.sub(r"[^a-z0-9]+", "_", name.lower()).strip("_") or "unnamed"


def parse_codes(text: str) -> list[tuple[int, str, str]]:
    """The codes of a status dataset from the free text the files hold, as [(value, word, meaning), ...] in the
    order given: `word` is the code's name as one CF flag word, `meaning` the whole text of that code.

    Every form the program writes is read: "-2 outside_gap: not run ...; -1 not_run: ...", "-2: outside gap (not
    computed); -1: pending ...", "-1 not_run, 0 ok, 1 diverged (...), 2 newton_failed" (entries separated by ',' when
    ';' separates none), "1, 2, 3, 4: the last branch ..." (one text for several codes: each gets the word with its
    value appended), and a ';' part that starts with no code continues the meaning before it (or, before the first
    code, is a preamble and ignored: "stable means 0 ok; 0 ok: ..."). Separators inside parentheses do not count.
    Raises ValueError when no code is found or a value repeats.
    """
    def entries(sep: str) -> list[tuple[list[int], str]]:
        found: list[tuple[list[int], str]] = []
        for part in _split_top(text, sep):
            m = _CODE.match(part)
            if m:
                found.append(([int(v) for v in m.group(1).split(",")], (m.group(2) or "").strip()))
            elif found:  # the meaning goes on past a ';' of its own
                values, rest = found[-1]
                found[-1] = (values, f"{rest}{sep} {part}")
        return found

    found = entries(";")
    if len(found) < 2:
        found = max(found, entries(","), key=len)
    if not found:
        raise ValueError(f"no codes in {text!r}")
    out: list[tuple[int, str, str]] = []
    for values, rest in found:
        word = flag_words(_cut_name(rest)) if rest else "unnamed"
        for v in values:
            out.append((v, word if len(values) == 1 else f"{word}_{v}", rest))
    seen = [v for v, _, _ in out]
    if len(set(seen)) != len(seen):
        raise ValueError(f"a code repeats in {text!r}")
    return out


# ------------------------------------------------------------------------------------------------ loading


def _as_str(values: np.ndarray) -> np.ndarray:
    """Fixed-length HDF5 strings (bytes) as a numpy str array, trailing NULs and blanks removed."""
    return np.vectorize(lambda b: b.decode("utf-8", "replace").rstrip("\x00").strip() if isinstance(b, bytes)
                        else str(b), otypes=[str])(values) if values.size else values.astype(str)


def _decode_text(ds):
    """The Dataset `ds` with every bytes variable and coordinate (dtype 'S' or bytes objects) as str."""
    changed = {}
    for name, var in ds.variables.items():
        if var.dtype.kind == "S" or (var.dtype.kind == "O" and var.size and isinstance(var.values.flat[0], bytes)):
            changed[name] = var.copy(data=_as_str(var.values))
    if not changed:
        return ds
    coords = {k: v for k, v in changed.items() if k in ds.coords}
    data = {k: v for k, v in changed.items() if k not in ds.coords}
    return ds.assign_coords(coords).assign(data)


def _cf_attrs(ds, path: str, codes: dict[str, str]):
    """`long_name` (from `description`) on every variable of the Dataset `ds` (the node at `path`), `flag_values`
    and `flag_meanings` on those with codes ({variable path: text}); `DIMENSION_LABELS` dropped."""
    for name, var in ds.variables.items():
        attrs = dict(var.attrs)
        attrs.pop("DIMENSION_LABELS", None)
        if "description" in attrs and "long_name" not in attrs:
            attrs["long_name"] = attrs["description"]
        full = f"{path.rstrip('/')}/{name}"
        if full in codes and var.dtype.kind in "iuf":
            try:
                parsed = parse_codes(codes[full])
            except ValueError as exc:  # a text this parser does not know: the variable without flags, said once
                warnings.warn(f"{full}: no CF flags ({exc})", stacklevel=3)
            else:
                attrs["flag_values"] = np.array([v for v, _, _ in parsed], dtype=var.dtype)
                attrs["flag_meanings"] = " ".join(w for _, w, _ in parsed)
        var.attrs = attrs
    return ds


def _group_attr(tree, group: str, attr: str) -> Any:
    """The attribute `attr` of the group `group` ('/runs') of the DataTree `tree`, None when either is absent."""
    try:
        return tree[group.lstrip("/")].attrs.get(attr)
    except KeyError:
        return None


def _codes_of(tree) -> dict[str, str]:
    """The codes text of every status dataset of the DataTree `tree`, {dataset path: text} (see SHARED_CODES)."""
    out: dict[str, str] = {}
    for node in tree.subtree:
        for name, var in node.to_dataset(inherit=False).variables.items():
            full = f"{node.path.rstrip('/')}/{name}"
            text = var.attrs.get("codes")
            if text is None:
                for pattern, (group, attr) in SHARED_CODES.items():
                    if re.fullmatch(pattern, full):
                        text = _group_attr(tree, group, attr)
                        break
            if isinstance(text, str) and text.strip():
                out[full] = text
    return out


#: Datasets that label an axis whose dimension scale is a bare index (docs/output.md): each becomes a coordinate,
#: under its own name, of every group with all of its dimensions (as the curve labels do).
AXIS_LABELS = ("/probes/sites", "/stair_time", "/stair_amplitude", "/stair_direction", "/dt")


def _labels(tree) -> dict[str, Any]:
    """The coordinates that label index axes, {name: xarray Variable}: of `curve`, `potential` (str) and the varied
    parameter (named by the `/curves` attribute `vary`, values `/curves/value`) unless `vary` is 'none'; the
    datasets of AXIS_LABELS the file has, over index dimensions only (`/dt` of `work_precision`, over (methods,
    dt_index), not the `/dt` axis of `stability`)."""
    import xarray as xr  # noqa: PLC0415

    labels: dict[str, Any] = {}
    if "curves" in tree.children:
        curves = tree["curves"].to_dataset(inherit=False)
        if "potential" in curves:
            p = curves["potential"].variable
            labels["potential"] = xr.Variable(("curve",), _as_str(np.asarray(p.values)), {
                **p.attrs, "long_name": "on-site potential of each curve"})
        vary = str(tree["curves"].attrs.get("vary", "none")).strip()
        if vary and vary != "none" and "value" in curves:
            v = curves["value"].variable
            labels[vary] = xr.Variable(("curve",), v.values, {
                **v.attrs, "long_name": f"{vary} of each curve (the varied parameter: /curves/value)"})
    for path in AXIS_LABELS:
        group, name = path.rsplit("/", 1)
        try:
            ds = tree[group.lstrip("/")].to_dataset(inherit=False) if group else tree.to_dataset(inherit=False)
        except KeyError:
            continue
        if name in ds.data_vars and name not in ds.dims and not set(ds[name].dims) & {name}:
            var = ds[name].variable
            labels.setdefault(name, var.copy(data=_as_str(var.values) if var.dtype.kind == "S" else var.values))
    for var in labels.values():
        var.attrs.pop("DIMENSION_LABELS", None)
        var.attrs.setdefault("long_name", var.attrs.get("description", ""))
    return labels


def _label(ds, labels: dict[str, Any]):
    """The Dataset `ds` with each label whose dimensions it has all of as a coordinate; a data variable of the
    same name, dimensions and values (in the group the label comes from) becomes that coordinate, another variable
    of that name is left alone."""
    add = {}
    for name, var in labels.items():
        if not set(var.dims) <= set(ds.dims):
            continue
        if name in ds.variables:
            own = ds[name].variable
            if name not in ds.coords and own.dims == var.dims and np.array_equal(np.asarray(own.values), var.values,
                                                                                   equal_nan=own.dtype.kind == "f"):
                ds = ds.set_coords(name)
                ds[name].attrs.update(long_name=var.attrs["long_name"])
            continue
        add[name] = var
    return ds.assign_coords(add) if add else ds


def load(path: Any):
    """The supratrans output file `path` (or its partial snapshot `<path>.partial.h5`) as labelled xarray data: an
    `xarray.DataTree` for a file with groups (every supratrans file: `/parameters`, `/provenance`, ...), else an
    `xarray.Dataset`.

    Every variable has its coordinates (the root's axes are inherited by every group), `curve` carries the
    coordinates `potential` (str) and the varied parameter (e.g. `gamma`), text is str, status variables carry CF
    `flag_values` and `flag_meanings`, every variable `long_name` and `units`. Read eagerly; the file is closed.

        tree = supratrans_post.load("out/fig2.h5")
        e = tree["energy/injected"]                       # (curve, amplitude), with potential and gamma
        e.sel(amplitude=1.8).where(e.potential == "sine-gordon", drop=True)

    Raises PlotError (one line) for a file that is missing, not HDF5 or not readable by h5netcdf; ImportError with
    what to install when xarray or h5netcdf is missing.
    """
    try:
        import xarray as xr  # noqa: PLC0415 (only the loader needs xarray)
        import h5netcdf  # noqa: F401, PLC0415
    except ImportError as exc:
        raise ImportError(f"supratrans_post.load needs xarray and h5netcdf ({exc}): pip install xarray h5netcdf "
                          "(versions in postprocess/requirements.txt)") from exc
    p = resolve(path)
    try:
        with xr.open_datatree(p, engine="h5netcdf", phony_dims="sort", decode_times=False,
                              decode_timedelta=False) as opened:
            tree = opened.load()
    except (OSError, ValueError, KeyError, TypeError) as exc:
        first = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise PlotError(p, f"cannot open with xarray/h5netcdf ({first})") from None
    codes = _codes_of(tree)
    labels = _labels(tree)
    nodes = {}
    for node in tree.subtree:
        ds = _decode_text(node.to_dataset(inherit=False))
        ds = _label(ds, labels)
        nodes[node.path] = _cf_attrs(ds, node.path, codes)
    out = xr.DataTree.from_dict(nodes, name=tree.name)
    return out if out.children else out.to_dataset()
