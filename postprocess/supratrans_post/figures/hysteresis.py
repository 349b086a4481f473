"""Figure of the scene `hysteresis`: the two edges of the bistable window as a slow protocol sees them.

- one frequency: the mean power of each stair (through the bond beyond the detector) vs its amplitude, the way up
  solid with filled marks, the way down dashed with open marks, one colour per stair length; the bistable window
  between the downward and the upward edge shaded; the transmitting criterion (power_threshold) as a dotted line;
- several frequencies: the upward edge (solid) and the downward edge (dashed) of each stair length over the
  frequency, the window between them shaded, and A_s = 4 arctan(lambda c / Omega) as x-marks.
"""
from __future__ import annotations

import math

import numpy as np

from ..reader import Scene
from ..style import fmt, styled, subplots
from .common import COLOURS, PANEL, conditions, curve_name, title, vary_of


def _curves(s: Scene) -> tuple[list[str], np.ndarray, str]:
    pots = [str(x) for x in s.data["curves/potential"]]
    return pots, np.asarray(s.data["curves/value"], dtype=float), vary_of(s)


@styled
def draw_hysteresis(s: Scene):
    """Power vs amplitude up and down (one frequency) or the edges over the frequency, see the module docstring."""
    omega = np.asarray(s.data["omega"], dtype=float)
    if omega.size == 1:
        return _draw_stairs(s)
    return _draw_edges(s)


def edge_reason(levels: np.ndarray, power: np.ndarray, threshold: float, up: float, down: float) -> str:
    """Why an edge of a stair length is missing (NaN), from its stairs' mean powers: '' when both are found."""
    k = levels.size // 2
    if not math.isfinite(up):
        top = float(levels[k])
        return f"no upward edge: no stair transmitted on the way up (to A = {fmt(top, 4)})"
    if not math.isfinite(down):
        low = float(levels[-1])
        if math.isfinite(threshold) and math.isfinite(float(power[-1])) and float(power[-1]) > threshold:
            return (f"no downward edge: still transmitting at the last stair down (A = {fmt(low, 4)}); "
                    "the edge lies below the stairs")
        return "no downward edge: the way down left transmission at no stair the criterion could place"
    return ""


def _draw_stairs(s: Scene):
    pots, values, vary = _curves(s)
    lengths = np.asarray(s.data["stair_time"], dtype=float)
    levels = np.asarray(s.data["stair_amplitude"], dtype=float)
    k = levels.size // 2
    thr = float(s.params.get("power_threshold", math.nan))
    fig, axes = subplots(1, len(pots), figsize=(PANEL[0] * 1.5 * len(pots), PANEL[1] * 1.35), squeeze=False)
    for c, ax in enumerate(axes[0]):
        reasons = []
        for i, ts in enumerate(lengths):
            color = COLOURS[(i + 1) % len(COLOURS)]
            p = np.asarray(s.data["power"][c, 0, i], dtype=float)
            ax.plot(levels[: k + 1], p[: k + 1], "-o", ms=3, color=color, label=f"$T_s$ = {fmt(ts)}: up")
            ax.plot(levels[k:], p[k:], "--o", ms=3, mfc="none", color=color, label="down")
            up = float(s.data["upward_threshold"][c, 0, i])
            down = float(s.data["downward_threshold"][c, 0, i])
            # each stair length's window its own bar above the data (not shaded areas that blend)
            y = 1.0 - 0.045 * (i + 1)
            if math.isfinite(up) and math.isfinite(down) and up > down:
                ax.plot([down, up], [y, y], "-", lw=5, color=color, solid_capstyle="butt", alpha=0.8,
                        transform=ax.get_xaxis_transform(), gid=f"window:{ts:g}", clip_on=False,
                        label=f"window {fmt(down, 4)} .. {fmt(up, 4)}")
            why = edge_reason(levels, p, thr, up, down)
            if why:
                reasons.append((color, f"$T_s$ = {fmt(ts)}: {why}"))
        for j, (color, why) in enumerate(reasons):
            ax.text(0.01, 0.80 - 0.06 * j, why, transform=ax.transAxes, fontsize=7, color=color, va="top",
                    gid="reason")
        if math.isfinite(thr):
            ax.axhline(thr, color="0.4", lw=0.8, ls=":", label=f"transmits above {fmt(thr)}")
        a_s = s.data.get("threshold_As")
        if a_s is not None and math.isfinite(float(a_s[c, 0])):
            ax.axvline(float(a_s[c, 0]), color="0.5", lw=0.8, ls="-.", label=rf"$A_s$ = {fmt(float(a_s[c, 0]), 4)}")
        ax.set_ylim(top=ax.get_ylim()[1] * 1.25)  # room for the window bars above the data
        ax.set_xlabel(f"stair amplitude $A${s.unit('stair_amplitude')}")
        ax.set_ylabel("mean power beyond the detector" + s.unit("power") + " (linear)")
        ax.set_title(curve_name(pots[c], vary, values[c]), fontsize=9)
    fig.legend(*axes[0][0].get_legend_handles_labels(), loc="outside right center", fontsize=7, framealpha=0.9)
    w = float(s.data["omega"][0])
    fig.suptitle(title(s, rf"stairs up and down at $\Omega$ = {fmt(w, 4)}") + "\n" + conditions(s))
    return fig


def _draw_edges(s: Scene):
    pots, values, vary = _curves(s)
    omega = np.asarray(s.data["omega"], dtype=float)
    lengths = np.asarray(s.data["stair_time"], dtype=float)
    fig, ax = subplots(figsize=(PANEL[0] * 1.35, PANEL[1] * 1.3))
    for c in range(len(pots)):
        name = curve_name(pots[c], vary, values[c])
        for i, ts in enumerate(lengths):
            color = COLOURS[(c * len(lengths) + i + 1) % len(COLOURS)]
            up = np.asarray(s.data["upward_threshold"][c, :, i], dtype=float)
            down = np.asarray(s.data["downward_threshold"][c, :, i], dtype=float)
            ax.plot(omega, up, "-", marker=".", ms=3, color=color, label=f"up, $T_s$ = {fmt(ts)}, {name}")
            ax.plot(omega, down, "--", marker=".", ms=3, color=color, label="down")
            ax.fill_between(omega, down, up, where=np.isfinite(up) & np.isfinite(down), color=color, alpha=0.12,
                            lw=0)
    a_s = s.data.get("threshold_As")
    if a_s is not None and np.isfinite(np.asarray(a_s, dtype=float)).any():
        ax.plot(omega, np.asarray(a_s, dtype=float)[0], "x", color="black", ms=4,
                label=r"$A_s = 4\arctan(\lambda c/\Omega)$")
    ax.set_xlabel(rf"driving frequency $\Omega${s.unit('omega')}")
    ax.set_ylabel(f"amplitude $A${s.unit('upward_threshold')}")
    ax.legend(loc="best", fontsize=6, framealpha=0.85)
    fig.suptitle(title(s, "upward and downward edges of supratransmission vs driving frequency") + "\n"
                 + conditions(s))
    return fig


def summary_hysteresis(s: Scene, full: bool = False) -> list[str]:
    """Per curve and frequency (about seven of them unless `full`): each stair length's upward and downward edge
    and window, and the spreads of the edges over the stair lengths."""
    pots, values, vary = _curves(s)
    omega = np.asarray(s.data["omega"], dtype=float)
    lengths = np.asarray(s.data["stair_time"], dtype=float)
    cols = range(omega.size) if full or omega.size <= 7 else np.unique(np.linspace(0, omega.size - 1, 7).astype(int))
    lines = []
    for c in range(len(pots)):
        parts = []
        for w in cols:
            edges = []
            for i, ts in enumerate(lengths):
                up = float(s.data["upward_threshold"][c, w, i])
                down = float(s.data["downward_threshold"][c, w, i])
                edges.append(f"T_s {fmt(ts)}: up {fmt(up, 4)}, down {fmt(down, 4)}")
            spread = (f"spread up {fmt(float(s.data['upward_spread'][c, w]), 3)}, "
                      f"down {fmt(float(s.data['downward_spread'][c, w]), 3)}")
            parts.append(f"Omega {fmt(omega[w], 3)}: " + ", ".join(edges) + f" ({spread})")
        lines.append(f"  {curve_name(pots[c], vary, values[c])}: " + "; ".join(parts))
    return lines
