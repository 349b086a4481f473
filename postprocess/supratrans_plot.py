"""Read the HDF5 files written by supratrans and draw the paper's figures (Macias-Diaz & Puri).

Everything a figure shows comes from its file: the axes and curves from the datasets, every parameter
(Omega, N, T, the varied gamma / beta / m^2, ...) from the attributes of `/parameters` and `/curves`.

Scenes and what is drawn (README.md, "Output", has the layouts):

- `timeseries`: one file: u_n(t) at one probe site and the energy ledger; several files (Fig. 1): a grid of
  u_n(t), one row per potential, one column per driving amplitude;
- `amplitude_sweep`: total energy injected vs driving amplitude (Figs. 2, 3, 3-and-a-half, 4), one panel per
  potential, or, for one potential whose masses have both signs, 'Pure-imaginary masses' and 'Real masses';
- `map`: total energy over driving frequency x amplitude (Fig. 11), one panel per curve, A_s(Omega) over it;
- `bifurcation`: threshold amplitude vs driving frequency (Bif1-Bif3), A_s as x-marks.

Families are styled like the paper: the curves of a panel, ordered by the magnitude of the varied parameter,
are solid, dashed, dash-dotted and dotted.

A file that cannot be used raises `PlotError`; the command-line scripts print it as the one line
`error: <file>: <what is wrong>` and exit with status 2. Partial files (`<output>.partial.h5`, written while a
scene runs or left by a killed one) are drawn with the runs not done as gaps, and their titles say
`partial: k of n runs`.
"""
from __future__ import annotations

import logging
import math
import os
import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = ["PlotError", "Scene", "open_scene", "figure_name", "draw", "draw_timeseries", "draw_sweep",
           "draw_map", "draw_bifurcation", "summary", "output_path", "SCENES"]

#: Scenes the program writes.
SCENES = ("timeseries", "amplitude_sweep", "map", "bifurcation")

#: Figures of the paper, by the name of the input file that makes them (its stem, `input/<name>.nml`):
#: (label, scene, what the figure shows).
FIGURES = {
    "fig1": ("Fig. 1", "timeseries", "u_60(t) before and after the threshold"),
    "fig2": ("Fig. 2", "amplitude_sweep", "total energy vs driving amplitude, external damping gamma"),
    "fig3": ("Fig. 3", "amplitude_sweep", "total energy vs driving amplitude, mass m^2 (gamma = 0.01)"),
    "fig3half": ("Fig. 3-and-a-half", "amplitude_sweep", "total energy vs driving amplitude, internal damping beta"),
    "fig4": ("Fig. 4", "amplitude_sweep", "total energy vs driving amplitude, mass m^2 (beta = 0.2)"),
    "fig11": ("Fig. 11", "map", "total energy vs driving frequency and amplitude"),
    "bif1": ("Bif1", "bifurcation", "threshold vs driving frequency, external damping gamma"),
    "bif2": ("Bif2", "bifurcation", "threshold vs driving frequency, internal damping beta"),
    "bif3": ("Bif3", "bifurcation", "threshold vs driving frequency, mass m^2"),
}

#: Line styles of a family, in the paper's order.
LINESTYLES = ["-", "--", "-.", ":"]
#: Colours of a family (dark first), used with the line styles.
COLOURS = ["black", "tab:blue", "tab:red", "tab:green", "tab:purple", "tab:orange", "tab:brown", "tab:olive"]
#: Names of the potentials as the paper writes them.
POTENTIAL_TITLES = {"sine-gordon": "Sine-Gordon chain", "klein-gordon": "Klein-Gordon chain"}
#: Symbols of the parameters a family may vary.
SYMBOLS = {"gamma": r"\gamma", "beta": r"\beta", "m2": r"m^2"}
#: Figure size of one panel (inches) and the resolution of saved figures.
PANEL = (5.0, 3.6)
DPI = 96


class PlotError(Exception):
    """A file that cannot be drawn: its path and what is wrong with it, in one line."""

    def __init__(self, path, what):
        super().__init__(f"{path}: {what}")
        self.path = str(path)
        self.what = " ".join(str(what).split())

    def line(self):
        """The message the scripts print: `error: <file>: <what is wrong>`."""
        return f"error: {self.path}: {self.what}"


# ------------------------------------------------------------------------------------------------ reading


def _text(value):
    """An HDF5 string attribute or element (fixed-length bytes) as str."""
    if isinstance(value, (bytes, np.bytes_)):
        return value.decode("utf-8", "replace").strip().rstrip("\x00").strip()
    if isinstance(value, np.ndarray) and value.dtype.kind == "S":
        return [_text(v) for v in value.tolist()]
    return value


def _value(value):
    """An HDF5 attribute as a plain Python value (str, int, float, or a list for arrays)."""
    value = _text(value)
    if isinstance(value, np.ndarray):
        return value.tolist() if value.ndim > 0 else value.item()
    if isinstance(value, np.generic):
        return value.item()
    return value


@dataclass
class Scene:
    """What a figure needs from one file, read eagerly (the file is closed again)."""

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
    #: Attributes of groups read (`/run`, `/runs`, `/curves`, ...), by group path without the slash.
    groups: dict = field(default_factory=dict)
    #: Units of the datasets read (their attribute `units`).
    units: dict = field(default_factory=dict)

    @property
    def name(self):
        """Figure name: the stem of the input file that made the file (`input/fig2.nml` -> 'fig2')."""
        return figure_name(self)

    @property
    def partial(self):
        """Whether the file is a partial snapshot of a scene still running or killed (`complete` = 0)."""
        return int(self.attrs.get("complete", 1)) == 0

    def progress(self):
        """(runs done, runs in all, what a run is) of a grid scene; None for a timeseries."""
        if self.scene in ("amplitude_sweep", "map"):
            total = self.attrs.get("runs_total", self.data["runs/status"].size)
            done = self.attrs.get("runs_done", int(np.count_nonzero(self.data["runs/status"] != -1)))
            return int(done), int(total), "runs"
        if self.scene == "bifurcation":
            total = self.attrs.get("tasks_total", self.data["status"].size)
            done = self.attrs.get("tasks_done", int(np.count_nonzero(self.data["status"] != -1)))
            return int(done), int(total), "threshold searches"
        return None

    def partial_note(self):
        """'partial: k of n runs' for a partial file, '' otherwise."""
        if not self.partial:
            return ""
        done, total, what = self.progress()
        return f"partial: {done} of {total} {what}"

    def unit(self, name, default=""):
        """Units of a dataset read, as an axis label suffix: ' [rad]'; ' (scaled)' for the model's
        dimensionless time, energy and frequency ('time', 'energy', '1/time'); '' for pure numbers."""
        u = self.units.get(name, default)
        if not u or u == "1":
            return ""
        if u in ("time", "energy", "1/time", "1/time^2", "time^-1"):
            return " (scaled)"
        return f" [{u}]"


#: Datasets each scene must have (h5py paths) and the rank each must have.
REQUIRED = {
    "timeseries": {"probes/sites": 1, "probes/time": 1, "probes/u": 2, "ledger/time": 1, "ledger/stored": 1,
                   "ledger/injected": 1, "ledger/dissipated_gamma": 1, "ledger/dissipated_beta": 1,
                   "ledger/dissipated_absorber": 1},
    "amplitude_sweep": {"amplitude": 1, "curves/potential": 1, "curves/value": 1, "energy/injected": 2,
                        "runs/status": 2, "runs/transmitting": 2},
    "map": {"omega": 1, "amplitude": 1, "curves/potential": 1, "curves/value": 1, "threshold_As": 2,
            "energy/injected": 3, "runs/status": 3, "runs/transmitting": 3},
    "bifurcation": {"omega": 1, "curves/potential": 1, "curves/value": 1, "threshold": 2, "threshold_As": 2,
                    "status": 2},
}
#: Datasets read when present.
OPTIONAL = {
    "timeseries": {"ledger/residual": 1},
    "amplitude_sweep": {"curves/threshold_As": 1, "curves/m2": 1, "curves/band_gap_edge": 1,
                        **{f"energy/{k}": 2 for k in ("injected_after_ramp", "stored", "dissipated_gamma",
                                                     "dissipated_beta", "dissipated_absorber")}},
    "map": {"curves/m2": 1, "curves/band_gap_edge": 1,
            **{f"energy/{k}": 3 for k in ("injected_after_ramp", "stored", "dissipated_gamma", "dissipated_beta",
                                          "dissipated_absorber")}},
    "bifurcation": {"curves/m2": 1, "curves/band_gap_edge": 1, "cost/runs": 2, "cost/wall_time": 2},
}
#: Groups whose attributes are read when present.
GROUPS = {"timeseries": ("run",), "amplitude_sweep": ("runs", "curves"), "map": ("runs", "curves"),
          "bifurcation": ("curves", "status", "cost")}


def resolve(path):
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


def open_scene(path, expect=None):
    """Read the file `path` (or its partial snapshot, see `resolve`) for drawing.

    `expect`: a scene name or a tuple of them the caller can draw. Raises PlotError (one line) when the file
    is missing, not HDF5 or truncated, not a supratrans file, of another scene, or lacks a dataset.
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


def _read(f, p, expect):
    attrs = {k: _value(v) for k, v in f.attrs.items()}
    if "scene" not in attrs:
        code = attrs.get("code")
        raise PlotError(p, "no root attribute 'scene': not a supratrans output file"
                        + (f" (code '{code}')" if code else ""))
    scene = str(attrs["scene"])
    if scene not in SCENES:
        raise PlotError(p, f"unknown scene '{scene}' (this script draws {', '.join(SCENES)})")
    if expect is not None:
        wanted = (expect,) if isinstance(expect, str) else tuple(expect)
        if scene not in wanted:
            raise PlotError(p, f"scene is '{scene}', expected '{' or '.join(wanted)}'")
    if "parameters" not in f or not hasattr(f["parameters"], "keys"):
        raise PlotError(p, f"group '/parameters' missing (scene {scene})")
    params = {k: _value(v) for k, v in f["parameters"].attrs.items()}
    out = Scene(path=str(p), scene=scene, attrs=attrs, params=params)
    for name, rank in REQUIRED[scene].items():
        _read_dataset(f, p, scene, out, name, rank, required=True)
    for name, rank in OPTIONAL[scene].items():
        _read_dataset(f, p, scene, out, name, rank, required=False)
    for g in GROUPS[scene]:
        if g in f:
            out.groups[g] = {k: _value(v) for k, v in f[g].attrs.items()}
    _check_shapes(p, out)
    return out


def _read_dataset(f, p, scene, out, name, rank, required):
    import h5py  # noqa: PLC0415

    obj = f.get(name)
    if obj is None or not isinstance(obj, h5py.Dataset):
        if required:
            raise PlotError(p, f"dataset '/{name}' missing (scene {scene})")
        return
    data = obj[()]
    if data.dtype.kind == "S":
        data = np.array(_text(data) if data.ndim else [_text(data)], dtype=object)
    if np.ndim(data) != rank:
        raise PlotError(p, f"dataset '/{name}' has shape {np.shape(data)}, expected rank {rank}")
    out.data[name] = data
    if "units" in obj.attrs:
        out.units[name] = _text(obj.attrs["units"])


def _check_shapes(p, s):
    """The datasets of a scene agree on their dimensions."""
    d = s.data

    def need(name, shape):
        if name in d and tuple(d[name].shape) != tuple(shape):
            raise PlotError(p, f"dataset '/{name}' has shape {tuple(d[name].shape)}, expected {tuple(shape)}")

    if s.scene == "timeseries":
        nprobe, ntime = d["probes/sites"].size, d["probes/time"].size
        need("probes/u", (nprobe, ntime))
        for k in ("stored", "injected", "dissipated_gamma", "dissipated_beta", "dissipated_absorber", "residual"):
            need("ledger/" + k, d["ledger/time"].shape)
        return
    ncurve = d["curves/potential"].size
    need("curves/value", (ncurve,))
    for k in ("curves/threshold_As", "curves/m2", "curves/band_gap_edge"):
        need(k, (ncurve,))
    if s.scene == "amplitude_sweep":
        shape = (ncurve, d["amplitude"].size)
        for k in ("runs/status", "runs/transmitting") + tuple(e for e in d if e.startswith("energy/")):
            need(k, shape)
    elif s.scene == "map":
        shape = (ncurve, d["omega"].size, d["amplitude"].size)
        for k in ("runs/status", "runs/transmitting") + tuple(e for e in d if e.startswith("energy/")):
            need(k, shape)
        need("threshold_As", shape[:2])
    else:
        shape = (ncurve, d["omega"].size)
        for k in ("threshold", "threshold_As", "status", "cost/runs", "cost/wall_time"):
            need(k, shape)


def figure_name(scene):
    """Name of the figure a file belongs to: the stem of its input file (`input/fig3half.nml` -> 'fig3half'),
    'fig1' for the four Fig. 1 runs (`fig1_sg_A177` ...)."""
    stem = Path(str(scene.attrs.get("input_file", "") or Path(scene.path).name)).name
    stem = re.sub(r"(\.h5)?(\.partial\.h5)?$", "", stem)
    stem = re.sub(r"\.nml$", "", stem)
    if re.match(r"fig1_", stem):
        return "fig1"
    return stem


def open_h5(path):
    """Open an HDF5 file for reading; a missing, truncated or non-HDF5 file is a one-line PlotError."""
    import h5py  # noqa: PLC0415

    try:
        return h5py.File(path, "r")
    except OSError as exc:
        reason = str(exc).split("\n")[0]
        if "truncated" in reason:
            raise PlotError(path, f"truncated HDF5 file ({reason})") from None
        if "signature" in reason or "not an hdf5" in reason.lower():
            raise PlotError(path, "not an HDF5 file") from None
        raise PlotError(path, f"cannot open as HDF5 ({reason})") from None


def output_path(path, suffix=".png"):
    """Default image path for a data file: `out/fig2.h5` -> `out/fig2.png`, a partial snapshot
    `out/fig2.h5.partial.h5` -> `out/fig2.partial.png`."""
    p = Path(path)
    name = p.name
    if name.endswith(".h5.partial.h5"):
        name = name[: -len(".h5.partial.h5")] + ".partial"
    elif name.endswith(".h5"):
        name = name[:-3]
    return p.with_name(name + suffix)


# ------------------------------------------------------------------------------------------------ styles


def _pyplot():
    """matplotlib.pyplot with a file backend and without chatter on stderr."""
    logging.getLogger("matplotlib").setLevel(logging.ERROR)
    import matplotlib  # noqa: PLC0415

    if "MPLBACKEND" not in os.environ and not getattr(_pyplot, "interactive", False):
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # noqa: PLC0415

    plt.rcParams.update({"font.size": 9, "axes.titlesize": 9, "legend.fontsize": 8, "figure.titlesize": 10,
                         "axes.grid": True, "grid.alpha": 0.25, "lines.linewidth": 1.3,
                         "savefig.bbox": "tight", "figure.constrained_layout.use": True})
    return plt


def _fmt(x, digits=4):
    """A parameter as short text: 0.9, 1.8, 0.0025, 200."""
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "nan"
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    return f"{x:.{digits}g}"


def _potential_title(name):
    return POTENTIAL_TITLES.get(name, name)


def _family_label(vary, value, potential=None, show_potential=False):
    """Legend entry of a curve: '$\\gamma$ = 0.01', '$m^2$ = -0.0025 (|m| = 0.05)', ..."""
    if vary == "m2":
        m = math.sqrt(abs(value))
        text = rf"$m^2$ = {_fmt(value)}"
        if value != 0:
            text += rf" ($|m|$ = {_fmt(m, 3)})"
    elif vary in SYMBOLS:
        text = rf"${SYMBOLS[vary]}$ = {_fmt(value)}"
    else:
        text = _potential_title(potential) if potential else "run"
        show_potential = False
    if show_potential and potential:
        text = f"{_potential_title(potential).replace(' chain', '')}, {text}"
    return text


def _styles(values, vary, potentials):
    """Line style and colour of each curve of a panel: the style by the rank of |value| among the panel's
    distinct magnitudes (solid, dashed, dash-dotted, dotted, ...), the colour by rank too, or by the sign of
    m^2 when a mass family has both signs, or by the potential when several share the panel."""
    values = np.asarray(values, dtype=float)
    rank = _magnitude_ranks(values, vary)
    mags = sorted(set(rank))
    pots = list(dict.fromkeys(potentials))
    signs = vary == "m2" and (values < 0).any() and (values > 0).any()
    out = []
    for i, v in enumerate(values):
        style = LINESTYLES[rank[i] % len(LINESTYLES)]
        marker = None if rank[i] < len(LINESTYLES) else "os^v"[(rank[i] // len(LINESTYLES) - 1) % 4]
        if signs:
            if v == 0:
                colour = "black"
            else:
                shade = 0.45 + 0.55 * rank[i] / max(1, len(mags) - 1)
                colour = (_cmap("Blues")(shade) if v < 0 else _cmap("Reds")(shade))
        elif len(pots) > 1:
            colour = COLOURS[pots.index(potentials[i]) % len(COLOURS)]
        else:
            colour = COLOURS[rank[i] % len(COLOURS)]
        out.append({"linestyle": style, "color": colour, "marker": marker, "markersize": 3})
    return out


def _magnitude_ranks(values, vary):
    """Rank of each value's magnitude among the distinct magnitudes (0 for the smallest). For a mass family the
    magnitude is the shift |sqrt(1 + m^2) - 1| of the band edge, and magnitudes within 2 % are one (so that
    m^2 = -0.0025 and 0.0025, or sqrt(1 + m^2) = 1 -+ 1/40, share a line style)."""
    values = np.asarray(values, dtype=float)
    if vary == "m2":
        mag = np.abs(np.sqrt(np.maximum(1.0 + np.where(np.isfinite(values), values, 0.0), 0.0)) - 1.0)
    else:
        mag = np.abs(np.where(np.isfinite(values), values, 0.0))
    levels = []
    for m in sorted(mag):
        if not levels or m > levels[-1] * 1.02 + 1e-12:
            levels.append(m)
    return [max(k for k, lev in enumerate(levels) if m >= lev * (1 - 1e-9) - 1e-15) for m in mag]


def _cmap(name):
    import matplotlib  # noqa: PLC0415

    return matplotlib.colormaps[name]


def _conditions(s, skip=()):
    """The fixed parameters of a figure, read from `/parameters`: 'Omega = 0.9, N = 200, T = 200, ...'."""
    p = s.params
    vary = str(p.get("vary", "none"))
    items = []
    if s.scene != "map" and s.scene != "bifurcation" and "omega" not in skip:
        items.append(rf"$\Omega$ = {_fmt(p.get('omega'))}")
    for key in ("gamma", "beta", "m2"):
        if key != vary and key not in skip and key in p:
            items.append(rf"${SYMBOLS[key]}$ = {_fmt(p[key])}")
    items.append(rf"$c$ = {_fmt(p.get('c'))}")
    items.append(rf"$N$ = {_fmt(p.get('n'))}")
    items.append(rf"$T$ = {_fmt(p.get('t_final'))}")
    items.append(rf"$\Delta t$ = {_fmt(p.get('dt'))}")
    if "ramp_time" in p:
        items.append(f"ramp {_fmt(p['ramp_time'])}")
    return ", ".join(items)


def _title(s, what):
    """Figure title: the paper's label (from the input file name), what is shown, the partial note."""
    label = FIGURES.get(s.name, (s.name,))[0]
    title = f"{label}: {what}"
    note = s.partial_note()
    if note:
        title += f"  [{note}]"
    return title


def _failed_note(status):
    n = int(np.count_nonzero(np.asarray(status) > 0))
    return f"{n} run(s) failed (gaps)" if n else ""


# ------------------------------------------------------------------------------------------------ figures


def draw(scenes):
    """The figure of one file, or Fig. 1 of several timeseries files. Returns a matplotlib Figure."""
    if isinstance(scenes, Scene):
        scenes = [scenes]
    kinds = {s.scene for s in scenes}
    if len(scenes) > 1 and kinds != {"timeseries"}:
        bad = next(s for s in scenes if s.scene != "timeseries")
        raise PlotError(bad.path, f"scene is '{bad.scene}': only timeseries files are drawn together (Fig. 1)")
    s = scenes[0]
    if s.scene == "timeseries":
        return draw_timeseries(scenes)
    if s.scene == "amplitude_sweep":
        return draw_sweep(s)
    if s.scene == "map":
        return draw_map(s)
    return draw_bifurcation(s)


def _probe_index(s, site):
    sites = [int(x) for x in s.data["probes/sites"]]
    if not sites:
        raise PlotError(s.path, "no probe recorded (/probes/sites is empty)")
    if site is None:
        site = 60 if 60 in sites else sites[len(sites) // 2]
    if site not in sites:
        raise PlotError(s.path, f"site {site} was not recorded (probes: {', '.join(map(str, sites))})")
    return sites.index(site), site


def _run_note(s):
    run = s.groups.get("run", {})
    bits = []
    if "transmitting" in run:
        bits.append("transmits" if int(run["transmitting"]) else "does not transmit")
    if "energy_injected" in run and run["energy_injected"] is not None:
        bits.append(f"energy injected {_fmt(float(run['energy_injected']), 4)}")
    status = run.get("status")
    if status not in (None, "ok", 0):
        bits.append(f"status {status}")
    return ", ".join(bits)


def draw_timeseries(scenes, site=None):
    """One file: u_n(t) at the probe `site` (default 60) and the energy ledger. Several files (Fig. 1): a grid
    of u_n(t), one row per potential (file order), one column per driving amplitude (ascending)."""
    plt = _pyplot()
    if len(scenes) == 1:
        s = scenes[0]
        i, site = _probe_index(s, site)
        fig, (ax, bx) = plt.subplots(2, 1, figsize=(PANEL[0] * 1.3, PANEL[1] * 1.6), sharex=True)
        t = s.data["probes/time"]
        ax.plot(t, s.data["probes/u"][i], color="black", lw=0.8)
        ax.set_ylabel(rf"$u_{{{site}}}(t)${s.unit('probes/u')}")
        p = s.params
        ax.set_title(f"{_potential_title(p.get('potential'))}, $A$ = {_fmt(p.get('amplitude'))}, "
                     + _conditions(s) + (f"\n{_run_note(s)}" if _run_note(s) else ""))
        lt = s.data["ledger/time"]
        for key, label, style in (("injected", "injected", "-"), ("stored", "stored $E$", "--"),
                                  ("dissipated_absorber", "absorbed (end)", "-."),
                                  ("dissipated_gamma", r"dissipated by $\gamma$", ":"),
                                  ("dissipated_beta", r"dissipated by $\beta$", (0, (1, 3)))):
            y = s.data["ledger/" + key]
            if key.startswith("dissipated_") and key != "dissipated_absorber" and not np.any(y):
                continue
            bx.plot(lt, y, linestyle=style, label=label, color="black" if key == "injected" else None)
        bx.set_xlabel(f"time $t${s.unit('probes/time')}")
        bx.set_ylabel(f"energy{s.unit('ledger/injected')}")
        bx.legend(loc="upper left")
        fig.suptitle(_title(s, rf"$u_{{{site}}}(t)$ and the energy ledger"))
        return fig

    potentials = sorted(dict.fromkeys(str(s.params.get("potential")) for s in scenes),
                        key=lambda q: (list(POTENTIAL_TITLES).index(q) if q in POTENTIAL_TITLES else 9, q))
    amplitudes = sorted({float(s.params.get("amplitude")) for s in scenes})
    nr, nc = len(potentials), len(amplitudes)
    fig, axes = plt.subplots(nr, nc, figsize=(PANEL[0] * nc * 0.85, PANEL[1] * nr * 0.8), squeeze=False,
                             sharex=True)
    seen = set()
    for s in scenes:
        r = potentials.index(str(s.params.get("potential")))
        c = amplitudes.index(float(s.params.get("amplitude")))
        if (r, c) in seen:
            raise PlotError(s.path, f"two files for the same panel ({s.params.get('potential')}, "
                                    f"A = {_fmt(s.params.get('amplitude'))})")
        seen.add((r, c))
        i, st = _probe_index(s, site)
        ax = axes[r, c]
        ax.plot(s.data["probes/time"], s.data["probes/u"][i], color="black", lw=0.7)
        letter = "abcdefgh"[c] if c < 8 else str(c + 1)
        note = _run_note(s)
        ax.set_title(f"({letter}) $A$ = {_fmt(s.params.get('amplitude'))}   "
                     f"{_potential_title(s.params.get('potential'))}" + (f"\n{note}" if note else ""))
        ax.set_ylabel(rf"$u_{{{st}}}(t)${s.unit('probes/u')}")
        if r == nr - 1:
            ax.set_xlabel(f"time $t${s.unit('probes/time')}")
    for r in range(nr):
        for c in range(nc):
            if (r, c) not in seen:
                axes[r, c].set_visible(False)
    s0 = scenes[0]
    fig.suptitle(f"{FIGURES['fig1'][0] if s0.name == 'fig1' else s0.name}: displacement at one site, "
                 "before (a) and after (b) the threshold\n" + _conditions(s0))
    return fig


def _sweep_panels(s):
    """Panels of a sweep: (title, curve indices). One per potential; for a single potential whose m^2 family
    has both signs, 'Pure-imaginary masses' (m^2 <= 0) and 'Real masses' (m^2 >= 0), m^2 = 0 in both."""
    pots = [str(x) for x in s.data["curves/potential"]]
    values = np.asarray(s.data["curves/value"], dtype=float)
    vary = str(s.groups.get("curves", {}).get("vary", s.params.get("vary", "none")))
    distinct = list(dict.fromkeys(pots))
    if vary == "m2" and len(distinct) == 1 and (values < 0).any() and (values > 0).any():
        title = _potential_title(distinct[0])
        return [(f"Pure-imaginary masses ({title})", [i for i, v in enumerate(values) if v <= 0]),
                (f"Real masses ({title})", [i for i, v in enumerate(values) if v >= 0])], vary
    return [(_potential_title(p), [i for i, q in enumerate(pots) if q == p]) for p in distinct], vary


def _massless(s, idx):
    """The curves among `idx` whose A_s is drawn: A_s = 4 arctan(lambda c / Omega) is the massless theory, so
    only the curves with m^2 = 0 when there are any (Figs. 3, 4, Bif3), else all of them."""
    m2 = s.data.get("curves/m2")
    if m2 is None:
        vary = str(s.groups.get("curves", {}).get("vary", s.params.get("vary", "none")))
        m2 = s.data["curves/value"] if vary == "m2" else np.full(len(s.data["curves/value"]),
                                                                 float(s.params.get("m2", 0.0)))
    zero = [i for i in idx if m2[i] == 0]
    return zero or list(idx)


def _first_transmitting(amplitudes, transmitting, status):
    """Smallest amplitude of a curve whose run transmits (status ok), NaN when none does."""
    ok = (np.asarray(status) == 0) & (np.asarray(transmitting) == 1)
    return float(amplitudes[np.argmax(ok)]) if ok.any() else float("nan")


#: The energies of a sweep or map (datasets /energy/<name>) and how an axis names them.
ENERGIES = {
    "injected": "total energy injected $E$",
    "injected_after_ramp": "energy injected after the ramp",
    "stored": "energy stored at $T$",
    "dissipated_gamma": r"energy dissipated by $\gamma$",
    "dissipated_beta": r"energy dissipated by $\beta$",
    "dissipated_absorber": "energy absorbed at the end",
}


def _energy(s, which):
    """The dataset /energy/<which> of a sweep or map (PlotError when the file lacks it) and its axis label."""
    if which not in ENERGIES:
        raise PlotError(s.path, f"unknown energy '{which}' (one of {', '.join(ENERGIES)})")
    name = f"energy/{which}"
    if name not in s.data:
        raise PlotError(s.path, f"dataset '/{name}' missing (scene {s.scene})")
    return np.asarray(s.data[name], dtype=float), ENERGIES[which] + s.unit(name)


def _zoom_window(amp, first):
    """Amplitude window around the jumps (first transmitting amplitudes) of a sweep, or None when the jumps
    already fill the plot (spread over more than 40 % of the amplitude range) or there are none."""
    first = np.asarray([a for a in first if math.isfinite(a)])
    if first.size == 0 or amp.size < 8:
        return None
    span = float(amp.max() - amp.min())
    step = float(np.min(np.diff(amp)))
    lo, hi = first.min() - max(4 * step, 0.03 * span), first.max() + max(4 * step, 0.03 * span)
    lo, hi = max(lo, float(amp.min())), min(hi, float(amp.max()))
    return (lo, hi) if hi - lo < 0.4 * span else None


def draw_sweep(s, zoom=True, energy="injected"):
    """Total energy injected vs driving amplitude (Figs. 2, 3, 3-and-a-half, 4), one column per panel; when the
    jumps of the curves lie in a narrow window (and `zoom`), a second row shows that window, every run as a dot.
    `energy`: another energy of the file instead (ENERGIES: 'stored', 'dissipated_gamma', ...)."""
    plt = _pyplot()
    panels, vary = _sweep_panels(s)
    amp = np.asarray(s.data["amplitude"], dtype=float)
    which = energy
    energy, ylabel = _energy(s, which)
    status = s.data["runs/status"]
    trans = s.data["runs/transmitting"]
    values = np.asarray(s.data["curves/value"], dtype=float)
    pots = [str(x) for x in s.data["curves/potential"]]
    a_s = s.data.get("curves/threshold_As")
    first = [_first_transmitting(amp, trans[i], status[i]) for i in range(len(pots))]
    window = _zoom_window(amp, first) if zoom else None
    rows = 2 if window else 1
    fig, axes = plt.subplots(rows, len(panels), figsize=(PANEL[0] * len(panels), PANEL[1] * (1 + 0.85 * (rows - 1))),
                             squeeze=False, height_ratios=[1, 0.85][:rows])
    for col, (title, idx) in enumerate(panels):
        order = sorted(idx, key=lambda i: (abs(values[i]) if math.isfinite(values[i]) else 0, values[i]))
        styles = _styles(values[order], vary, [pots[i] for i in order])
        for row in range(rows):
            ax = axes[row, col]
            for i, st in zip(order, styles):
                y = np.where(status[i] == 0, energy[i], np.nan)
                if row == 0:
                    ax.plot(amp, y, label=_family_label(vary, values[i], pots[i]), **st)
                else:
                    ax.plot(amp, y, **{**st, "marker": "o", "markersize": 2.5})
            if a_s is not None:  # x-marks on the axis, one per distinct A_s, in the colour of its curve
                marks = {}
                keep = _massless(s, idx)
                for i, st in zip(order, styles):
                    if i in keep and math.isfinite(a_s[i]):
                        marks.setdefault(round(float(a_s[i]), 6), st["color"])
                for a, colour in sorted(marks.items()):
                    one = len(marks) == 1
                    ax.plot([a], [0], marker="x", color="black" if one else colour, ms=7, mew=1.5, ls="none",
                            clip_on=False, zorder=5, transform=ax.get_xaxis_transform(),
                            label=(rf"$A_s$ = {a:.3f}" + (" ($m^2$ = 0)" if vary == "m2" else ""))
                            if one and row == 0 else None)
                if len(marks) > 1 and row == 0:
                    ax.plot([], [], "x", color="0.4", ms=7, mew=1.5, label=r"$A_s$ of each curve (its colour)")
            ax.set_ylabel(ylabel)
            if row == rows - 1:
                ax.set_xlabel(f"driving amplitude $A${s.unit('amplitude')}")
            if row == 0:
                ax.set_title(title)
                if amp.size > 1:
                    ax.set_xlim(amp.min(), amp.max())
                ax.legend(loc="upper left", frameon=False)
                note = _failed_note(status[idx])
                if note:
                    ax.text(0.99, 0.02, note, transform=ax.transAxes, ha="right", va="bottom", fontsize=7,
                            color="tab:red")
                if not (status[idx] == 0).any():
                    ax.text(0.5, 0.5, "no run done yet" if s.partial else "no run completed",
                            transform=ax.transAxes, ha="center", va="center", color="0.4")
                if window:
                    ax.axvspan(*window, color="0.9", zorder=0)
            else:
                ax.set_xlim(*window)
                inside = (amp >= window[0]) & (amp <= window[1])
                ys = np.where(status[idx] == 0, energy[idx], np.nan)[:, inside]
                top = np.nanmax(ys) if np.isfinite(ys).any() else 1.0
                ax.set_ylim(0, 1.08 * top)
                ax.set_title(f"zoom on the jump, A = {window[0]:.3g} .. {window[1]:.3g} (one dot per run)",
                             fontsize=8)
            ax.set_ylim(bottom=0)
    sym = SYMBOLS.get(vary)
    what = ENERGIES[which].replace(" $E$", "") + " vs driving amplitude" + (rf", family in ${sym}$" if sym else "")
    fig.suptitle(_title(s, what) + "\n" + _conditions(s))
    return fig


def draw_map(s, surface=False, energy="injected"):
    """Total energy over driving frequency x amplitude (Fig. 11), one panel per curve, log colour scale, with the
    continuum-limit threshold A_s(Omega) (x-marks and line) and the first transmitting amplitude of each
    frequency (white dots) drawn over it. Runs outside the band gap or not done are gaps (grey)."""
    plt = _pyplot()
    from matplotlib.colors import LogNorm  # noqa: PLC0415

    omega = np.asarray(s.data["omega"], dtype=float)
    amp = np.asarray(s.data["amplitude"], dtype=float)
    which = energy
    energy, elabel = _energy(s, which)
    status = s.data["runs/status"]
    trans = s.data["runs/transmitting"]
    a_s = np.asarray(s.data["threshold_As"], dtype=float)
    pots = [str(x) for x in s.data["curves/potential"]]
    values = np.asarray(s.data["curves/value"], dtype=float)
    vary = str(s.groups.get("curves", {}).get("vary", s.params.get("vary", "none")))
    ncurve = len(pots)
    good = energy[(status == 0) & np.isfinite(energy) & (energy > 0)]
    vmin, vmax = (float(good.min()), float(good.max())) if good.size else (1.0, 10.0)
    if vmax <= vmin:
        vmax = vmin * 10
    norm = LogNorm(vmin=vmin, vmax=vmax)
    kw = {"subplot_kw": {"projection": "3d"}} if surface else {}
    fig, axes = plt.subplots(1, ncurve, figsize=(PANEL[0] * ncurve, PANEL[1] * 1.15), squeeze=False, **kw)
    mesh = None
    for c, ax in enumerate(axes[0]):
        e = np.where(status[c] == 0, energy[c], np.nan).T  # (namp, nomega)
        title = _potential_title(pots[c])
        if vary in SYMBOLS and math.isfinite(values[c]):
            title += f", {_family_label(vary, values[c])}"
        if surface:
            W, A = np.meshgrid(omega, amp)
            ax.plot_surface(W, A, np.log10(np.where(e > 0, e, np.nan)), cmap="viridis", norm=None,
                            linewidth=0, antialiased=False)
            inside = np.isfinite(a_s[c]) & (a_s[c] >= amp.min()) & (a_s[c] <= amp.max())
            ax.plot(omega[inside], a_s[c][inside], np.full(int(inside.sum()), np.log10(vmin)), "rx",
                    label=r"$A_s(\Omega)$")
            ax.set_zlabel(r"$\log_{10} E$")
        else:
            ax.set_facecolor("0.85")
            mesh = ax.pcolormesh(omega, amp, np.ma.masked_invalid(np.where(e > 0, e, np.nan)), norm=norm,
                                 cmap="viridis", shading="nearest")
            ok = np.isfinite(a_s[c])
            ax.plot(omega[ok], a_s[c][ok], color="white", lw=1.0, ls="-", zorder=3)
            ax.plot(omega[ok], a_s[c][ok], "x", color="red", ms=5, mew=1.3, zorder=4,
                    label=r"$A_s(\Omega) = 4\arctan(\lambda c/\Omega)$")
            first = np.array([_first_transmitting(amp, trans[c, w], status[c, w]) for w in range(omega.size)])
            okf = np.isfinite(first)
            if okf.any():
                ax.plot(omega[okf], first[okf], "o", mfc="white", mec="black", ms=3.5, zorder=4,
                        label="first transmitting run")
            ax.set_xlim(omega.min() - _half(omega), omega.max() + _half(omega))
            ax.set_ylim(amp.min() - _half(amp), amp.max() + _half(amp))
            ax.legend(loc="lower left", fontsize=7, framealpha=0.85)
        ax.set_title(title)
        ax.set_xlabel(rf"driving frequency $\Omega${s.unit('omega')}")
        ax.set_ylabel(f"driving amplitude $A${s.unit('amplitude')}")
        note = _failed_note(status[c])
        if note:
            ax.text2D(0.01, 0.01, note, transform=ax.transAxes) if surface else ax.text(
                0.01, 0.01, note, transform=ax.transAxes, fontsize=7, color="tab:red")
    if mesh is not None:
        cb = fig.colorbar(mesh, ax=list(axes[0]), shrink=0.9, pad=0.02)
        cb.set_label(elabel)
    what = ENERGIES[which].replace(" $E$", "").replace("total energy injected", "total energy")
    fig.suptitle(_title(s, f"{what} vs driving frequency and amplitude (grey: not run)") + "\n"
                 + _conditions(s))
    return fig


def _half(axis):
    return 0.5 * float(np.min(np.diff(axis))) if axis.size > 1 else 0.5


def draw_bifurcation(s):
    """Threshold amplitude vs driving frequency (Bif1-Bif3), one curve per (potential, value), A_s as x-marks."""
    plt = _pyplot()
    omega = np.asarray(s.data["omega"], dtype=float)
    thr = np.asarray(s.data["threshold"], dtype=float)
    a_s = np.asarray(s.data["threshold_As"], dtype=float)
    status = s.data["status"]
    pots = [str(x) for x in s.data["curves/potential"]]
    values = np.asarray(s.data["curves/value"], dtype=float)
    vary = str(s.groups.get("curves", {}).get("vary", s.params.get("vary", "none")))
    several = len(set(pots)) > 1
    order = sorted(range(len(pots)), key=lambda i: (pots.index(pots[i]), values[i] if math.isfinite(values[i])
                                                    else 0))
    styles = _styles(values[order], vary, [pots[i] for i in order])
    fig, ax = plt.subplots(figsize=(PANEL[0] * 1.35, PANEL[1] * 1.3))
    if not np.isin(status, (0, 1)).any():
        ax.text(0.5, 0.5, "no threshold found yet" if s.partial else "no threshold found", transform=ax.transAxes,
                ha="center", va="center", color="0.4")
    for i, st in zip(order, styles):
        y = np.where(np.isin(status[i], (0, 1)), thr[i], np.nan)
        if vary == "m2":
            edge = math.sqrt(1.0 + values[i])
            ell = 40.0 * (edge - 1.0)
            label = rf"$\sqrt{{m^2+1}}$ = {edge:.4g}"
            if abs(ell - round(ell)) < 1e-6:
                label += rf" ($\ell$ = {int(round(ell))})"
            if several:
                label = f"{_potential_title(pots[i]).replace(' chain', '')}, {label}"
        else:
            label = _family_label(vary, values[i], pots[i], several)
        line, = ax.plot(omega, y, label=label, **st)
        single = np.isfinite(y) & ~np.isfinite(np.roll(y, 1)) & ~np.isfinite(np.roll(y, -1))
        if single.any():  # points without a neighbour would not show as a line
            ax.plot(omega[single], y[single], ".", color=line.get_color())
    # A_s: one set of x-marks per distinct A_s(Omega) curve (it does not depend on gamma or beta).
    rows = []
    keep = _massless(s, order)
    for i in order:
        if i not in keep:
            continue
        row = a_s[i]
        if np.isfinite(row).any() and not any(np.allclose(row, r, equal_nan=True) for r, _ in rows):
            rows.append((row, i))
    for k, (row, i) in enumerate(rows):
        one = len(rows) == 1
        massless = " ($m^2$ = 0)" if vary == "m2" else ""
        ax.plot(omega, row, "x", color="black" if one else styles[order.index(i)]["color"], ms=5 if one else 4,
                mew=1.0, label=r"$A_s = 4\arctan(\lambda c/\Omega)$" + massless if one else None)
    if len(rows) > 1:
        ax.plot([], [], "x", color="0.4", ms=5, mew=1.0, label=r"$A_s = 4\arctan(\lambda c/\Omega)$ of each curve")
    lower = np.count_nonzero(status == 1)
    none = np.count_nonzero(status == 2)
    failed = np.count_nonzero(status == 3)
    notes = []
    if lower:
        notes.append(f"{lower} point(s) at the lower bound A = {_fmt(s.params.get('amplitude_min'))}")
    if none:
        notes.append(f"{none} with no transmission up to A = {_fmt(s.params.get('amplitude_max'))} (gaps)")
    if failed:
        notes.append(f"{failed} search(es) failed (gaps)")
    if notes:
        ax.text(0.99, 0.01, "; ".join(notes), transform=ax.transAxes, ha="right", va="bottom", fontsize=7,
                color="0.3")
    ax.set_xlabel(rf"driving frequency $\Omega${s.unit('omega')}")
    ax.set_ylabel(f"threshold amplitude $A${s.unit('threshold')}")
    ax.legend(loc="best", ncol=2 if len(order) > 4 else 1, framealpha=0.85)
    sym = SYMBOLS.get(vary)
    what = "smallest transmitting amplitude vs driving frequency" + (rf", family in ${sym}$" if sym else "")
    res = s.params.get("resolution")
    cond = _conditions(s) + (f", resolution {_fmt(res)}" if res is not None else "")
    fig.suptitle(_title(s, what) + "\n" + cond)
    return fig


# ------------------------------------------------------------------------------------------------ numbers


def summary(s, full=False):
    """Lines of text with the numbers a figure shows (printed by the scripts, quoted in README.md); `full`: every
    frequency of a map or bifurcation, not about seven of them."""
    lines = []
    if s.scene == "timeseries":
        run = s.groups.get("run", {})
        i, site = _probe_index(s, None)
        lines.append(f"{s.path}: {s.params.get('potential')}, A = {_fmt(s.params.get('amplitude'))}, "
                     f"Omega = {_fmt(s.params.get('omega'))}: {_run_note(s) or 'no outcome recorded'}, "
                     f"max |u_{site}| = {_fmt(float(np.max(np.abs(s.data['probes/u'][i]))), 3)}"
                     + (f", max |u| over the chain = {_fmt(float(run['max_abs_u']), 3)}" if "max_abs_u" in run
                        else ""))
        return lines
    pots = [str(x) for x in s.data["curves/potential"]]
    values = np.asarray(s.data["curves/value"], dtype=float)
    vary = str(s.groups.get("curves", {}).get("vary", s.params.get("vary", "none")))
    head = f"{s.path}" + (f" ({s.partial_note()})" if s.partial else "")
    lines.append(head)
    if s.scene == "amplitude_sweep":
        amp = np.asarray(s.data["amplitude"], dtype=float)
        e = np.asarray(s.data["energy/injected"], dtype=float)
        st, tr = s.data["runs/status"], s.data["runs/transmitting"]
        for c in range(len(pots)):
            a = _first_transmitting(amp, tr[c], st[c])
            text = f"  {_curve_name(pots[c], vary, values[c])}: "
            if math.isfinite(a):
                k = int(np.argmax(amp == a))
                before = e[c, k - 1] if k > 0 else float("nan")
                text += (f"transmits from A = {a:.4g} (E = {_fmt(before, 4)} at A = {_fmt(amp[k - 1]) if k else '-'}"
                         f" -> {_fmt(e[c, k], 4)})")
            else:
                text += "no run transmits"
            if np.isfinite(e[c]).any():
                text += f", E up to {_fmt(np.nanmax(e[c]), 4)}"
            lines.append(text)
    elif s.scene == "map":
        omega, amp = np.asarray(s.data["omega"]), np.asarray(s.data["amplitude"])
        st, tr = s.data["runs/status"], s.data["runs/transmitting"]
        for c in range(len(pots)):
            first = np.array([_first_transmitting(amp, tr[c, w], st[c, w]) for w in range(omega.size)])
            ok = np.isfinite(first)
            text = f"  {pots[c]}: "
            if ok.any():
                text += f"some run transmits for Omega >= {_fmt(omega[ok].min(), 3)}; "
            else:
                text += "no run transmits; "
            cols = _columns(omega, full)
            text += "Omega: first transmitting A / A_s = " + ", ".join(
                f"{_fmt(omega[w], 3)}: {_fmt(first[w], 3)}/{_fmt(s.data['threshold_As'][c, w], 3)}" for w in cols)
            lines.append(text)
    else:
        omega = np.asarray(s.data["omega"])
        thr, status = s.data["threshold"], s.data["status"]
        cols = _columns(omega, full)
        for c in range(len(pots)):
            found = np.isin(status[c], (0, 1))
            name = _curve_name(pots[c], vary, values[c])
            text = (f"  {name}: {int(found.sum())} of {omega.size} thresholds found"
                    f" (Omega {_fmt(omega[found].min(), 3)}..{_fmt(omega[found].max(), 3)})" if found.any() else
                    f"  {name}: no threshold found")
            text += "; Omega: A = " + ", ".join(f"{_fmt(omega[w], 3)}: {_fmt(thr[c, w], 3)}" for w in cols)
            lines.append(text)
        for c in _massless(s, range(len(pots)))[:1]:
            lines.append("  A_s" + (f" (m2 = 0)" if vary == "m2" else "") + ": " + ", ".join(
                f"{_fmt(omega[w], 3)}: {_fmt(s.data['threshold_As'][c, w], 3)}" for w in cols))
    return lines


def _curve_name(potential, vary, value):
    """A curve in plain text: 'sine-gordon, gamma = 0.01', or the potential alone when nothing varies."""
    return f"{potential}, {vary} = {_fmt(value)}" if vary in SYMBOLS else str(potential)


def _columns(axis, full):
    """Indices of the axis points a summary shows: all of them, or the points nearest to round values (multiples
    of 0.1, 0.2, ... chosen to give at most eight) over the axis."""
    axis = np.asarray(axis, dtype=float)
    n = axis.size
    if full or n <= 8:
        return list(range(n))
    lo, hi = float(axis.min()), float(axis.max())
    for nice in (0.01, 0.02, 0.05, 0.1, 0.2, 0.25, 0.5, 1.0, 2.0, 5.0, 10.0):
        if (hi - lo) / nice <= 7:
            break
    targets = np.arange(math.ceil(lo / nice - 1e-9), math.floor(hi / nice + 1e-9) + 1) * nice
    return sorted({int(np.argmin(np.abs(axis - t))) for t in targets})


#: PNGs larger than this are stored with a 256-colour palette (line plots: a third of the size, no visible change).
PNG_BUDGET = 120_000


def save(fig, path, dpi=DPI):
    """Write a figure, creating the folder; returns the path. A PNG above PNG_BUDGET bytes is stored with a
    256-colour palette."""
    import io  # noqa: PLC0415

    import matplotlib.pyplot as plt  # noqa: PLC0415

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if path.suffix.lower() != ".png":
            fig.savefig(path, dpi=dpi)
        else:
            buf = io.BytesIO()
            fig.savefig(buf, dpi=dpi, format="png")
            data = buf.getvalue()
            if len(data) > PNG_BUDGET:
                try:
                    from PIL import Image  # noqa: PLC0415 (a dependency of matplotlib)

                    with Image.open(io.BytesIO(data)) as im:
                        out = io.BytesIO()
                        im.convert("RGB").quantize(colors=256, method=Image.Quantize.FASTOCTREE).save(
                            out, format="PNG", optimize=True)
                    data = out.getvalue()
                except ImportError:
                    pass
            path.write_bytes(data)
    plt.close(fig)
    return path
