"""Figures of the scene `amplitude_sweep` (Figs. 2, 3, 3-and-a-half, 4): total energy injected vs driving
amplitude, one panel per potential, or, for one potential whose masses have both signs, 'Pure-imaginary masses' and
'Real masses'; a zoom on the jumps below when they lie in a narrow window."""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..reader import Scene
from ..style import fmt, styled, subplots
from .common import (ENERGIES, PANEL, SYMBOLS, conditions, curve_name, failed_note, family_label, first_transmitting,
                     massless, potential_title, styles, title, vary_of)
from .common import energy as energy_of


def sweep_panels(s: Scene) -> tuple[list[tuple[str, list[int]]], str]:
    """Panels of a sweep, [(title, curve indices)], and the varied parameter. One panel per potential; for a
    single potential whose m^2 family has both signs, 'Pure-imaginary masses' (m^2 <= 0) and 'Real masses'
    (m^2 >= 0), m^2 = 0 in both."""
    pots = [str(x) for x in s.data["curves/potential"]]
    values = np.asarray(s.data["curves/value"], dtype=float)
    vary = vary_of(s)
    distinct = list(dict.fromkeys(pots))
    if vary == "m2" and len(distinct) == 1 and (values < 0).any() and (values > 0).any():
        name = potential_title(distinct[0])
        return [(f"Pure-imaginary masses ({name})", [i for i, v in enumerate(values) if v <= 0]),
                (f"Real masses ({name})", [i for i, v in enumerate(values) if v >= 0])], vary
    return [(potential_title(p), [i for i, q in enumerate(pots) if q == p]) for p in distinct], vary


def zoom_window(amp: Any, first: Any) -> tuple[float, float] | None:
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


@styled
def draw_sweep(s: Scene, zoom: bool = True, energy: str = "injected"):
    """Total energy injected vs driving amplitude, one column per panel; when the jumps of the curves lie in a
    narrow window (and `zoom`), a second row shows that window, every run as a dot. `energy`: another energy
    of the file instead (ENERGIES: 'stored', 'dissipated_gamma', ...)."""
    panels, vary = sweep_panels(s)
    amp = np.asarray(s.data["amplitude"], dtype=float)
    e, ylabel = energy_of(s, energy)
    status = s.data["runs/status"]
    trans = s.data["runs/transmitting"]
    values = np.asarray(s.data["curves/value"], dtype=float)
    pots = [str(x) for x in s.data["curves/potential"]]
    a_s = s.data.get("curves/threshold_As")
    first = [first_transmitting(amp, trans[i], status[i]) for i in range(len(pots))]
    window = zoom_window(amp, first) if zoom else None
    rows = 2 if window else 1
    fig, axes = subplots(rows, len(panels), figsize=(PANEL[0] * len(panels), PANEL[1] * (1 + 0.85 * (rows - 1))),
                         squeeze=False, height_ratios=[1, 0.85][:rows])
    for col, (name, idx) in enumerate(panels):
        order = sorted(idx, key=lambda i: (abs(values[i]) if math.isfinite(values[i]) else 0, values[i]))
        st_order = styles(values[order], vary, [pots[i] for i in order])
        for row in range(rows):
            ax = axes[row, col]
            for i, st in zip(order, st_order):
                y = np.where(status[i] == 0, e[i], np.nan)
                if row == 0:
                    ax.plot(amp, y, label=family_label(vary, values[i], pots[i]), **st)
                else:
                    ax.plot(amp, y, **{**st, "marker": "o", "markersize": 2.5})
            if a_s is not None:
                _as_marks(s, ax, idx, order, st_order, a_s, vary, row)
            _thin_marks(s, ax, amp, e, order, st_order, row)
            ax.set_ylabel(ylabel)
            if row == rows - 1:
                ax.set_xlabel(f"driving amplitude $A${s.unit('amplitude')}")
            if row == 0:
                _first_row(s, ax, name, amp, status[idx], window)
            else:
                ax.set_xlim(*window)
                inside = (amp >= window[0]) & (amp <= window[1])
                ys = np.where(status[idx] == 0, e[idx], np.nan)[:, inside]
                top = np.nanmax(ys) if np.isfinite(ys).any() else 1.0
                ax.set_ylim(0, 1.08 * top)
                ax.set_title(f"zoom on the jump, A = {window[0]:.3g} .. {window[1]:.3g} (one dot per run)",
                             fontsize=8)
            ax.set_ylim(bottom=0)
    sym = SYMBOLS.get(vary)
    what = ENERGIES[energy].replace(" $E$", "") + " vs driving amplitude" + (rf", family in ${sym}$" if sym else "")
    fig.suptitle(title(s, what) + "\n" + conditions(s))
    return fig


def _as_marks(s: Scene, ax, idx: list[int], order: list[int], st_order: list[dict], a_s, vary: str,
              row: int) -> None:
    """x-marks on the amplitude axis, one per distinct A_s, in the colour of its curve."""
    marks: dict[float, Any] = {}
    keep = massless(s, idx)
    for i, st in zip(order, st_order):
        if i in keep and math.isfinite(a_s[i]):
            marks.setdefault(round(float(a_s[i]), 6), st["color"])
    for a, colour in sorted(marks.items()):
        one = len(marks) == 1
        ax.plot([a], [0], marker="x", color="black" if one else colour, ms=7, mew=1.5, ls="none",
                clip_on=False, zorder=5, transform=ax.get_xaxis_transform(),
                label=(rf"$A_s$ = {a:.3f}" + (" ($m^2$ = 0)" if vary == "m2" else "")) if one and row == 0 else None)
    if len(marks) > 1 and row == 0:
        ax.plot([], [], "x", color="0.4", ms=7, mew=1.5, label=r"$A_s$ of each curve (its colour)")


#: The factor `min_energy_jump` of a file written before it was an input key (`&scene min_energy_jump`, whose
#: default it is; the program had it as a constant): only for such files, which lack the /parameters attribute.
LEGACY_MIN_ENERGY_JUMP = 3.0


def min_energy_jump(s: Scene) -> float:
    """The file's `min_energy_jump` (its /parameters attribute): a verdict change whose energy injected after the
    ramp grows by less than this factor is "without an energy jump" (the file counts them in the /runs attribute
    verdict_changes_without_energy_jump). A file written before the key falls back to LEGACY_MIN_ENERGY_JUMP."""
    return float(s.params.get("min_energy_jump", LEGACY_MIN_ENERGY_JUMP))


def thin_thresholds(s: Scene) -> list[tuple[int, float, str]]:
    """The thresholds (first transmitting amplitude) of a sweep whose verdict is thin, [(curve, amplitude, why)]:
    the run there or just below it has a thin verdict (/runs/thin_verdict), or the energy injected after the ramp
    does not jump there (/runs/energy_jump below the file's `min_energy_jump`)."""
    amp = np.asarray(s.data["amplitude"], dtype=float)
    thin = s.data.get("runs/thin_verdict")
    jump = s.data.get("runs/energy_jump")
    min_jump = min_energy_jump(s)
    out = []
    for c in range(len(s.data["curves/potential"])):
        a = first_transmitting(amp, s.data["runs/transmitting"][c], s.data["runs/status"][c])
        if not math.isfinite(a):
            continue
        k = int(np.argmax(amp == a))
        why = []
        if thin is not None and (np.asarray(thin[c][max(k - 1, 0):k + 1]) == 1).any():
            why.append("thin margin")
        if jump is not None and k > 0 and math.isfinite(float(jump[c][k])) and float(jump[c][k]) < min_jump:
            why.append(f"energy x{float(jump[c][k]):.2g} only")
        if why:
            out.append((c, a, ", ".join(why)))
    return out


def _thin_marks(s: Scene, ax, amp: np.ndarray, e: np.ndarray, order: list[int], st_order: list[dict],
                row: int) -> None:
    """An open circle on each thin threshold (`thin_thresholds`), in its curve's colour, with its reason."""
    marks = thin_thresholds(s)
    for c, a, why in marks:
        if c not in order:
            continue
        k = int(np.argmax(amp == a))
        colour = st_order[order.index(c)]["color"]
        ax.plot([a], [e[c, k]], "o", ms=8, mfc="none", mew=1.0, color=colour, zorder=6, gid="thin")
        if row == 0:
            ax.annotate(why, (a, e[c, k]), textcoords="offset points", xytext=(6, -10), fontsize=6.5, color=colour)
    if row == 0 and any(c in order for c, _, _ in marks):
        ax.plot([], [], "o", ms=8, mfc="none", color="0.3", label="thin verdict at the threshold")


def _first_row(s: Scene, ax, name: str, amp: np.ndarray, status: np.ndarray, window) -> None:
    """Title, limits, legend and notes of a panel of the first row."""
    ax.set_title(name)
    if amp.size > 1:
        ax.set_xlim(amp.min(), amp.max())
    ax.legend(loc="upper left", frameon=False)
    note = failed_note(status)
    if note:
        ax.text(0.99, 0.02, note, transform=ax.transAxes, ha="right", va="bottom", fontsize=7, color="#D55E00")
    if not (status == 0).any():
        ax.text(0.5, 0.5, "no run done yet" if s.partial else "no run completed", transform=ax.transAxes,
                ha="center", va="center", color="0.4")
    if window:
        ax.axvspan(*window, color="0.9", zorder=0)


def summary_sweep(s: Scene) -> list[str]:
    """Per curve: the first transmitting amplitude, the jump of the energy there, the largest energy."""
    pots = [str(x) for x in s.data["curves/potential"]]
    values = np.asarray(s.data["curves/value"], dtype=float)
    vary = vary_of(s)
    amp = np.asarray(s.data["amplitude"], dtype=float)
    e = np.asarray(s.data["energy/injected"], dtype=float)
    st, tr = s.data["runs/status"], s.data["runs/transmitting"]
    lines = []
    for c in range(len(pots)):
        a = first_transmitting(amp, tr[c], st[c])
        line = f"  {curve_name(pots[c], vary, values[c])}: "
        if math.isfinite(a):
            k = int(np.argmax(amp == a))
            before = e[c, k - 1] if k > 0 else float("nan")
            line += (f"transmits from A = {a:.4g} (E = {fmt(before, 4)} at A = {fmt(amp[k - 1]) if k else '-'}"
                     f" -> {fmt(e[c, k], 4)})")
        else:
            line += "no run transmits"
        if np.isfinite(e[c]).any():
            line += f", E up to {fmt(np.nanmax(e[c]), 4)}"
        lines.append(line)
    return lines
