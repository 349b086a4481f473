"""Figures of the scene `timeseries`: one file, u_n(t) at one probe site and the energy ledger; several files
(Fig. 1), a grid of u_n(t), one row per potential and one column per driving amplitude."""
from __future__ import annotations

import numpy as np

from ..reader import PlotError, Scene
from ..style import close, fmt, styled, subplots
from .common import FIGURES, PANEL, POTENTIAL_TITLES, conditions, label_of, notes, potential_title, title


def probe_index(s: Scene, site: int | None) -> tuple[int, int]:
    """(index in /probes/sites, site) of the probe to draw: `site`, or 60 when recorded, else the middle probe."""
    sites = [int(x) for x in s.data["probes/sites"]]
    if not sites:
        raise PlotError(s.path, "no probe recorded (/probes/sites is empty)")
    if site is None:
        site = 60 if 60 in sites else sites[len(sites) // 2]
    if site not in sites:
        raise PlotError(s.path, f"site {site} was not recorded (probes: {', '.join(map(str, sites))})")
    return sites.index(site), site


def run_note(s: Scene) -> str:
    """The outcome of the run as text: 'transmits, energy injected 255.1', with its status when not ok."""
    run = s.groups.get("run", {})
    bits = []
    if "transmitting" in run:
        bits.append("transmits" if int(run["transmitting"]) else "does not transmit")
    if "energy_injected" in run and run["energy_injected"] is not None:
        bits.append(f"energy injected {fmt(float(run['energy_injected']), 4)}")
    status = run.get("status")
    if status not in (None, "ok", 0):
        bits.append(f"status {status}")
    return ", ".join(bits)


@styled
def draw_timeseries(scenes: list[Scene], site: int | None = None):
    """One file: u_n(t) at the probe `site` (default 60) and the energy ledger. Several files (Fig. 1): a grid
    of u_n(t), one row per potential (file order), one column per driving amplitude (ascending)."""
    if len(scenes) == 1:
        return _one(scenes[0], site)
    potentials = sorted(dict.fromkeys(str(s.params.get("potential")) for s in scenes),
                        key=lambda q: (list(POTENTIAL_TITLES).index(q) if q in POTENTIAL_TITLES else 9, q))
    amplitudes = sorted({float(s.params.get("amplitude")) for s in scenes})
    nr, nc = len(potentials), len(amplitudes)
    fig, axes = subplots(nr, nc, figsize=(PANEL[0] * nc * 0.85, PANEL[1] * nr * 0.8), squeeze=False,
                         sharex=True)
    seen = set()
    for s in scenes:
        r = potentials.index(str(s.params.get("potential")))
        c = amplitudes.index(float(s.params.get("amplitude")))
        if (r, c) in seen:
            close(fig)
            raise PlotError(s.path, f"two files for the same panel ({s.params.get('potential')}, "
                                    f"A = {fmt(s.params.get('amplitude'))})")
        seen.add((r, c))
        i, st = probe_index(s, site)
        ax = axes[r, c]
        ax.plot(s.data["probes/time"], s.data["probes/u"][i], color="black", lw=0.7)
        letter = "abcdefgh"[c] if c < 8 else str(c + 1)
        note = run_note(s)
        ax.set_title(f"({letter}) $A$ = {fmt(s.params.get('amplitude'))}   "
                     f"{potential_title(s.params.get('potential'))}" + (f"\n{note}" if note else ""))
        ax.set_ylabel(rf"$u_{{{st}}}(t)${s.unit('probes/u')}")
        if r == nr - 1:
            ax.set_xlabel(f"time $t${s.unit('probes/time')}")
    for r in range(nr):
        for c in range(nc):
            if (r, c) not in seen:
                axes[r, c].set_visible(False)
    s0 = scenes[0]
    label = FIGURES["fig1"][0] if s0.name.startswith("fig1") else label_of(s0)
    fig.suptitle(f"{label}: displacement at one site, before (a) and after (b) the threshold{notes(*scenes)}\n"
                 + conditions(s0))
    return fig


def _one(s: Scene, site: int | None):
    """u_n(t) at one probe and the energy ledger of one file."""
    i, site = probe_index(s, site)
    fig, (ax, bx) = subplots(2, 1, figsize=(PANEL[0] * 1.3, PANEL[1] * 1.6), sharex=True)
    t = s.data["probes/time"]
    ax.plot(t, s.data["probes/u"][i], color="black", lw=0.8)
    ax.set_ylabel(rf"$u_{{{site}}}(t)${s.unit('probes/u')}")
    p = s.params
    ax.set_title(f"{potential_title(p.get('potential'))}, $A$ = {fmt(p.get('amplitude'))}, "
                 + conditions(s) + (f"\n{run_note(s)}" if run_note(s) else ""))
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
    fig.suptitle(title(s, rf"$u_{{{site}}}(t)$ and the energy ledger"))
    return fig


def summary_timeseries(s: Scene) -> list[str]:
    """One line: the run's parameters, its outcome, the largest |u| at the probe and over the chain."""
    run = s.groups.get("run", {})
    i, site = probe_index(s, None)
    return [f"{s.path}: {s.params.get('potential')}, A = {fmt(s.params.get('amplitude'))}, "
            f"Omega = {fmt(s.params.get('omega'))}: {run_note(s) or 'no outcome recorded'}, "
            f"max |u_{site}| = {fmt(float(np.max(np.abs(s.data['probes/u'][i]))), 3)}"
            + (f", max |u| over the chain = {fmt(float(run['max_abs_u']), 3)}" if "max_abs_u" in run else "")]
