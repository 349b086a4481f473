"""Figures of the continuation scene solved by harmonic balance (root attribute `solver = "harmonic_balance"`,
src/scenes/supratrans_fold_hb.f90): the fold of the ODE's driven periodic state, with no dt.

- the fold line (input/fold_hb_sg.nml): A_f(Omega) of each curve over the scan thresholds of a bifurcation file
  and the shooting scene's fold line when given, A_s = 4 arctan(lambda c / Omega) as x-marks; below it, on a
  log scale, how far each fold is converged: the truncation estimate in the number K of odd harmonics, the
  closure of one rk8 period from the fold's state, the absorber spread when computed, with K on its own axis;
- the continuum limit (input/fold_continuum.nml, a file with /continuum): one column per frequency, the fold
  against 1/c^2 at each coupling c of `c_values`, the Richardson line of the two largest c and its limit at
  1/c^2 = 0 with the file's error estimate, A_s of each c and of the continuum (4 arccos Omega, massless) as
  references; below, the same folds zoomed, the absorber spread of the base chain's fold as its error bar (how
  far the finite chain's fold is from the semi-infinite chain's).
"""
from __future__ import annotations

import math

import numpy as np

from ..reader import Scene
from ..style import fmt, styled, subplots
from .common import PANEL, conditions, curve_name, styles, title, vary_of

#: Outside the legend's axes: the legends sit right of the panels, off the data.
OUTSIDE = {"loc": "upper left", "bbox_to_anchor": (1.02, 1.0), "borderaxespad": 0.0, "framealpha": 0.9}


def is_harmonic_balance(s: Scene) -> bool:
    """Whether `s` is a continuation file written by the harmonic-balance solver."""
    return s.scene == "continuation" and s.solver == "harmonic_balance"


def _curves(s: Scene) -> tuple[list[str], np.ndarray, str]:
    pots = [str(x) for x in s.data["curves/potential"]]
    return pots, np.asarray(s.data["curves/value"], dtype=float), vary_of(s)


def _m2(s: Scene, c: int) -> float:
    """m^2 of curve `c` (/curves/m2, else the varied value or the /parameters value)."""
    if "curves/m2" in s.data:
        return float(s.data["curves/m2"][c])
    if vary_of(s) == "m2":
        return float(s.data["curves/value"][c])
    return float(s.params.get("m2", 0.0))


def threshold_as(c: float, omega: float, m2: float = 0.0) -> float:
    """A_s = 4 arctan(lambda c / Omega) of the chain of coupling c, lambda = acosh(1 + (1 + m^2 - Omega^2) / (2 c^2))
    (src/physics/supratrans_chain.f90); NaN outside the gap."""
    x = 1.0 + (1.0 + m2 - omega**2) / (2.0 * c**2)
    return 4.0 * math.atan(math.acosh(x) * c / omega) if x > 1.0 else float("nan")


def threshold_as_continuum(omega: float, m2: float = 0.0) -> float:
    """The limit c -> infinity of `threshold_as`: 4 arctan(sqrt(1 + m^2 - Omega^2) / Omega), 4 arccos(Omega) for
    m^2 = 0; NaN outside the gap."""
    q = 1.0 + m2 - omega**2
    return 4.0 * math.atan(math.sqrt(q) / omega) if q > 0.0 else float("nan")


def _positive(x: np.ndarray) -> np.ndarray:
    """`x` with the values a log axis cannot show (zero, negative, NaN) as NaN."""
    x = np.asarray(x, dtype=float)
    return np.where(np.isfinite(x) & (x > 0), x, np.nan)


# ------------------------------------------------------------------------------------------------ the fold line


@styled
def draw_fold_line_hb(s: Scene, scan: Scene | None = None, shooting: Scene | None = None):
    """The fold line by harmonic balance and its convergence (see the module docstring). `scan`: a bifurcation
    file whose thresholds are drawn as points; `shooting`: a continuation file by shooting whose fold line is
    drawn beside."""
    pots, values, vary = _curves(s)
    omega = np.asarray(s.data["omega"], dtype=float)
    fold = np.asarray(s.data["fold_amplitude"], dtype=float)
    st = styles(values, vary, pots)
    fig, (ax, axc) = subplots(2, 1, figsize=(PANEL[0] * 1.75, PANEL[1] * 1.9), sharex=True,
                              gridspec_kw={"height_ratios": [1.5, 1.0]})
    several = len(pots) > 1
    for c in range(len(pots)):
        name = f", {curve_name(pots[c], vary, values[c])}" if several else ""
        ax.plot(omega, fold[c], label=f"fold $A_f$ by harmonic balance{name}",
                **{**st[c], "marker": ".", "markersize": 3}, gid=f"fold_hb:{c}")
    if shooting is not None:
        w = np.asarray(shooting.data["omega"], dtype=float)
        f = np.asarray(shooting.data["fold_amplitude"], dtype=float)
        dt = fmt(shooting.params.get("dt"))
        note = f", {w.size} frequencies" + (f", {shooting.partial_note()}" if shooting.partial else "")
        for c in range(f.shape[0]):
            ax.plot(w, f[c], "--", color="#E69F00", lw=1.0, marker="o", ms=3, mfc="none", gid=f"fold_shooting:{c}",
                    label=rf"fold by shooting ({shooting.params.get('method', 'newton')}, $\Delta t$ = {dt}{note})"
                    if c == 0 else None)
    if scan is not None:
        thr = np.asarray(scan.data["threshold"], dtype=float)
        status = np.asarray(scan.data["status"])
        w2 = np.asarray(scan.data["omega"], dtype=float)
        for c in range(thr.shape[0]):
            ax.plot(w2, np.where(np.isin(status[c], (0, 1)), thr[c], np.nan), "s", ms=3.5, mfc="none", mew=0.8,
                    color="0.4", gid=f"scan:{c}", label="ramped scan threshold (time domain)" if c == 0 else None)
    a_s = np.asarray(s.data["threshold_As"], dtype=float)
    if np.isfinite(a_s).any():
        ax.plot(omega, a_s[0], "x", color="black", ms=4, gid="A_s", label=r"$A_s = 4\arctan(\lambda c/\Omega)$")
    ax.set_ylabel(f"driving amplitude $A${s.unit('fold_amplitude')}")
    ax.set_title("fold of the driven periodic state against the thresholds of the time domain")
    ax.legend(fontsize=7, **OUTSIDE)
    _draw_convergence(s, axc, st)
    axc.set_xlabel(rf"driving frequency $\Omega${s.unit('omega')}")
    fig.suptitle(title(s, "the model's threshold by harmonic balance (no time step)") + "\n" + _conditions(s))
    return fig


def _conditions(s: Scene) -> str:
    """The fixed parameters of `conditions`, the time step named for what it is here (the rk8 check of each fold;
    the fold itself has none), and the harmonics' tolerance."""
    method = f", {s.params.get('method', 'newton')}, " + rf"$\Delta t$ = {fmt(s.params.get('dt'))}"
    text = conditions(s).removesuffix(method)
    return (text + rf", K grown until the fold moves by < {fmt(s.params.get('harmonics_tol'), 2)}, rk8 check "
            rf"with $\Delta t$ = {fmt(s.params.get('dt'))}")


def _draw_convergence(s: Scene, ax, st: list[dict]) -> None:
    """On `ax` (log scale) the truncation estimate in K, the rk8 period's closure and the absorber spread of each
    curve; on a twin axis K."""
    omega = np.asarray(s.data["omega"], dtype=float)
    several = len(st) > 1
    quantities = [("convergence/harmonics_error", "truncation estimate $|A_f(K) - A_f(K')|$", "o", "#0072B2"),
                  ("fold_period_closure", "closure of one rk8 period from the fold's state", "s", "#D55E00"),
                  ("convergence/absorber_spread", "absorber spread (fold's distance to the semi-infinite chain)",
                   "^", "#009E73")]
    for c in range(len(st)):
        suffix = f" (curve {c + 1})" if several else ""
        for name, label, marker, colour in quantities:
            if name not in s.data:
                continue
            y = _positive(np.asarray(s.data[name], dtype=float)[c])
            if np.isfinite(y).any():
                ax.plot(omega, y, marker=marker, ls="-", lw=0.8, ms=3, mfc="none", color=colour,
                        label=label + suffix, gid=f"{name}:{c}")
    tol = float(s.params.get("harmonics_tol", float("nan")))
    if math.isfinite(tol) and tol > 0:
        ax.axhline(tol, color="#0072B2", ls="--", lw=0.8, gid="harmonics_tol",
                   label=f"tolerance in K (harmonics_tol = {fmt(tol, 2)})")
    ax.set_yscale("log")
    ax.set_ylabel(f"error{s.unit('fold_amplitude')}")
    ax.set_title("how far each fold is converged, and the number K of odd harmonics it took")
    axk = ax.twinx()
    k = np.asarray(s.data["harmonics"], dtype=float)
    for c in range(k.shape[0]):
        kc = np.where(k[c] > 0, k[c], np.nan)
        axk.step(omega, kc, where="mid", color="0.3", lw=1.0, gid=f"harmonics:{c}",
                 label="harmonics $K$ (right axis)" if c == 0 else None)
    axk.set_ylabel("odd harmonics $K$")
    axk.grid(False)
    if np.isfinite(np.where(k > 0, k, np.nan)).any():
        axk.set_ylim(0, 1.1 * np.nanmax(np.where(k > 0, k, np.nan)))
    handles, labels = ax.get_legend_handles_labels()
    h2, l2 = axk.get_legend_handles_labels()
    ax.legend(handles + h2, labels + l2, fontsize=7, **{**OUTSIDE, "bbox_to_anchor": (1.09, 1.0)})


# ------------------------------------------------------------------------------------------------ the continuum


def has_continuum(s: Scene) -> bool:
    """Whether the file holds the folds at several couplings c (/continuum)."""
    return "continuum/folds" in s.data and "continuum/c" in s.data


@styled
def draw_continuum(s: Scene):
    """The fold against 1/c^2 per frequency with its limit c -> infinity (see the module docstring)."""
    pots, values, vary = _curves(s)
    omega = np.asarray(s.data["omega"], dtype=float)
    cs = np.asarray(s.data["continuum/c"], dtype=float)
    folds = np.asarray(s.data["continuum/folds"], dtype=float)
    limit = np.asarray(s.data.get("continuum/fold", np.full(folds.shape[:2], np.nan)), dtype=float)
    error = np.asarray(s.data.get("continuum/error_estimate", np.full(folds.shape[:2], np.nan)), dtype=float)
    spread = np.asarray(s.data.get("convergence/absorber_spread", np.full(folds.shape[:2], np.nan)), dtype=float)
    base = np.asarray(s.data["fold_amplitude"], dtype=float)
    c0 = float(s.params.get("c", cs[0]))
    x = 1.0 / cs**2
    st = styles(values, vary, pots)
    ncol = omega.size
    fig, axes = subplots(2, ncol, figsize=(max(PANEL[0] * 0.85 * ncol, PANEL[0]) + 2.2, PANEL[1] * 1.9),
                         squeeze=False, gridspec_kw={"height_ratios": [1.0, 1.2]})
    several = len(pots) > 1
    for w in range(ncol):
        top, zoom = axes[0, w], axes[1, w]
        for c in range(len(pots)):
            colour = st[c].get("color")
            name = f", {curve_name(pots[c], vary, values[c])}" if several else ""
            m2 = _m2(s, c)
            for ax in (top, zoom):
                ax.plot(x, folds[c, w], "o", color=colour, ms=4, gid=f"folds:{c}",
                        label=f"fold $A_f$ at $c$ = {', '.join(fmt(v) for v in cs)}{name}")
                if math.isfinite(limit[c, w]) and cs.size >= 2:
                    ax.plot([0.0, x[-2]], [limit[c, w], folds[c, w, -2]], ":", color=colour, lw=1.0,
                            gid=f"richardson:{c}", label=r"Richardson line in $1/c^2$ of the two largest $c$")
                    ax.errorbar([0.0], [limit[c, w]], yerr=[np.nan_to_num(error[c, w])], fmt="D", color=colour,
                                ms=5, capsize=3, gid=f"limit:{c}",
                                label=r"limit $c \to \infty$ ± its error estimate")
            a_c = [threshold_as(v, float(omega[w]), m2) for v in cs]
            a_inf = threshold_as_continuum(float(omega[w]), m2)
            top.plot(x, a_c, "x", color="0.35", ms=5, gid=f"A_s:{c}", label=r"$A_s = 4\arctan(\lambda c/\Omega)$")
            top.plot([0.0], [a_inf], "*", color="0.35", ms=8, gid=f"A_s_continuum:{c}",
                     label=(r"$A_s = 4\arccos\Omega$" if m2 == 0 else r"$A_s$") + r" of the continuum")
            if math.isfinite(spread[c, w]) and math.isfinite(base[c, w]):
                zoom.errorbar([1.0 / c0**2], [base[c, w]], yerr=[spread[c, w]], fmt="none", ecolor="#009E73",
                              elinewidth=1.2, capsize=4, gid=f"absorber_spread:{c}",
                              label=rf"absorber spread of the $c$ = {fmt(c0)} fold (to the semi-infinite chain)")
            for i, (v, xv, yv) in enumerate(zip(cs[::-1], x[::-1], folds[c, w, ::-1])):
                if c == 0 and math.isfinite(yv):  # from the largest c, alternately above and below
                    zoom.annotate(f"c = {fmt(v)}", (xv, yv), textcoords="offset points", fontsize=7,
                                  xytext=(4, 4) if i % 2 else (4, -10))
            if c == 0 and math.isfinite(limit[c, w]):
                zoom.text(0.6, 0.04, rf"limit {limit[c, w]:.{decimals(error[c, w])}f} ± {fmt(error[c, w], 2)}",
                          transform=zoom.transAxes, ha="center", va="bottom", fontsize=7)
                top.text(0.6, 0.5, rf"limit $-$ $A_s(c \to \infty)$ = {fmt(limit[c, w] - a_inf, 3)}",
                         transform=top.transAxes, ha="center", va="center", fontsize=8)
        top.set_title(rf"$\Omega$ = {fmt(float(omega[w]))}: fold and $A_s$")
        zoom.set_title("the fold's approach to its limit (zoom)")
        zoom.set_xlabel(r"$1/c^2$")
        zoom.margins(y=0.12)  # room for the names of the points at the ends
        for ax in (top, zoom):
            ax.set_xlim(-0.004, 1.08 * float(np.nanmax(x)))
            ax.ticklabel_format(axis="y", useOffset=False)
        if w == 0:
            top.set_ylabel(f"amplitude $A${s.unit('fold_amplitude')}")
            zoom.set_ylabel(f"fold $A_f${s.unit('fold_amplitude')}")
    handles, labels = {}, {}
    for ax in (axes[0, -1], axes[1, -1]):
        for h, lab in zip(*ax.get_legend_handles_labels()):
            if lab not in labels:
                labels[lab] = h
    axes[0, -1].legend(list(labels.values()), list(labels), fontsize=7, **OUTSIDE)
    fig.suptitle(title(s, r"the fold in the continuum limit $c \to \infty$ (N, N0 and the absorber scaled with c)")
                 + "\n" + _conditions(s).replace(rf"$c$ = {fmt(s.params.get('c'))}, $N$ = {fmt(s.params.get('n'))}",
                                                  rf"$N$ = {fmt(s.params.get('n'))} at $c$ = {fmt(s.params.get('c'))}"))
    return fig


# ------------------------------------------------------------------------------------------------ text


def decimals(uncertainty: float, most: int = 10) -> int:
    """The decimals a value uncertain by `uncertainty` is worth: those above its first significant digit (at most
    `most`; `most` when the uncertainty is zero or unknown)."""
    if not math.isfinite(uncertainty) or uncertainty <= 0:
        return most
    return max(0, min(most, -math.floor(math.log10(uncertainty))))


def summary_harmonic_balance(s: Scene, full: bool = False) -> list[str]:
    """Per curve and frequency (about seven unless `full`): the fold, K, the truncation estimate, the rk8 closure,
    the absorber's spread with the semi-infinite chain's fold (no more digits than the spread allows), A_s; with
    /continuum, the folds at each c and their limit."""
    pots, values, vary = _curves(s)
    omega = np.asarray(s.data["omega"], dtype=float)
    cols = range(omega.size) if full or omega.size <= 7 else np.unique(np.linspace(0, omega.size - 1, 7).astype(int))
    lines = []

    def get(name: str, c: int, w: int) -> float:
        return float(s.data[name][c, w]) if name in s.data else float("nan")

    for c in range(len(pots)):
        parts = []
        for w in cols:
            af = get("fold_amplitude", c, w)
            status = int(s.data["status"][c, w])
            if not math.isfinite(af):
                parts.append(f"Omega {fmt(omega[w], 3)}: no fold (status {status})")
                continue
            text = (f"Omega {fmt(omega[w], 3)}: A_f = {af:.8f} (K {int(s.data['harmonics'][c, w])}, truncation "
                    f"{fmt(get('convergence/harmonics_error', c, w), 2)}, rk8 closure "
                    f"{fmt(get('fold_period_closure', c, w), 2)})")
            spread, semi = get("convergence/absorber_spread", c, w), get("convergence/fold_semi_infinite", c, w)
            if math.isfinite(spread) and math.isfinite(semi):
                text += (f", absorber spread {fmt(spread, 2)}: semi-infinite chain "
                         f"{semi:.{decimals(spread)}f}")
            if "continuum/folds" in s.data:
                cs = np.asarray(s.data["continuum/c"], dtype=float)
                each = ", ".join(f"{fmt(v)}: {float(f):.6f}" for v, f in zip(cs, s.data["continuum/folds"][c, w]))
                lim, err = get("continuum/fold", c, w), get("continuum/error_estimate", c, w)
                text += (f", c {each}; limit c -> inf {lim:.{decimals(err)}f} (+- {fmt(err, 2)}), "
                         f"A_s(inf) = {fmt(threshold_as_continuum(float(omega[w]), _m2(s, c)), 5)}")
            parts.append(text + f", A_s = {fmt(get('threshold_As', c, w), 4)}")
        lines.append(f"  {curve_name(pots[c], vary, values[c])} (harmonic balance): " + "; ".join(parts))
    return lines
