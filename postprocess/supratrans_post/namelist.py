"""The namelists of `input/`, read and written with f90nml: the scene a namelist runs, the file it writes, and the
`--quick` copies of make_figures.py (coarser scene grids, output elsewhere)."""
from __future__ import annotations

from pathlib import Path
from typing import Any

from .reader import PlotError

#: `--quick`: factor applied to the steps of the scene grids (amplitude, frequency, threshold resolution, stairs).
QUICK = {"amplitude_step": 5.0, "omega_step": 2.0, "resolution": 5.0, "coarse_step": 2.0, "stair_height": 5.0}
#: `--quick`: the factors of QUICK that a scene replaces. A fold costs seconds to minutes (much more at small Omega),
#: so a fold line takes every tenth frequency: input/fold_sg.nml's 95 folds become 10.
QUICK_SCENE = {"continuation": {"omega_step": 10.0}}
#: `--quick` of a continuation by harmonic balance (`solver = 'harmonic_balance'`): a fold costs about K^3 N with K
#: growing as 1/Omega (Omega = 0.05 alone takes minutes, 0.15 some seconds), so the frequencies start at
#: `omega_min` at the lowest; at least `frequencies` of them are kept (input/fold_continuum.nml's three), and the
#: first `couplings` of `c_values` (c = 4, 8, 16: the largest chain, N = 1600 at c = 32, costs as much as the others
#: together).
QUICK_HB = {"omega_min": 0.15, "frequencies": 3, "couplings": 3}


def read(path: Any):
    """The namelist file `path` as an f90nml Namelist ({group: {key: value}}, names in lower case); PlotError
    (one line) when it cannot be read or parsed."""
    import f90nml  # noqa: PLC0415 (only make_figures and work_precision read namelists)

    try:
        return f90nml.read(str(path))
    except OSError as exc:
        raise PlotError(path, f"cannot read ({exc.strerror or exc})") from None
    except Exception as exc:  # noqa: BLE001 (f90nml raises ValueError, IndexError, ... on bad syntax)
        first = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise PlotError(path, f"not a namelist f90nml can read ({first})") from None


def _group(nml, name: str) -> dict:
    """The group `&name` of a namelist ({} when absent; the first one when it is repeated)."""
    g = nml.get(name, {})
    if isinstance(g, list):
        g = g[0] if g else {}
    return g


def scene_kind(nml) -> str:
    """The scene a namelist runs (`&scene kind`, default 'timeseries'), in lower case."""
    return str(_group(nml, "scene").get("kind", "timeseries")).lower()


def output_file(nml) -> str | None:
    """The file a namelist writes (`&output file`), None when it names none."""
    out = _group(nml, "output").get("file")
    return str(out) if out else None


def _quick_harmonic_balance(scene, step: Any) -> None:
    """The `--quick` grid of a continuation by harmonic balance (QUICK_HB), its omega_step already scaled; `step`:
    the namelist's own omega_step."""
    if isinstance(scene.get("omega_min"), (int, float)):
        scene["omega_min"] = max(float(scene["omega_min"]), QUICK_HB["omega_min"])
    lo, hi, coarse = scene.get("omega_min"), scene.get("omega_max"), scene.get("omega_step")
    if all(isinstance(v, (int, float)) for v in (lo, hi, coarse, step)) and hi > lo:
        widest = (float(hi) - float(lo)) / (QUICK_HB["frequencies"] - 1)
        if coarse > widest:
            scene["omega_step"] = float(f"{max(float(step), widest):.6g}")
    values = scene.get("c_values")
    if isinstance(values, list) and len(values) > QUICK_HB["couplings"]:
        scene["c_values"] = values[: QUICK_HB["couplings"]]


def quick_copy(source: Any, target: Any, output: Any) -> Path:
    """Write to `target` a copy of the namelist `source` whose scene grids are coarser (the steps of QUICK scaled,
    rounded to 6 significant digits as the copies always were; a continuation by harmonic balance also QUICK_HB),
    that writes `output` and may overwrite it.
    Returns `target`."""
    nml = read(source)
    scene = _group(nml, "scene")
    step = scene.get("omega_step")
    factors = {**QUICK, **QUICK_SCENE.get(str(scene.get("kind", "")).lower(), {})}
    for key, factor in factors.items():
        value = scene.get(key)
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            scene[key] = float(f"{float(value) * factor:.6g}")
    if str(scene.get("kind", "")).lower() == "continuation":
        scene["fold_convergence"] = False  # the dt/2 and 2N folds cost 20x the fold itself
    if str(scene.get("solver", "")).lower() == "harmonic_balance":
        _quick_harmonic_balance(scene, step)
    if "output" not in nml:
        nml["output"] = {}
    out = _group(nml, "output")
    out["file"] = str(output)
    out["overwrite"] = True
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    nml.write(str(target), force=True)
    return target
