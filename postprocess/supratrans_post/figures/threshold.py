"""Charts that put the model's threshold next to the protocols' (issue 25, points 8 and 9).

- `draw_thresholds`: one Bif1-style chart (threshold amplitude vs driving frequency) with the fold line A_f(Omega)
  of a continuation file (the model's threshold, solid), the first loss of Floquet stability where it comes before
  the fold, the thresholds of a ramped scan (a bifurcation file, dashed), the bistable window of a hysteresis file
  (upward and downward edge of each stair length, the window between them shaded) and A_s = 4 arctan(lambda c /
  Omega) as x-marks; a zoom on the hysteresis window when it is at one frequency only.
- `draw_ramp`: the scan threshold at one frequency against the ramp time (one bifurcation file per ramp time, each
  threshold with its bracket: the scan's first transmitting amplitude A_t means the threshold is in
  (A_t - resolution, A_t]), next to the fold of a continuation file, its first loss of stability and A_s.

Every number comes from the files: the ramp times, resolutions, T from `/parameters`, the edges from the datasets.
"""
from __future__ import annotations

import math
import textwrap

import numpy as np

from ..reader import PlotError, Scene
from ..style import fmt, styled, subplots
from .common import COLOURS, PANEL, conditions, curve_name, draw_transmission_marks, notes, vary_of
from .continuation import KINDS
from .hysteresis import edge_reason

#: Width (in Omega) of the shaded window of a hysteresis file at a single frequency, as a fraction of the chart's
#: frequency step (or of 0.05 when no other file sets one).
WINDOW_WIDTH = 0.6


def _curve_keys(s: Scene) -> list[tuple[str, float]]:
    """(potential, value) of each curve of a grid scene."""
    pots = [str(x) for x in s.data["curves/potential"]]
    return list(zip(pots, (float(v) for v in np.asarray(s.data["curves/value"], dtype=float))))


def _match(s: Scene, key: tuple[str, float], vary: str) -> int | None:
    """The curve of `s` with the potential and varied value of `key` (the value only when both files vary the
    same parameter), None when there is none."""
    same = vary_of(s) == vary
    for i, (pot, value) in enumerate(_curve_keys(s)):
        if pot == key[0] and (not same or vary == "none" or math.isclose(value, key[1], abs_tol=1e-12)):
            return i
    return None


def _omega_step(*axes: np.ndarray) -> float:
    """The smallest spacing of the frequency axes given (0.05 when none has two points)."""
    steps = [float(np.min(np.diff(np.sort(a)))) for a in axes if a is not None and a.size > 1]
    return min(steps) if steps else 0.05


def hysteresis_windows(h: Scene, curve: int = 0) -> list[dict]:
    """Per stair length of curve `curve` of a hysteresis file: {stair_time, omega, up, down} (arrays over the
    file's frequencies; NaN where an edge was not found)."""
    omega = np.asarray(h.data["omega"], dtype=float)
    out = []
    for i, ts in enumerate(np.asarray(h.data["stair_time"], dtype=float)):
        out.append({"stair_time": float(ts), "omega": omega,
                    "up": np.asarray(h.data["upward_threshold"][curve, :, i], dtype=float),
                    "down": np.asarray(h.data["downward_threshold"][curve, :, i], dtype=float)})
    return out


def _draw_windows(ax, h: Scene, curve: int, width: float, name: str, legend: bool = True) -> None:
    """The hysteresis edges and shaded windows of one curve on `ax` (each shaded area has gid 'window:<T_s>'); at a
    single frequency the stair lengths side by side in a band of `width` around it, each with its own window."""
    wins = hysteresis_windows(h, curve)
    for i, w in enumerate(wins):
        color = COLOURS[(i + 1) % len(COLOURS)]
        ok = np.isfinite(w["up"]) & np.isfinite(w["down"])
        om = w["omega"]
        label = rf"bistable window, stairs $T_s$ = {fmt(w['stair_time'])}{name}" if legend else None
        gid = f"window:{w['stair_time']:g}"
        if om.size == 1:
            part = width / len(wins)
            x = om[0] - width / 2 + part * np.array([i + 0.1, i + 0.9])
            if ok[0]:
                ax.fill_between(x, w["down"][0], w["up"][0], color=color, alpha=0.3, lw=0, gid=gid, label=label)
            ax.plot([x.mean()], w["up"][:1], "^", ms=5, color=color, mec="black", mew=0.5)
            ax.plot([x.mean()], w["down"][:1], "v", ms=5, color=color, mec="black", mew=0.5)
        else:
            ax.fill_between(om, w["down"], w["up"], where=ok, color=color, alpha=0.18, lw=0, gid=gid, label=label)
            ax.plot(om, w["up"], "-^", ms=4, lw=0.8, color=color)
            ax.plot(om, w["down"], "--v", ms=4, lw=0.8, color=color)
    if legend:
        ax.plot([], [], "^", ms=5, color="0.6", mec="black", mew=0.5, label="upward edge (stairs up)")
        ax.plot([], [], "v", ms=5, color="0.6", mec="black", mew=0.5, label="downward edge (stairs down)")


def _scan_label(scan: Scene) -> str:
    p = scan.params
    return (f"ramped scan (ramp {fmt(p.get('ramp_time'))}, $T$ = {fmt(p.get('t_final'))}, "
            f"resolution {fmt(p.get('resolution'))})")


def _scan_line(scan: Scene, curve: int) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies and thresholds of a scan curve, NaN where no threshold was found."""
    thr = np.asarray(scan.data["threshold"], dtype=float)[curve]
    status = np.asarray(scan.data["status"])[curve]
    return np.asarray(scan.data["omega"], dtype=float), np.where(np.isin(status, (0, 1)), thr, np.nan)


@styled
def draw_thresholds(fold: Scene, scan: Scene | None = None, hysteresis: Scene | None = None):
    """The fold line, the scan thresholds, the hysteresis window and A_s on one chart (module docstring). A
    hysteresis file at one frequency is drawn at that frequency as one bar (the union of its windows) and, in an
    inset, each stair length's window against the stair length (its true abscissa), beside the fold, the scan's
    threshold and A_s there. The legend is below the axes."""
    if fold.scene != "continuation":
        raise PlotError(fold.path, f"scene is '{fold.scene}', not 'continuation' (the fold line)")
    _by_shooting(fold)
    for other, kind in ((scan, "bifurcation"), (hysteresis, "hysteresis")):
        if other is not None and other.scene != kind:
            raise PlotError(other.path, f"scene is '{other.scene}', not '{kind}'")
    omega = np.asarray(fold.data["omega"], dtype=float)
    fold_a = np.asarray(fold.data["fold_amplitude"], dtype=float)
    inst = np.asarray(fold.data["instability_amplitude"], dtype=float)
    vary = vary_of(fold)
    keys = _curve_keys(fold)
    several = len(keys) > 1
    width = WINDOW_WIDTH * _omega_step(omega, None if scan is None else np.asarray(scan.data["omega"], dtype=float))
    single = hysteresis is not None and np.asarray(hysteresis.data["omega"]).size == 1
    fig, ax = subplots(figsize=(PANEL[0] * 1.6, PANEL[1] * 1.6))
    inset = ax.inset_axes([0.40, 0.06, 0.34, 0.36]) if single else None  # below the mid-gap thresholds
    for c, key in enumerate(keys):
        name = f", {curve_name(key[0], vary, key[1])}" if several else ""
        color = COLOURS[c % len(COLOURS)]
        ax.plot(omega, fold_a[c], "-", marker=".", ms=4, lw=1.4, color=color, zorder=4,
                label=f"fold $A_f$ of the periodic state (model){name}")
        before = np.isfinite(inst[c]) & ~(inst[c] >= fold_a[c] - 1e-9)
        if before.any():
            ax.plot(omega[before], inst[c][before], "o", ms=4, mfc="none", color=color, zorder=4,
                    label=f"first loss of Floquet stability{name}")
        draw_transmission_marks(ax, fold, c, name)
        i = _match(scan, key, vary) if scan is not None else None
        if i is not None:
            w2, y = _scan_line(scan, i)
            ax.plot(w2, y, "--", marker="s", ms=3, lw=1.0, color="#0072B2" if not several else color, zorder=3,
                    label=_scan_label(scan) + name)
            thin = np.asarray(scan.data.get("thin_verdict", np.zeros_like(y)))[i] == 1
            if thin.any():
                ax.plot(w2[thin], y[thin], "o", ms=7, mfc="none", mew=0.9, color="#0072B2", zorder=5, gid="thin",
                        label=f"thin verdict of the scan ({int(thin.sum())})")
        j = _match(hysteresis, key, vary) if hysteresis is not None else None
        if j is not None and single:
            _window_bar(ax, hysteresis, j, name)
            _window_inset(inset, hysteresis, j, fold, c, scan, i)
        elif j is not None:
            _draw_windows(ax, hysteresis, j, width, name)
    a_s = np.asarray(fold.data["threshold_As"], dtype=float)
    if np.isfinite(a_s).any():
        ax.plot(omega, a_s[0], "x", color="black", ms=5, mew=1.0, zorder=5, markevery=_every(omega.size),
                label=r"$A_s = 4\arctan(\lambda c/\Omega)$")
    if inset is not None:
        w0 = float(np.asarray(hysteresis.data["omega"], dtype=float)[0])
        lo, hi = inset.get_ylim()
        ax.indicate_inset((w0 - width / 2, lo, width, hi - lo), inset, edgecolor="0.5")
    ax.set_xlabel(rf"driving frequency $\Omega${fold.unit('omega')}")
    ax.set_ylabel(f"threshold amplitude $A${fold.unit('fold_amplitude')}")
    handles, labels = ax.get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=2, fontsize=7, framealpha=0.9)
    head = "Undamped chain: the model's threshold (fold) against the protocols' (ramped scan, stairs)"
    fig.suptitle(head + notes(fold, scan, hysteresis) + "\n" + conditions(fold))
    return fig


def _every(n: int) -> int:
    """Every how many points x-marks go on a curve of n points (at most about 24: they stay marks)."""
    return max(1, -(-n // 24))


def _window_bar(ax, h: Scene, curve: int, name: str) -> None:
    """At the one frequency of a hysteresis file, at its true abscissa: one bar from the lowest downward edge to
    the highest upward edge of its stair lengths (the windows themselves: the inset)."""
    wins = hysteresis_windows(h, curve)
    w0 = float(wins[0]["omega"][0])
    ups = [float(w["up"][0]) for w in wins if math.isfinite(float(w["up"][0]))]
    downs = [float(w["down"][0]) for w in wins if math.isfinite(float(w["down"][0]))]
    if ups and downs:
        ax.plot([w0, w0], [min(downs), max(ups)], "-", lw=4, color="#CC79A7", alpha=0.8, zorder=4,
                solid_capstyle="butt", gid="window",
                label=rf"bistable window of the hysteresis stairs at $\Omega$ = {fmt(w0)} (inset: by stair length)"
                      + name)


def _window_inset(ax, h: Scene, curve: int, fold: Scene, c: int, scan: Scene | None, i: int | None) -> None:
    """The inset: each stair length's window (downward edge v to upward edge ^) against the stair length T_s (a
    log axis at the true T_s), with the fold, the scan's threshold and A_s at that frequency as lines."""
    wins = hysteresis_windows(h, curve)
    w0 = float(wins[0]["omega"][0])
    ts = np.array([w["stair_time"] for w in wins])
    up = np.array([float(w["up"][0]) for w in wins])
    down = np.array([float(w["down"][0]) for w in wins])
    for t, u, d in zip(ts, up, down):
        if math.isfinite(u) and math.isfinite(d):
            ax.plot([t, t], [d, u], "-", lw=5, color="#CC79A7", alpha=0.6, solid_capstyle="butt",
                    gid=f"window:{t:g}")
    ax.plot(ts, up, "^", ms=5, color="#CC79A7", mec="black", mew=0.5, ls="none")
    ax.plot(ts, down, "v", ms=5, color="#CC79A7", mec="black", mew=0.5, ls="none")
    for t, u, d in zip(ts, up, down):
        if not math.isfinite(d) and math.isfinite(u):
            k = int(np.argmin(np.abs(ts - t)))
            why = edge_reason(np.asarray(h.data["stair_amplitude"], dtype=float),
                              np.asarray(h.data["power"][curve, 0, k], dtype=float),
                              float(h.params.get("power_threshold", math.nan)), u, d)
            ax.annotate(textwrap.fill(why.replace("no downward edge: ", "no downward edge: "), 22), (t, u),
                        fontsize=5, ha="center", va="top", textcoords="offset points", xytext=(0, -7), color="0.3",
                        gid="reason")
    omega = np.asarray(fold.data["omega"], dtype=float)
    k = int(np.argmin(np.abs(omega - w0)))
    lines = []
    if math.isclose(omega[k], w0, abs_tol=1e-9):
        lines.append((float(fold.data["fold_amplitude"][c, k]), "-", "black", "$A_f$"))
        lines.append((float(fold.data["threshold_As"][c, k]), ":", "black", "$A_s$"))
    if scan is not None and i is not None:
        w2, y = _scan_line(scan, i)
        m = int(np.argmin(np.abs(w2 - w0)))
        if math.isclose(w2[m], w0, abs_tol=1e-9):
            lines.append((float(y[m]), "--", "#0072B2", "scan"))
    for v, ls, color, text in lines:
        if math.isfinite(v):
            ax.axhline(v, ls=ls, lw=1.0, color=color)
            ax.annotate(f"{text} {fmt(v, 4)}", (1.0, v), xycoords=("axes fraction", "data"), fontsize=6,
                        ha="right", va="bottom", color=color)
    ax.set_xscale("log")
    ax.set_xticks(ts)
    ax.set_xticklabels([fmt(t) for t in ts])
    ax.minorticks_off()
    ax.set_xlim(ts.min() / 1.6, ts.max() * 1.6)
    ax.tick_params(labelsize=6)
    ax.set_xlabel("stair length $T_s$", fontsize=6, labelpad=1)
    ax.set_title(rf"$\Omega$ = {fmt(w0)}: window of each stair length, v down to ^ up", fontsize=6.5, pad=2)


def summary_thresholds(fold: Scene, scan: Scene | None = None, hysteresis: Scene | None = None) -> list[str]:
    """The numbers the chart shows at the hysteresis file's frequencies (or about seven of the fold's): fold, first
    loss of stability, scan threshold, edges, A_s."""
    omega = np.asarray(fold.data["omega"], dtype=float)
    vary = vary_of(fold)
    if hysteresis is not None:
        wanted = np.asarray(hysteresis.data["omega"], dtype=float)
    else:
        wanted = omega[np.unique(np.linspace(0, omega.size - 1, min(7, omega.size)).astype(int))]
    lines = []
    for c, key in enumerate(_curve_keys(fold)):
        parts = []
        for w0 in wanted:
            k = int(np.argmin(np.abs(omega - w0)))
            on = math.isclose(omega[k], w0, abs_tol=1e-9)
            part = f"Omega {fmt(w0, 3)}: " + (f"A_f = {fmt(float(fold.data['fold_amplitude'][c, k]), 6)}" if on
                                              else "no fold computed")
            ai = float(fold.data["instability_amplitude"][c, k])
            if on and math.isfinite(ai):
                part += f", unstable from {fmt(ai, 5)} ({KINDS.get(int(fold.data['instability_type'][c, k]), '?')})"
            if scan is not None and (i := _match(scan, key, vary)) is not None:
                w2, y = _scan_line(scan, i)
                j = int(np.argmin(np.abs(w2 - w0)))
                if math.isclose(w2[j], w0, abs_tol=1e-9):
                    part += f", scan {fmt(y[j], 4)}"
            if hysteresis is not None and (j := _match(hysteresis, key, vary)) is not None:
                for w in hysteresis_windows(hysteresis, j):
                    m = int(np.argmin(np.abs(w["omega"] - w0)))
                    part += f", T_s {fmt(w['stair_time'])}: up {fmt(w['up'][m], 4)} down {fmt(w['down'][m], 4)}"
            if on:
                part += f", A_s = {fmt(float(fold.data['threshold_As'][c, k]), 4)}"
            parts.append(part)
        lines.append(f"  {curve_name(key[0], vary, key[1])}: " + "; ".join(parts))
    return lines


# ------------------------------------------------------------------------------------------------ ramp times


def ramp_points(scans: list[Scene], curve: int = 0) -> dict:
    """{ramp, threshold, resolution, t_final, omega} of the scans at their first frequency, sorted by ramp time.
    PlotError when a file is not a bifurcation scene, or the files are not at one frequency."""
    rows = []
    for s in scans:
        if s.scene != "bifurcation":
            raise PlotError(s.path, f"scene is '{s.scene}', not 'bifurcation' (a scan at one ramp time)")
        w = np.asarray(s.data["omega"], dtype=float)
        ok = int(np.asarray(s.data["status"])[curve, 0]) in (0, 1)
        thr = float(s.data["threshold"][curve, 0]) if ok else math.nan
        rows.append((float(s.params.get("ramp_time", math.nan)), thr, float(s.params.get("resolution", math.nan)),
                     float(s.params.get("t_final", math.nan)), float(w[0]), s.path))
    omegas = {round(r[4], 9) for r in rows}
    if len(omegas) > 1:
        raise PlotError(rows[0][5], f"the ramp scans are at several frequencies ({', '.join(map(str, omegas))})")
    rows.sort()
    cols = list(zip(*rows))
    return {"ramp": np.array(cols[0]), "threshold": np.array(cols[1]), "resolution": np.array(cols[2]),
            "t_final": np.array(cols[3]), "omega": rows[0][4]}


def _by_shooting(fold: Scene) -> None:
    """PlotError for a fold line by harmonic balance: these charts draw the shooting scene's loss of stability and
    transmission, which that file has not (its own figures: figures.harmonic)."""
    if fold.solver == "harmonic_balance":
        raise PlotError(fold.path, "a fold line by harmonic balance (no stability or transmission datasets): "
                                   "drawn by itself (make_figures' fold_hb_sg), not on this chart")


def _fold_at(fold: Scene, w0: float, curve: int = 0) -> tuple[float, float, int, float]:
    """(A_f, first loss of stability, its type, A_s) of a continuation file at the frequency nearest w0; PlotError
    when none is within 1e-9 or the file is by harmonic balance."""
    _by_shooting(fold)
    omega = np.asarray(fold.data["omega"], dtype=float)
    k = int(np.argmin(np.abs(omega - w0)))
    if not math.isclose(omega[k], w0, abs_tol=1e-9):
        raise PlotError(fold.path, f"no fold at Omega = {fmt(w0)} (the file has Omega = {fmt(omega.min())} .. "
                                   f"{fmt(omega.max())})")
    return (float(fold.data["fold_amplitude"][curve, k]), float(fold.data["instability_amplitude"][curve, k]),
            int(fold.data["instability_type"][curve, k]), float(fold.data["threshold_As"][curve, k]))


@styled
def draw_ramp(scans: list[Scene], fold: Scene | None = None):
    """Scan threshold vs ramp time at one frequency next to the fold (module docstring)."""
    if fold is not None:
        _by_shooting(fold)
    r = ramp_points(scans)
    fig, ax = subplots(figsize=(PANEL[0] * 1.3, PANEL[1] * 1.25))
    thr, res = r["threshold"], r["resolution"]
    ax.errorbar(r["ramp"], thr, yerr=[res, np.zeros_like(res)], fmt="s-", ms=4, lw=1.0, capsize=3,
                color="#0072B2", label="ramped scan: first transmitting $A$ (bar: the bracket below it)")
    for x, y in zip(r["ramp"], thr):
        if math.isfinite(y):
            ax.annotate(fmt(y, 4), (x, y), textcoords="offset points", xytext=(0, 6), ha="center", fontsize=7)
    if fold is not None:
        af, ai, kind, a_s = _fold_at(fold, r["omega"])
        if math.isfinite(af):
            ax.axhline(af, color="black", lw=1.4, label=rf"fold $A_f$ = {fmt(af, 7)} (model, no ramp)", gid="fold")
        if math.isfinite(ai) and ai < af - 1e-9:
            ax.axhline(ai, color="black", lw=0.8, ls=":",
                       label=f"first loss of Floquet stability = {fmt(ai, 6)} ({KINDS.get(kind, kind)})")
        if math.isfinite(a_s):
            ax.axhline(a_s, color="0.5", lw=0.8, ls="-.", label=rf"$A_s$ = {fmt(a_s, 4)} (continuum)")
    ax.set_xscale("log")
    ax.set_xticks(r["ramp"])
    ax.set_xticklabels([fmt(x) for x in r["ramp"]])
    ax.minorticks_off()
    ax.set_xlabel("ramp time (the drive's amplitude rises linearly from 0 to $A$ over it)")
    ax.set_ylabel(f"threshold amplitude $A${scans[0].unit('threshold')}")
    ax.legend(loc="lower right", fontsize=7, framealpha=0.9)
    s = scans[0]
    cond = conditions(s).split(r", $T$")[0]
    after = {fmt(float(t - x)) for t, x in zip(r["t_final"], r["ramp"])}
    cond += r", $T$ = ramp + " + "/".join(sorted(after)) + rf", $\Delta t$ = {fmt(s.params.get('dt'))}"
    fig.suptitle(rf"Ramp time: the scan threshold at $\Omega$ = {fmt(r['omega'])} against the ramp, next to the fold"
                 + notes(*scans, fold) + "\n" + cond)
    return fig


def summary_ramp(scans: list[Scene], fold: Scene | None = None) -> list[str]:
    """Per ramp time: the scan threshold and its distance to the fold."""
    r = ramp_points(scans)
    af = _fold_at(fold, r["omega"])[0] if fold is not None else math.nan
    parts = [f"ramp {fmt(x)}: {fmt(y, 4)}" + (f" ({y - af:+.4f})" if math.isfinite(af) else "")
             for x, y in zip(r["ramp"], r["threshold"])]
    head = f"  Omega {fmt(r['omega'])}: " + (f"fold A_f = {fmt(af, 8)}; " if math.isfinite(af) else "")
    return [head + "scan threshold (minus the fold) by ramp time: " + ", ".join(parts)]
