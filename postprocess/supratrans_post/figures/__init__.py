"""The paper's figures (Macias-Diaz & Puri), one module per scene. Everything a figure shows comes from its file:
the axes and curves from the datasets, every parameter (Omega, N, T, the varied gamma / beta / m^2, ...) from the
attributes of `/parameters` and `/curves`.

- `timeseries`: one file: u_n(t) at one probe site and the energy ledger; several files (Fig. 1): a grid of
  u_n(t), one row per potential, one column per driving amplitude;
- `amplitude_sweep`: total energy injected vs driving amplitude (Figs. 2, 3, 3-and-a-half, 4), one panel per
  potential, or, for one potential whose masses have both signs, 'Pure-imaginary masses' and 'Real masses';
- `map`: total energy over driving frequency x amplitude (Fig. 11), one panel per curve, A_s(Omega) over it;
- `bifurcation`: threshold amplitude vs driving frequency (Bif1-Bif3), A_s as x-marks;
- `continuation`: the branch of driven periodic states with its fold and multipliers (one frequency), or the fold
  line over the frequency (the model's threshold, not a protocol's); `harmonic`: a continuation file by harmonic
  balance (root attribute `solver`), its fold line with its convergence in K, or its continuum limit in 1/c^2;
- `hysteresis`: the mean power of each stair vs its amplitude, up and down, the bistable window shaded (one
  frequency), or the upward and downward edges over the frequency (several);
- `threshold`: charts of several files: the fold line, the scan thresholds, the hysteresis window and A_s on one
  Bif1-style chart (`draw_thresholds`), and the scan threshold at one frequency against the ramp time next to the
  fold (`draw_ramp`).

Families are styled like the paper: the curves of a panel, ordered by the magnitude of the varied parameter,
are solid, dashed, dash-dotted and dotted. Partial files (`<output>.partial.h5`, written while a scene runs or
left by a killed one) are drawn with the runs not done as gaps, and their titles say `partial: k of n runs`.
"""
from __future__ import annotations

from ..reader import FIGURE_SCENES, PlotError, Scene
from .bifurcation import draw_bifurcation, summary_bifurcation
from .continuation import draw_continuation, summary_continuation
from .hysteresis import draw_hysteresis, summary_hysteresis
from .common import ENERGIES, FIGURES
from .map import draw_map, summary_map
from .sweep import draw_sweep, summary_sweep, zoom_window
from .threshold import draw_ramp, draw_thresholds, summary_ramp, summary_thresholds
from .timeseries import draw_timeseries, summary_timeseries

__all__ = ["draw", "draw_timeseries", "draw_sweep", "draw_map", "draw_bifurcation", "draw_continuation",
           "draw_hysteresis", "draw_thresholds", "draw_ramp", "summary", "summary_thresholds", "summary_ramp",
           "zoom_window", "ENERGIES", "FIGURES", "SCENES"]

#: Scenes drawn as figures of the paper.
SCENES = FIGURE_SCENES


def draw(scenes: Scene | list[Scene]):
    """The figure of one file, or Fig. 1 of several timeseries files. Returns a matplotlib Figure."""
    if isinstance(scenes, Scene):
        scenes = [scenes]
    kinds = {s.scene for s in scenes}
    if len(scenes) > 1 and kinds != {"timeseries"}:
        bad = next(s for s in scenes if s.scene != "timeseries")
        raise PlotError(bad.path, f"scene is '{bad.scene}': only timeseries files are drawn together (Fig. 1)")
    s = scenes[0]
    if s.scene == "timeseries":
        return draw_timeseries(scenes)
    if s.scene == "amplitude_sweep":
        return draw_sweep(s)
    if s.scene == "map":
        return draw_map(s)
    if s.scene == "bifurcation":
        return draw_bifurcation(s)
    if s.scene == "continuation":
        return draw_continuation(s)
    if s.scene == "hysteresis":
        return draw_hysteresis(s)
    raise PlotError(s.path, f"scene '{s.scene}' is not a figure of the paper (its chart: chart_stability.py or "
                            "work_precision.py)")


def summary(s: Scene, full: bool = False) -> list[str]:
    """Lines of text with the numbers a figure shows (printed by the scripts, quoted in README.md); `full`: every
    frequency of a map or bifurcation, not about seven of them. A timeseries gives one line; the others a header
    line (the file) and one line per curve."""
    if s.scene == "timeseries":
        return summary_timeseries(s)
    head = [f"{s.path}" + (f" ({s.partial_note()})" if s.partial else "")]
    if s.scene == "amplitude_sweep":
        return head + summary_sweep(s)
    if s.scene == "map":
        return head + summary_map(s, full)
    if s.scene == "continuation":
        return head + summary_continuation(s, full)
    if s.scene == "hysteresis":
        return head + summary_hysteresis(s, full)
    return head + summary_bifurcation(s, full)
