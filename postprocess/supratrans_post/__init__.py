"""supratrans_post: the figures, charts and SciPy peer of the HDF5 files written by supratrans, and `load`, which
gives one of those files as labelled xarray data:

    import supratrans_post
    tree = supratrans_post.load("out/fig2.h5")        # xarray.DataTree: every group, its axes, units, flags
    tree["energy/injected"].sel(amplitude=1.8)       # (curve), with the coordinates potential and gamma

Modules (lower ones never import higher ones):

- `reader`: the one reader of the HDF5 files: each scene's datasets (`SCHEMA`), the axes of each dimension (its
  HDF5 dimension scale when attached), the one-line `PlotError`;
- `dataset`: `load`, a file as an xarray DataTree with labelled coordinates, CF flags, `long_name` and `units`
  (needs xarray and h5netcdf, imported on first use);
- `cli`: what the commands share: one-line argument errors, the checked `--dpi`, the checkout they run in;
- `style`: the house style of matplotlib, only within `style_context` (never the global rcParams), figures
  without pyplot, number formats, saving;
- `namelist`: the namelists of `input/` read and written with f90nml (scene, output file, `--quick` copies);
- `figures`: the paper's figures, one module per scene (timeseries, sweep, map, bifurcation);
- `peer`: the SciPy peer (`solve_ivp` on the same chain), timed and scored against a `work_precision` file;
- `charts`: the speed/accuracy charts (`stability`, `work_precision`);
- `scaling`: time and memory of the program against N, T and the number of runs;
- `plot`, `runner`: the command lines of `plot.py` and `make_figures.py`.

The scripts in `postprocess/` (`plot.py`, `make_figures.py`, `work_precision.py`, `chart_stability.py`,
`peer_scipy.py`, `scaling.py`, `builds.py`) only call the `main` of these modules; `pip install ./postprocess` installs the
package with the same mains as the commands `supratrans-plot`, `supratrans-figures`, `supratrans-stability-chart`,
`supratrans-work-precision`, `supratrans-peer`, `supratrans-scaling` and `supratrans-builds` (pyproject.toml). Every main parses its
arguments before it does anything else and writes only where its options (or documented defaults) say.
"""

from .dataset import load

__all__ = ["load"]
