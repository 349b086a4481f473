"""What the figures of the paper share: their labels, the styles of a family of curves, the fixed parameters of a
title, and the few facts read from the curves of a grid scene (first transmitting amplitude, massless curves,
energies)."""
from __future__ import annotations

import math
from typing import Any, Iterable

import numpy as np

from ..reader import PlotError, Scene
from ..style import cmap, fmt

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
POTENTIAL_TITLES = {"sine-gordon": "Sine-Gordon chain", "klein-gordon": "Klein-Gordon chain",
                    "double-sine-gordon": "Double sine-Gordon chain"}
#: Symbols of the parameters a family may vary.
SYMBOLS = {"gamma": r"\gamma", "beta": r"\beta", "m2": r"m^2"}
#: Figure size of one panel (inches).
PANEL = (5.0, 3.6)

#: The energies of a sweep or map (datasets /energy/<name>) and how an axis names them.
ENERGIES = {
    "injected": "total energy injected $E$",
    "injected_after_ramp": "energy injected after the ramp",
    "stored": "energy stored at $T$",
    "dissipated_gamma": r"energy dissipated by $\gamma$",
    "dissipated_beta": r"energy dissipated by $\beta$",
    "dissipated_absorber": "energy absorbed at the end",
}


# ------------------------------------------------------------------------------------------------ labels


def potential_title(name: Any) -> str:
    """'Sine-Gordon chain' for 'sine-gordon'; other names as they are."""
    return POTENTIAL_TITLES.get(name, name)


def vary_of(s: Scene) -> str:
    """The parameter the curves of a grid scene vary ('gamma', 'beta', 'm2' or 'none')."""
    return str(s.groups.get("curves", {}).get("vary", s.params.get("vary", "none")))


def family_label(vary: str, value: float, potential: str | None = None, show_potential: bool = False) -> str:
    """Legend entry of a curve: '$\\gamma$ = 0.01', '$m^2$ = -0.0025 (|m| = 0.05)', ..."""
    if vary == "m2":
        m = math.sqrt(abs(value))
        label = rf"$m^2$ = {fmt(value)}"
        if value != 0:
            label += rf" ($|m|$ = {fmt(m, 3)})"
    elif vary in SYMBOLS:
        label = rf"${SYMBOLS[vary]}$ = {fmt(value)}"
    else:
        label = potential_title(potential) if potential else "run"
        show_potential = False
    if show_potential and potential:
        label = f"{potential_title(potential).replace(' chain', '')}, {label}"
    return label


def curve_name(potential: str, vary: str, value: float) -> str:
    """A curve in plain text: 'sine-gordon, gamma = 0.01', or the potential alone when nothing varies."""
    return f"{potential}, {vary} = {fmt(value)}" if vary in SYMBOLS else str(potential)


def conditions(s: Scene, skip: Iterable[str] = ()) -> str:
    """The fixed parameters of a figure, read from `/parameters`: 'Omega = 0.9, N = 200, T = 200, ...'."""
    p = s.params
    vary = str(p.get("vary", "none"))
    items = []
    if s.scene not in ("map", "bifurcation", "continuation", "hysteresis") and "omega" not in skip:
        items.append(rf"$\Omega$ = {fmt(p.get('omega'))}")
    for key in ("gamma", "beta", "m2"):
        if key != vary and key not in skip and key in p:
            items.append(rf"${SYMBOLS[key]}$ = {fmt(p[key])}")
    items.append(rf"$c$ = {fmt(p.get('c'))}")
    items.append(rf"$N$ = {fmt(p.get('n'))}")
    if s.scene == "continuation":  # periodic states: no final time, no ramp; the method and its step
        items.append(f"{p.get('method', 'newton')}, " + rf"$\Delta t$ = {fmt(p.get('dt'))}")
        return ", ".join(items)
    if s.scene == "hysteresis":  # the run's T follows from the stairs
        items.append(f"{p.get('method', 'newton')}, " + rf"$\Delta t$ = {fmt(p.get('dt'))}")
        items.append(f"stairs of {fmt(p.get('stair_height'))}, ramps {fmt(p.get('stair_ramp'))}")
        return ", ".join(items)
    items.append(rf"$T$ = {fmt(p.get('t_final'))}")
    items.append(rf"$\Delta t$ = {fmt(p.get('dt'))}")
    if "ramp_time" in p:
        items.append(f"ramp {fmt(p['ramp_time'])}")
    return ", ".join(items)


def title(s: Scene, what: str) -> str:
    """Figure title: the paper's label (from the input file name), what is shown, the partial note."""
    label = FIGURES.get(s.name, (s.name,))[0]
    out = f"{label}: {what}"
    note = s.partial_note()
    if note:
        out += f"  [{note}]"
    return out


def failed_note(status: Any) -> str:
    """'k run(s) failed (gaps)' when some runs of `status` failed, '' otherwise."""
    n = int(np.count_nonzero(np.asarray(status) > 0))
    return f"{n} run(s) failed (gaps)" if n else ""


# ------------------------------------------------------------------------------------------------ styles


def styles(values: Any, vary: str, potentials: list[str]) -> list[dict]:
    """Line style and colour of each curve of a panel: the style by the rank of |value| among the panel's
    distinct magnitudes (solid, dashed, dash-dotted, dotted, ...), the colour by rank too, or by the sign of
    m^2 when a mass family has both signs, or by the potential when several share the panel."""
    values = np.asarray(values, dtype=float)
    rank = magnitude_ranks(values, vary)
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
                colour = (cmap("Blues")(shade) if v < 0 else cmap("Reds")(shade))
        elif len(pots) > 1:
            colour = COLOURS[pots.index(potentials[i]) % len(COLOURS)]
        else:
            colour = COLOURS[rank[i] % len(COLOURS)]
        out.append({"linestyle": style, "color": colour, "marker": marker, "markersize": 3})
    return out


def magnitude_ranks(values: Any, vary: str) -> list[int]:
    """Rank of each value's magnitude among the distinct magnitudes (0 for the smallest). For a mass family the
    magnitude is the shift |sqrt(1 + m^2) - 1| of the band edge, and magnitudes within 2 % are one (so that
    m^2 = -0.0025 and 0.0025, or sqrt(1 + m^2) = 1 -+ 1/40, share a line style)."""
    values = np.asarray(values, dtype=float)
    if vary == "m2":
        mag = np.abs(np.sqrt(np.maximum(1.0 + np.where(np.isfinite(values), values, 0.0), 0.0)) - 1.0)
    else:
        mag = np.abs(np.where(np.isfinite(values), values, 0.0))
    levels: list[float] = []
    for m in sorted(mag):
        if not levels or m > levels[-1] * 1.02 + 1e-12:
            levels.append(m)
    return [max(k for k, lev in enumerate(levels) if m >= lev * (1 - 1e-9) - 1e-15) for m in mag]


# ------------------------------------------------------------------------------------------------ curves


def massless(s: Scene, idx: Iterable[int]) -> list[int]:
    """The curves among `idx` whose A_s is drawn: A_s = 4 arctan(lambda c / Omega) is the massless theory, so
    only the curves with m^2 = 0 when there are any (Figs. 3, 4, Bif3), else all of them."""
    idx = list(idx)
    m2 = s.data.get("curves/m2")
    if m2 is None:
        m2 = s.data["curves/value"] if vary_of(s) == "m2" else np.full(len(s.data["curves/value"]),
                                                                       float(s.params.get("m2", 0.0)))
    zero = [i for i in idx if m2[i] == 0]
    return zero or idx


def first_transmitting(amplitudes: Any, transmitting: Any, status: Any) -> float:
    """Smallest amplitude of a curve whose run transmits (status ok), NaN when none does."""
    ok = (np.asarray(status) == 0) & (np.asarray(transmitting) == 1)
    return float(amplitudes[np.argmax(ok)]) if ok.any() else float("nan")


def energy(s: Scene, which: str) -> tuple[np.ndarray, str]:
    """The dataset /energy/<which> of a sweep or map (PlotError when the file lacks it) and its axis label."""
    if which not in ENERGIES:
        raise PlotError(s.path, f"unknown energy '{which}' (one of {', '.join(ENERGIES)})")
    name = f"energy/{which}"
    if name not in s.data:
        raise PlotError(s.path, f"dataset '/{name}' missing (scene {s.scene})")
    return np.asarray(s.data[name], dtype=float), ENERGIES[which] + s.unit(name)


def columns(axis: Any, full: bool) -> list[int]:
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


def localized_folds(fold, curve: int) -> np.ndarray:
    """Where the chain, driven just past the fold of `curve`, stays localized (/fold_fate 2): a fold that is not the
    supratransmission threshold (all False for files without /fold_fate)."""
    omega = np.asarray(fold.data["omega"], dtype=float)
    fate = fold.data.get("fold_fate")
    if fate is None:
        return np.zeros(omega.shape, dtype=bool)
    return np.asarray(fate)[curve] == 2


def later_transmission(fold, curve: int) -> np.ndarray:
    """The transmission fold of `curve` where it is not the first fold (the chain stayed localized past that one and
    was followed along the branch it settled on, /branches > 1), NaN elsewhere and for files without it."""
    omega = np.asarray(fold.data["omega"], dtype=float)
    trans, branches = fold.data.get("transmission_fold"), fold.data.get("branches")
    if trans is None or branches is None:
        return np.full(omega.shape, np.nan)
    later = np.asarray(branches)[curve] > 1
    switch, stairs = fold.data.get("branch_switch"), fold.data.get("transmission_stairs")
    if switch is not None:
        later &= np.asarray(switch)[curve] == 0
    if stairs is not None:
        later &= np.asarray(stairs)[curve] == 0
    return np.where(later, np.asarray(trans, dtype=float)[curve], np.nan)


def transmission_on_stairs(fold, curve: int) -> np.ndarray:
    """Where the chain of `curve`, settled past a fold on no stable periodic state, transmits when driven up in
    stairs from there (/transmission_stairs 1 with no loss of stability below the fold, /branch_switch 0), NaN
    elsewhere and for files without /transmission_stairs."""
    omega = np.asarray(fold.data["omega"], dtype=float)
    trans, stairs = fold.data.get("transmission_fold"), fold.data.get("transmission_stairs")
    if trans is None or stairs is None:
        return np.full(omega.shape, np.nan)
    on = np.asarray(stairs)[curve] == 1
    switch = fold.data.get("branch_switch")
    if switch is not None:
        on &= np.asarray(switch)[curve] == 0
    return np.where(on, np.asarray(trans, dtype=float)[curve], np.nan)


def transmission_spread(fold, curve: int) -> np.ndarray:
    """How far more climbs of stairs transmit from the first (/transmission_spread: where /transmission_fold is
    a stair, the chain intermittent), NaN elsewhere and for files without it."""
    omega = np.asarray(fold.data["omega"], dtype=float)
    spread = fold.data.get("transmission_spread")
    if spread is None:
        return np.full(omega.shape, np.nan)
    return np.asarray(spread, dtype=float)[curve]


def transmission_past_loss(fold, curve: int) -> np.ndarray:
    """Where the chain of `curve` transmits past a loss of stability below the fold (/branch_switch > 0: past a
    branch point the other branch's fold, a later one, or the branch point itself; past a torus or a period
    doubling the stair where it transmits), NaN elsewhere and for files without /branch_switch."""
    omega = np.asarray(fold.data["omega"], dtype=float)
    trans, switch = fold.data.get("transmission_fold"), fold.data.get("branch_switch")
    if trans is None or switch is None:
        return np.full(omega.shape, np.nan)
    return np.where(np.asarray(switch)[curve] > 0, np.asarray(trans, dtype=float)[curve], np.nan)


def draw_transmission_marks(ax, fold, curve: int, suffix: str = "", legend: bool = True) -> None:
    """On `ax`, where the chain of `curve` transmits when that is not its first fold: past a loss of stability
    (green triangles), the folds past which it stays localized (red open diamonds) with a later branch's fold
    (red stars) or the stair from where it settled (red v), and a stair's spread over its climbs (grey error bars).
    `suffix` ends each legend label (", curve name"); `legend` False leaves them out (an inset's marks)."""
    omega = np.asarray(fold.data["omega"], dtype=float)
    fold_a = np.asarray(fold.data["fold_amplitude"], dtype=float)[curve]

    def lab(text: str) -> str | None:
        return text + suffix if legend else None

    def mark(values: np.ndarray, marker: str, ms: int, text: str, **style) -> None:
        if np.isfinite(values).any():
            ax.plot(omega, values, marker, ms=ms, zorder=5, label=lab(text), **style)

    mark(transmission_past_loss(fold, curve), "^", 5, "where the chain transmits past a loss of stability",
         color="tab:green")
    spread = transmission_spread(fold, curve)
    if np.isfinite(spread).any():
        trans = np.asarray(fold.data["transmission_fold"], dtype=float)[curve]
        ax.errorbar(omega, np.where(np.isfinite(spread), trans, np.nan), yerr=np.nan_to_num(spread), fmt="none",
                    ecolor="0.35", elinewidth=0.8, capsize=2, zorder=5, label=lab("spread of the climbs of stairs"))
    stays = localized_folds(fold, curve)
    if not stays.any():
        return
    ax.plot(omega[stays], fold_a[stays], "D", ms=5, mfc="none", mec="tab:red", zorder=5,
            label=lab("fold past which the chain stays localized"))
    mark(later_transmission(fold, curve), "*", 7, "fold of a later branch, past which the chain transmits",
         color="tab:red")
    mark(transmission_on_stairs(fold, curve), "v", 5,
         "stair on which the chain, settled on no stable periodic state, transmits", color="tab:red")
