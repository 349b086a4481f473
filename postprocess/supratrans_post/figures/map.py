"""Figure of the scene `map` (Fig. 11): total energy over driving frequency x amplitude, one panel per curve, with
the continuum-limit threshold A_s(Omega) and the first transmitting amplitude of each frequency over it."""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..reader import Scene
from ..style import fmt, styled, subplots
from .common import (ENERGIES, PANEL, SYMBOLS, columns, conditions, failed_note, family_label, first_transmitting,
                     potential_title, title, vary_of)
from .common import energy as energy_of


@styled
def draw_map(s: Scene, surface: bool = False, energy: str = "injected"):
    """Total energy over driving frequency x amplitude, one panel per curve, log colour scale, with the
    continuum-limit threshold A_s(Omega) (x-marks and line) and the first transmitting amplitude of each
    frequency (white dots) drawn over it. Runs outside the band gap or not done are gaps (grey). `surface`: 3-D
    surfaces of log10 E instead, like the paper. `energy`: another energy of the file (ENERGIES)."""
    from matplotlib.colors import LogNorm  # noqa: PLC0415

    omega = np.asarray(s.data["omega"], dtype=float)
    amp = np.asarray(s.data["amplitude"], dtype=float)
    e_all, elabel = energy_of(s, energy)
    status = s.data["runs/status"]
    trans = s.data["runs/transmitting"]
    a_s = np.asarray(s.data["threshold_As"], dtype=float)
    pots = [str(x) for x in s.data["curves/potential"]]
    values = np.asarray(s.data["curves/value"], dtype=float)
    vary = vary_of(s)
    ncurve = len(pots)
    good = e_all[(status == 0) & np.isfinite(e_all) & (e_all > 0)]
    vmin, vmax = (float(good.min()), float(good.max())) if good.size else (1.0, 10.0)
    if vmax <= vmin:
        vmax = vmin * 10
    norm = LogNorm(vmin=vmin, vmax=vmax)
    kw = {"subplot_kw": {"projection": "3d"}} if surface else {}
    fig, axes = subplots(1, ncurve, figsize=(PANEL[0] * ncurve, PANEL[1] * 1.15), squeeze=False, **kw)
    mesh = None
    for c, ax in enumerate(axes[0]):
        e = np.where(status[c] == 0, e_all[c], np.nan).T  # (namp, nomega)
        name = potential_title(pots[c])
        if vary in SYMBOLS and math.isfinite(values[c]):
            name += f", {family_label(vary, values[c])}"
        if surface:
            _surface(ax, omega, amp, e, a_s[c], vmin)
        else:
            mesh = _colour_map(ax, omega, amp, e, a_s[c], trans[c], status[c], norm)
        ax.set_title(name)
        ax.set_xlabel(rf"driving frequency $\Omega${s.unit('omega')}")
        ax.set_ylabel(f"driving amplitude $A${s.unit('amplitude')}")
        note = failed_note(status[c])
        if note:
            ax.text2D(0.01, 0.01, note, transform=ax.transAxes) if surface else ax.text(
                0.01, 0.01, note, transform=ax.transAxes, fontsize=7, color="#D55E00")
    if mesh is not None:
        cb = fig.colorbar(mesh, ax=list(axes[0]), shrink=0.9, pad=0.02)
        cb.set_label(elabel)
    what = ENERGIES[energy].replace(" $E$", "").replace("total energy injected", "total energy")
    fig.suptitle(title(s, f"{what} vs driving frequency and amplitude (grey: not run)") + "\n" + conditions(s))
    return fig


def _surface(ax, omega: np.ndarray, amp: np.ndarray, e: np.ndarray, a_s: np.ndarray, vmin: float) -> None:
    """One panel as a 3-D surface of log10 E, A_s as x-marks on its floor."""
    w, a = np.meshgrid(omega, amp)
    ax.plot_surface(w, a, np.log10(np.where(e > 0, e, np.nan)), cmap="viridis", norm=None, linewidth=0,
                    antialiased=False)
    inside = np.isfinite(a_s) & (a_s >= amp.min()) & (a_s <= amp.max())
    ax.plot(omega[inside], a_s[inside], np.full(int(inside.sum()), np.log10(vmin)), "rx", label=r"$A_s(\Omega)$")
    ax.set_zlabel(r"$\log_{10} E$")


def _colour_map(ax, omega: np.ndarray, amp: np.ndarray, e: np.ndarray, a_s: np.ndarray, trans: np.ndarray,
                status: np.ndarray, norm) -> Any:
    """One panel as a colour map, A_s and the first transmitting amplitudes over it; returns the mesh."""
    ax.set_facecolor("0.85")
    mesh = ax.pcolormesh(omega, amp, np.ma.masked_invalid(np.where(e > 0, e, np.nan)), norm=norm, cmap="viridis",
                         shading="nearest")
    ok = np.isfinite(a_s)
    ax.plot(omega[ok], a_s[ok], color="white", lw=1.0, ls="-", zorder=3)
    ax.plot(omega[ok], a_s[ok], "x", color="red", ms=5, mew=1.3, zorder=4,
            label=r"$A_s(\Omega) = 4\arctan(\lambda c/\Omega)$")
    first = np.array([first_transmitting(amp, trans[w], status[w]) for w in range(omega.size)])
    okf = np.isfinite(first)
    if okf.any():
        ax.plot(omega[okf], first[okf], "o", mfc="white", mec="black", ms=3.5, zorder=4,
                label="first transmitting run")
    ax.set_xlim(omega.min() - _half(omega), omega.max() + _half(omega))
    ax.set_ylim(amp.min() - _half(amp), amp.max() + _half(amp))
    ax.legend(loc="lower left", fontsize=7, framealpha=0.85)
    return mesh


def _half(axis: np.ndarray) -> float:
    """Half the smallest spacing of an axis (0.5 for a single point)."""
    return 0.5 * float(np.min(np.diff(axis))) if axis.size > 1 else 0.5


def summary_map(s: Scene, full: bool = False) -> list[str]:
    """Per curve: from which Omega some run transmits, and the first transmitting A against A_s at about seven
    frequencies (`full`: at every one)."""
    pots = [str(x) for x in s.data["curves/potential"]]
    omega, amp = np.asarray(s.data["omega"]), np.asarray(s.data["amplitude"])
    st, tr = s.data["runs/status"], s.data["runs/transmitting"]
    lines = []
    for c in range(len(pots)):
        first = np.array([first_transmitting(amp, tr[c, w], st[c, w]) for w in range(omega.size)])
        ok = np.isfinite(first)
        line = f"  {pots[c]}: "
        if ok.any():
            line += f"some run transmits for Omega >= {fmt(omega[ok].min(), 3)}; "
        else:
            line += "no run transmits; "
        line += "Omega: first transmitting A / A_s = " + ", ".join(
            f"{fmt(omega[w], 3)}: {fmt(first[w], 3)}/{fmt(s.data['threshold_As'][c, w], 3)}"
            for w in columns(omega, full))
        lines.append(line)
    return lines
