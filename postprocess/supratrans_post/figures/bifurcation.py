"""Figure of the scene `bifurcation` (Bif1-Bif3): threshold amplitude vs driving frequency, one curve per
(potential, value), A_s = 4 arctan(lambda c / Omega) as x-marks."""
from __future__ import annotations

import math
import textwrap

import numpy as np

from ..reader import Scene
from ..style import fmt, styled, subplots
from .common import (PANEL, SYMBOLS, columns, conditions, curve_name, family_label, massless, potential_title,
                     styles, title, vary_of)


#: Markers of the curves of a family, in order (with the line styles of `styles`).
MARKS = ["o", "s", "^", "D", "v", "P", "X", "*"]


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


#: At most this many markers along a curve: a curve of more points carries them every k-th point (A_s and the
#: thresholds alike, so that the x-marks of A_s sit at the frequencies of the curves' markers).
MARKERS = 24
#: What each curve of a diagram measures (the figure's caption): the scan, the fold beside it (where drawn), the
#: thin verdicts, and why damped curves climb (where a curve is damped).
CAPTION = {
    "scan": "Lines: the detector's threshold, the smallest ramped drive amplitude at which an oscillator beyond the "
            "detector site passes the detect amplitude (a protocol: ramp, T, detector).",
    "fold": "Thick orange: the fold of the driven periodic state (harmonic balance: the model's threshold, no "
            "protocol), where its file has the curve's chain.",
    "thin": "Open circles: thin verdicts (the run just below the threshold came within thin_margin of the detect "
            "amplitude).",
    "damped": "With strong damping the emitted wave decays before the detector site, so the detector fires late "
              "and the damped curves climb near the band edge: that is the detector, not the chain "
              "(docs/method.md, Classification).",
}


def marker_step(n: int) -> int:
    """Every how many points a curve of n points carries a marker (at most MARKERS of them)."""
    return max(1, -(-n // MARKERS))


def thin_mask(s: Scene) -> np.ndarray | None:
    """Where a threshold is a thin verdict (/thin_verdict = 1), (curve, omega); None for a file without it."""
    thin = s.data.get("thin_verdict")
    return None if thin is None else np.asarray(thin) == 1


def chain_of(s: Scene, c: int) -> tuple:
    """(potential, gamma, beta, m^2, c) of curve c of a grid scene: the varied parameter from `/curves/value`, the
    others from `/parameters`."""
    vary = vary_of(s)
    values = np.asarray(s.data["curves/value"], dtype=float)
    return (str(s.data["curves/potential"][c]),
            *(float(values[c]) if vary == k else float(s.params.get(k, 0.0)) for k in ("gamma", "beta", "m2")),
            float(s.params.get("c", math.nan)))


def _fold_curve(s: Scene, c: int, fold: Scene | None) -> int | None:
    """The curve of the fold-line file `fold` with the chain of curve c of the bifurcation file `s` (potential,
    gamma, beta, m^2 and c equal), None when it has none (or there is no fold file)."""
    if fold is None:
        return None
    mine = chain_of(s, c)
    for j in range(len(fold.data["curves/potential"])):
        theirs = chain_of(fold, j)
        if mine[0] == theirs[0] and all(math.isclose(a, b, abs_tol=1e-12) for a, b in zip(mine[1:], theirs[1:])):
            return j
    return None


@styled
def draw_bifurcation(s: Scene, fold: Scene | None = None):
    """Threshold amplitude vs driving frequency, one curve per (potential, value), A_s as x-marks (one set per
    distinct A_s(Omega) curve: it does not depend on gamma or beta), the thin verdicts as open circles, the points
    without a threshold noted; with `fold` (a continuation file's fold line, e.g. by harmonic balance), its fold
    A_f(Omega) beside each curve of the same chain. The legend beside the axes, the caption (CAPTION) below."""
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
    step = marker_step(omega.size)
    thin = thin_mask(s)
    fig, ax = subplots(figsize=(PANEL[0] * 1.75, PANEL[1] * 1.45))
    if not np.isin(status, (0, 1)).any():
        ax.text(0.5, 0.5, "no threshold found yet" if s.partial else "no threshold found", transform=ax.transAxes,
                ha="center", va="center", color="0.4")
    folds_drawn = False
    for k, (i, st) in enumerate(zip(order, st_order)):
        y = np.where(np.isin(status[i], (0, 1)), thr[i], np.nan)
        line, = ax.plot(omega, y, label=_label(vary, values[i], pots[i], several), markevery=(k % step, step),
                        **{**st, "marker": st.get("marker") or MARKS[k % len(MARKS)], "markersize": 3.5})
        single = np.isfinite(y) & ~np.isfinite(np.roll(y, 1)) & ~np.isfinite(np.roll(y, -1))
        if single.any():  # points without a neighbour would not show as a line
            ax.plot(omega[single], y[single], ".", color=line.get_color())
        if thin is not None and thin[i].any():
            ax.plot(omega[thin[i]], y[thin[i]], "o", ms=6, mfc="none", mew=0.9, color=line.get_color(), zorder=5,
                    gid="thin")
        j = _fold_curve(s, i, fold)
        if j is not None:
            wf = np.asarray(fold.data["omega"], dtype=float)
            half = 0.5 * (float(np.min(np.diff(omega))) if omega.size > 1 else 0.0)
            inside = (wf >= omega.min() - half - 1e-12) & (wf <= omega.max() + half + 1e-12)
            af = np.asarray(fold.data["fold_amplitude"], dtype=float)[j][inside]
            label = rf"fold $A_f$ ({_fold_solver(fold)}), " + _label(vary, values[i], pots[i], several)
            ax.plot(wf[inside], af, "-", lw=3.2, alpha=0.55, color="#E69F00", zorder=1, gid="fold",
                    marker="o" if inside.sum() <= 2 * MARKERS else None, ms=3, label=label)
            folds_drawn = True
    if thin is not None and thin.any():
        ax.plot([], [], "o", ms=6, mfc="none", color="0.3",
                label=f"thin verdict ({int(thin.sum())} of {int((np.asarray(s.data['thin_verdict']) >= 0).sum())}):"
                      f" margin < {fmt(s.attr('thin_verdict', 'thin_margin', 0.2))}")
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
                mew=1.0, markevery=step, label=r"$A_s = 4\arctan(\lambda c/\Omega)$" + mass if one else None)
    if len(rows) > 1:
        ax.plot([], [], "x", color="0.4", ms=5, mew=1.0, label=r"$A_s = 4\arctan(\lambda c/\Omega)$ of each curve")
    notes = _notes(s, status)
    if notes:
        ax.text(0.99, 0.01, "; ".join(notes), transform=ax.transAxes, ha="right", va="bottom", fontsize=7,
                color="0.3")
    ax.set_xlabel(rf"driving frequency $\Omega${s.unit('omega')}")
    ax.set_ylabel(f"threshold amplitude $A${s.unit('threshold')}")
    fig.legend(*ax.get_legend_handles_labels(), loc="outside right center", fontsize=7.5, framealpha=0.9)
    sym = SYMBOLS.get(vary)
    what = "smallest transmitting amplitude vs driving frequency" + (rf", family in ${sym}$" if sym else "")
    res = s.params.get("resolution")
    cond = conditions(s) + (f", resolution {fmt(res)}" if res is not None else "")
    fig.suptitle(title(s, what) + "\n" + cond)
    damped = any(chain_of(s, i)[1] > 0.0 for i in order)
    caption = " ".join(CAPTION[k] for k, on in (("scan", True), ("fold", folds_drawn), ("thin", thin is not None),
                                                ("damped", damped)) if on)
    fig.text(0.01, 0.0, textwrap.fill(caption, 150), ha="left", va="top", fontsize=7, color="0.25", gid="caption")
    return fig


def _fold_solver(fold: Scene) -> str:
    """How the fold line was computed, in words."""
    return "harmonic balance" if fold.solver == "harmonic_balance" else "shooting"


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
