"""Figure of the scene `bifurcation` (Bif1-Bif3): threshold amplitude vs driving frequency, one curve per
(potential, value), A_s = 4 arctan(lambda c / Omega) as x-marks."""
from __future__ import annotations

import math

import numpy as np

from ..reader import Scene
from ..style import fmt, styled, subplots
from .common import (PANEL, SYMBOLS, columns, conditions, curve_name, family_label, massless, potential_title,
                     styles, title, vary_of)


def _label(vary: str, value: float, potential: str, several: bool) -> str:
    """Legend entry of a curve; a mass curve by its band edge sqrt(m^2 + 1) (and l when it is 1 + l/40)."""
    if vary != "m2":
        return family_label(vary, value, potential, several)
    edge = math.sqrt(1.0 + value)
    ell = 40.0 * (edge - 1.0)
    label = rf"$\sqrt{{m^2+1}}$ = {edge:.4g}"
    if abs(ell - round(ell)) < 1e-6:
        label += rf" ($\ell$ = {int(round(ell))})"
    if several:
        label = f"{potential_title(potential).replace(' chain', '')}, {label}"
    return label


@styled
def draw_bifurcation(s: Scene):
    """Threshold amplitude vs driving frequency, one curve per (potential, value), A_s as x-marks (one set per
    distinct A_s(Omega) curve: it does not depend on gamma or beta), the points without a threshold noted."""
    omega = np.asarray(s.data["omega"], dtype=float)
    thr = np.asarray(s.data["threshold"], dtype=float)
    a_s = np.asarray(s.data["threshold_As"], dtype=float)
    status = s.data["status"]
    pots = [str(x) for x in s.data["curves/potential"]]
    values = np.asarray(s.data["curves/value"], dtype=float)
    vary = vary_of(s)
    several = len(set(pots)) > 1
    order = sorted(range(len(pots)), key=lambda i: (pots.index(pots[i]), values[i] if math.isfinite(values[i])
                                                    else 0))
    st_order = styles(values[order], vary, [pots[i] for i in order])
    fig, ax = subplots(figsize=(PANEL[0] * 1.35, PANEL[1] * 1.3))
    if not np.isin(status, (0, 1)).any():
        ax.text(0.5, 0.5, "no threshold found yet" if s.partial else "no threshold found", transform=ax.transAxes,
                ha="center", va="center", color="0.4")
    for i, st in zip(order, st_order):
        y = np.where(np.isin(status[i], (0, 1)), thr[i], np.nan)
        line, = ax.plot(omega, y, label=_label(vary, values[i], pots[i], several), **st)
        single = np.isfinite(y) & ~np.isfinite(np.roll(y, 1)) & ~np.isfinite(np.roll(y, -1))
        if single.any():  # points without a neighbour would not show as a line
            ax.plot(omega[single], y[single], ".", color=line.get_color())
    rows: list[tuple[np.ndarray, int]] = []
    keep = massless(s, order)
    for i in order:
        if i not in keep:
            continue
        row = a_s[i]
        if np.isfinite(row).any() and not any(np.allclose(row, r, equal_nan=True) for r, _ in rows):
            rows.append((row, i))
    for row, i in rows:
        one = len(rows) == 1
        mass = " ($m^2$ = 0)" if vary == "m2" else ""
        ax.plot(omega, row, "x", color="black" if one else st_order[order.index(i)]["color"], ms=5 if one else 4,
                mew=1.0, label=r"$A_s = 4\arctan(\lambda c/\Omega)$" + mass if one else None)
    if len(rows) > 1:
        ax.plot([], [], "x", color="0.4", ms=5, mew=1.0, label=r"$A_s = 4\arctan(\lambda c/\Omega)$ of each curve")
    notes = _notes(s, status)
    if notes:
        ax.text(0.99, 0.01, "; ".join(notes), transform=ax.transAxes, ha="right", va="bottom", fontsize=7,
                color="0.3")
    ax.set_xlabel(rf"driving frequency $\Omega${s.unit('omega')}")
    ax.set_ylabel(f"threshold amplitude $A${s.unit('threshold')}")
    ax.legend(loc="best", ncol=2 if len(order) > 4 else 1, framealpha=0.85)
    sym = SYMBOLS.get(vary)
    what = "smallest transmitting amplitude vs driving frequency" + (rf", family in ${sym}$" if sym else "")
    res = s.params.get("resolution")
    cond = conditions(s) + (f", resolution {fmt(res)}" if res is not None else "")
    fig.suptitle(title(s, what) + "\n" + cond)
    return fig


def _notes(s: Scene, status: np.ndarray) -> list[str]:
    """What the gaps of the diagram are: searches at the lower bound, without transmission, failed."""
    lower = np.count_nonzero(status == 1)
    none = np.count_nonzero(status == 2)
    failed = np.count_nonzero(status == 3)
    notes = []
    if lower:
        notes.append(f"{lower} point(s) at the lower bound A = {fmt(s.params.get('amplitude_min'))}")
    if none:
        notes.append(f"{none} with no transmission up to A = {fmt(s.params.get('amplitude_max'))} (gaps)")
    if failed:
        notes.append(f"{failed} search(es) failed (gaps)")
    return notes


def summary_bifurcation(s: Scene, full: bool = False) -> list[str]:
    """Per curve: how many thresholds were found and the threshold at about seven frequencies (`full`: every
    one); then A_s of the massless curve."""
    pots = [str(x) for x in s.data["curves/potential"]]
    values = np.asarray(s.data["curves/value"], dtype=float)
    vary = vary_of(s)
    omega = np.asarray(s.data["omega"])
    thr, status = s.data["threshold"], s.data["status"]
    cols = columns(omega, full)
    lines = []
    for c in range(len(pots)):
        found = np.isin(status[c], (0, 1))
        name = curve_name(pots[c], vary, values[c])
        line = (f"  {name}: {int(found.sum())} of {omega.size} thresholds found"
                f" (Omega {fmt(omega[found].min(), 3)}..{fmt(omega[found].max(), 3)})" if found.any() else
                f"  {name}: no threshold found")
        line += "; Omega: A = " + ", ".join(f"{fmt(omega[w], 3)}: {fmt(thr[c, w], 3)}" for w in cols)
        lines.append(line)
    for c in massless(s, range(len(pots)))[:1]:
        lines.append("  A_s" + (" (m2 = 0)" if vary == "m2" else "") + ": " + ", ".join(
            f"{fmt(omega[w], 3)}: {fmt(s.data['threshold_As'][c, w], 3)}" for w in cols))
    return lines
