"""Figure of the scene `continuation`: the threshold as a property of the model.

- one frequency: the branch of driven periodic states (max |u| over a period vs the drive amplitude A), stable
  part solid, unstable part dashed, the fold A_f and the first loss of stability marked; beside it the Floquet
  multipliers of largest modulus in the complex plane at the sampled points of the branch, with the unit circle;
- several frequencies: the fold line A_f(Omega) of each curve, the first loss of stability where it comes before
  the fold, and A_s = 4 arctan(lambda c / Omega) as x-marks; with a bifurcation scene's file (`scan`), its scan
  thresholds on the same chart;
- a file by harmonic balance (root attribute `solver`): its fold line or its continuum limit (`harmonic`).
"""
from __future__ import annotations

import math

import numpy as np

from ..reader import Scene
from ..style import fmt, styled, subplots
from .common import PANEL, conditions, curve_name, draw_transmission_marks, styles, title, vary_of
from .harmonic import draw_continuum, draw_fold_line_hb, has_continuum, is_harmonic_balance, summary_harmonic_balance

#: Names of the instability types (the file's /instability_type codes).
KINDS = {0: "stable to the fold", 1: "multiplier +1", 2: "period doubling (-1)", 3: "torus (complex pair)"}


def _curves(s: Scene) -> tuple[list[str], np.ndarray, str]:
    pots = [str(x) for x in s.data["curves/potential"]]
    return pots, np.asarray(s.data["curves/value"], dtype=float), vary_of(s)


@styled
def draw_continuation(s: Scene, scan: Scene | None = None, shooting: Scene | None = None):
    """The branch and its multipliers (one frequency) or the fold lines (several), see the module docstring; a
    file by harmonic balance (root attribute `solver`) is drawn by `harmonic`: its continuum limit when it has
    one, else its fold line (over `scan` and beside the fold line by `shooting`, when given)."""
    if is_harmonic_balance(s):
        return draw_continuum(s) if has_continuum(s) else draw_fold_line_hb(s, scan, shooting)
    omega = np.asarray(s.data["omega"], dtype=float)
    if omega.size == 1 and scan is None:
        return _draw_branch(s)
    return _draw_fold_line(s, scan)


def _draw_branch(s: Scene):
    pots, values, vary = _curves(s)
    fig, (ax, axm) = subplots(1, 2, figsize=(PANEL[0] * 2.1, PANEL[1] * 1.25),
                              gridspec_kw={"width_ratios": [1.6, 1.0]})
    st = styles(values, vary, pots)
    zoom = ax.inset_axes([0.56, 0.08, 0.42, 0.46])  # the lower right is empty: the branch rises from (0, 0)
    zoom_box: list[float] = []
    for c in range(len(pots)):
        n = int(s.data["branch/points"][c, 0])
        a = np.asarray(s.data["branch/amplitude"][c, 0, :n], dtype=float)
        u = np.asarray(s.data["branch/umax"][c, 0, :n], dtype=float)
        verdict = verdicts(np.asarray(s.data["branch/stable"][c, 0, :n], dtype=float))
        color = st[c].get("color")
        label = curve_name(pots[c], vary, values[c])
        parts = {1: ("-", 1.5, f"{label}: stable"), 0: ("--", 1.5, "unstable"),
                 -1: (":", 0.8, "stability not computed (floquet_every)")}
        line = None
        for v, (ls, lw, lab) in parts.items():
            m = verdict == v
            if not m.any() and v == -1:
                continue
            m = m | np.r_[m[1:], False]  # each part joins the next: no gap where the verdict changes
            ln, = ax.plot(np.where(m, a, np.nan), np.where(m, u, np.nan), ls, lw=lw, label=lab,
                          color=color if line is None else line.get_color())
            zoom.plot(np.where(m, a, np.nan), np.where(m, u, np.nan), ls, lw=lw, marker=".", ms=3,
                      color=ln.get_color())
            line = line or ln
        af = float(s.data["fold_amplitude"][c, 0])
        if math.isfinite(af):
            for a_ in (ax, zoom):
                a_.axvline(af, color=line.get_color(), lw=0.8, ls=":")
            zoom.annotate(rf"fold $A_f$ = {fmt(af, 6)}", (af, np.nanmax(u)), textcoords="offset points",
                          xytext=(-4, -10), ha="right", fontsize=7)
            near = a >= af - 0.08 * max(af, 1e-9)
            if near.any():
                zoom_box += [float(np.nanmin(a[near])), af, float(np.nanmin(u[near])), float(np.nanmax(u[near]))]
        ai = float(s.data["instability_amplitude"][c, 0])
        kind = int(s.data["instability_type"][c, 0])
        if math.isfinite(ai) and (not math.isfinite(af) or ai < af - 1e-9):
            ui = np.interp(ai, a[: int(np.nanargmax(a)) + 1], u[: int(np.nanargmax(a)) + 1])
            ax.plot([ai], [ui], "o", mfc="none", color=line.get_color(),
                    label=f"first loss of stability, {KINDS.get(kind, kind)}: A = {fmt(ai, 6)}")
            zoom.plot([ai], [ui], "o", mfc="none", color=line.get_color())
        a_s = float(s.data["threshold_As"][c, 0])
        if math.isfinite(a_s):
            for a_ in (ax, zoom):
                a_.axvline(a_s, color="0.5", lw=0.8, ls="-.", label=rf"$A_s$ = {fmt(a_s, 4)}" if a_ is ax else None)
    if zoom_box:
        x0, x1 = min(zoom_box[0::4]), max(zoom_box[1::4])
        y0, y1 = min(zoom_box[2::4]), max(zoom_box[3::4])
        pad_x, pad_y = 0.12 * max(x1 - x0, 1e-3), 0.08 * max(y1 - y0, 1e-3)
        zoom.set_xlim(x0 - pad_x, x1 + pad_x)
        zoom.set_ylim(y0 - pad_y, y1 + pad_y)
        zoom.tick_params(labelsize=6)
        zoom.set_title("zoom on the fold (dots: the branch's points)", fontsize=7, pad=2)
        ax.indicate_inset_zoom(zoom, edgecolor="0.5")
    else:
        zoom.set_visible(False)
    ax.set_xlabel(f"driving amplitude $A${s.unit('branch/amplitude')}")
    ax.set_ylabel(r"max $|u_n|$ over a period" + s.unit("branch/umax"))
    ax.legend(loc="upper left", fontsize=7, framealpha=0.85)
    _draw_multipliers(s, axm)
    w = float(s.data["omega"][0])
    fig.suptitle(title(s, rf"branch of driven periodic states at $\Omega$ = {fmt(w, 4)}") + "\n" + conditions(s))
    return fig


def verdicts(stable: np.ndarray) -> np.ndarray:
    """The stability of each branch point: the file's /branch/stable (1 stable, 0 unstable, -1 not computed: with
    `floquet_every` > 1 the multipliers are computed at every k-th point only), a point not computed taking the
    verdict of the computed points on both sides of it when they agree, -1 (unknown) when they differ."""
    st = np.where(np.isfinite(stable), stable, -1).astype(int)
    idx = np.arange(st.size)
    known = st >= 0
    if not known.any():
        return st
    prev = np.maximum.accumulate(np.where(known, idx, -1))
    nxt = np.minimum.accumulate(np.where(known, idx, st.size)[::-1])[::-1]
    before = np.where(prev >= 0, st[np.clip(prev, 0, None)], -1)
    after = np.where(nxt < st.size, st[np.clip(nxt, None, st.size - 1)], -1)
    fill = np.where(before == after, before, np.where(after < 0, before, np.where(before < 0, after, -1)))
    return np.where(known, st, fill)


def _draw_multipliers(s: Scene, ax) -> None:
    t = np.linspace(0.0, 2.0 * np.pi, 361)
    ax.plot(np.cos(t), np.sin(t), color="0.6", lw=0.8)
    if "multipliers/real" not in s.data:
        return
    re = np.asarray(s.data["multipliers/real"], dtype=float)
    im = np.asarray(s.data["multipliers/imag"], dtype=float)
    amp = np.asarray(s.data["multipliers/amplitude"], dtype=float)
    af = float(s.data["fold_amplitude"][0, 0])
    marks = ["o", "s", "*", "x"]
    for k in range(re.shape[1]):
        if not math.isfinite(amp[0, k]):
            continue
        ax.plot(re[0, k], im[0, k], marks[k % 4], ms=5, mfc="none" if marks[k % 4] != "x" else None,
                label=multiplier_label(k, float(amp[0, k]), af))
    ax.set_aspect("equal")
    ax.set_xlabel(r"Re $\mu$")
    ax.set_ylabel(r"Im $\mu$")
    ax.set_title("Floquet multipliers of largest modulus", fontsize=9)
    ax.legend(loc="lower left", fontsize=6, framealpha=0.85)


def multiplier_label(k: int, a: float, af: float) -> str:
    """Legend entry of the k-th sample of the multipliers (the file keeps them at the branch's first point, the
    computed point nearest half the fold, the fold, the last point), by the amplitude it is at: the second sample
    is named by its true fraction of A_f (with floquet_every > 1 the nearest point with multipliers can be far from
    A_f / 2)."""
    at = f"A = {fmt(a, 4)}"
    if k % 4 == 0:
        return f"first point ({at})"
    if k % 4 == 2:
        return f"the fold ({at})"
    if k % 4 == 3:
        return f"last point ({at}" + (f", {fmt(a / af, 3)} $A_f$)" if math.isfinite(af) and af > 0 else ")")
    if math.isfinite(af) and af > 0:
        return f"{fmt(a / af, 2)} $A_f$ ({at}; $A_f/2$ = {fmt(af / 2, 4)})"
    return f"midway ({at})"


def _draw_fold_line(s: Scene, scan: Scene | None):
    pots, values, vary = _curves(s)
    omega = np.asarray(s.data["omega"], dtype=float)
    fold = np.asarray(s.data["fold_amplitude"], dtype=float)
    inst = np.asarray(s.data["instability_amplitude"], dtype=float)
    st = styles(values, vary, pots)
    fig, ax = subplots(figsize=(PANEL[0] * 1.35, PANEL[1] * 1.3))
    for c in range(len(pots)):
        name = curve_name(pots[c], vary, values[c])
        line, = ax.plot(omega, fold[c], label=f"fold $A_f$, {name}", **{**st[c], "marker": ".", "markersize": 3})
        before = np.isfinite(inst[c]) & ~(inst[c] >= fold[c] - 1e-9)
        if before.any():
            ax.plot(omega[before], inst[c][before], "v", ms=4, mfc="none", color=line.get_color(),
                    label="first loss of stability" + (" (in its curve's colour)" if len(pots) > 1 else ""))
        draw_transmission_marks(ax, s, c, "")      # the same marks for every curve: one legend entry each
    a_s = np.asarray(s.data["threshold_As"], dtype=float)
    if np.isfinite(a_s).any():
        ax.plot(omega, a_s[0], "x", color="black", ms=4, label=r"$A_s = 4\arctan(\lambda c/\Omega)$")
    if scan is not None:
        thr = np.asarray(scan.data["threshold"], dtype=float)
        status = np.asarray(scan.data["status"])
        w2 = np.asarray(scan.data["omega"], dtype=float)
        for c in range(thr.shape[0]):
            y = np.where(np.isin(status[c], (0, 1)), thr[c], np.nan)
            ax.plot(w2, y, ".", ms=3, color="0.35", label="ramped scan threshold" if c == 0 else None)
    ax.set_xlabel(rf"driving frequency $\Omega${s.unit('omega')}")
    ax.set_ylabel(f"amplitude $A${s.unit('fold_amplitude')}")
    # below the axes, off the data: the fold line fills the panel from corner to corner (its dips reach A ~ 1.8)
    handles, labels = ax.get_legend_handles_labels()
    unique = dict(zip(labels, handles))           # a mark's meaning once, whatever curve it is drawn on
    ax.legend(unique.values(), unique.keys(), loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2, fontsize=7,
              framealpha=0.9)
    fig.suptitle(title(s, "fold of the driven periodic state vs driving frequency") + "\n" + conditions(s))
    return fig


def summary_continuation(s: Scene, full: bool = False) -> list[str]:
    """Per curve and frequency (about seven of them unless `full`): the fold, the first loss of stability, A_s, the
    converged digits; a file by harmonic balance: `harmonic.summary_harmonic_balance`."""
    if is_harmonic_balance(s):
        return summary_harmonic_balance(s, full)
    pots, values, vary = _curves(s)
    omega = np.asarray(s.data["omega"], dtype=float)
    cols = range(omega.size) if full or omega.size <= 7 else np.unique(np.linspace(0, omega.size - 1, 7).astype(int))
    digits = s.data.get("convergence/digits")
    lines = []
    for c in range(len(pots)):
        parts = []
        for w in cols:
            d = "" if digits is None or not math.isfinite(float(digits[c, w])) else f" ({int(digits[c, w])} digits)"
            kind = int(s.data["instability_type"][c, w])
            inst = float(s.data["instability_amplitude"][c, w])
            extra = f", unstable from {fmt(inst, 6)} ({KINDS.get(kind, kind)})" if math.isfinite(inst) else ""
            extra += _past_branch_point(s, c, w)
            parts.append(f"Omega {fmt(omega[w], 3)}: A_f = {fmt(float(s.data['fold_amplitude'][c, w]), 8)}{d}"
                         f"{extra}, A_s = {fmt(float(s.data['threshold_As'][c, w]), 4)}")
        lines.append(f"  {curve_name(pots[c], vary, values[c])}: " + "; ".join(parts))
    return lines


SWITCHES = {1: "supercritical", 2: "subcritical", 3: "other branch not found", 5: "side unknown: only bracketed"}
STAIRS = 4


def _past_branch_point(s: Scene, c: int, w: int) -> str:
    """", transmits at A past the branch point (its kind)" where the file switched branch there (/branch_switch
    1 .. 3, 5), ", transmits at A on stairs past the loss" where it drove the chain up in stairs past a torus or a
    period doubling (4; ", transmits at A past the fold" where no stair did and the fold's fate transmits),
    ", transmits at A on stairs from where the chain settled" where it did so past a fold from
    where the chain settled on no stable periodic state (/transmission_stairs 1, /branch_switch 0); a stair's
    number with the spread of the climbs (/transmission_spread) where the file has it."""
    switch, stairs = s.data.get("branch_switch"), s.data.get("transmission_stairs")
    trans = float(s.data["transmission_fold"][c, w]) if "transmission_fold" in s.data else float("nan")
    spread = float(s.data["transmission_spread"][c, w]) if "transmission_spread" in s.data else float("nan")
    at = f"{fmt(trans, 6)} (climbs spread by {fmt(spread, 2)})" if math.isfinite(spread) else fmt(trans, 6)
    if (switch is None or int(switch[c, w]) <= 0) and stairs is not None and int(stairs[c, w]) == 1:
        return f", transmits at {at} on stairs from where the chain settled"
    if switch is None or int(switch[c, w]) <= 0:
        return ""
    where = f"transmits at {at}" if math.isfinite(trans) else "no transmission found"
    if int(switch[c, w]) == STAIRS:
        if stairs is not None and int(stairs[c, w]) == 0 and math.isfinite(trans):
            return f", {where} past the fold (the stairs from the loss did not transmit below it)"
        return f", {where} on stairs past the loss"
    return f", {where} past the branch point ({SWITCHES.get(int(switch[c, w]), 'unknown')})"
