"""supratrans_post: the figures, charts and SciPy peer of the HDF5 files written by supratrans.

Modules (lower ones never import higher ones):

- `reader`: the one reader of the HDF5 files: each scene's datasets (`SCHEMA`), the one-line `PlotError`;
- `style`: matplotlib without a window, number formats, saving;
- `namelist`: the namelists of `input/` read and written with f90nml (scene, output file, `--quick` copies);
- `figures`: the paper's figures, one module per scene (timeseries, sweep, map, bifurcation);
- `peer`: the SciPy peer (`solve_ivp` on the same chain), timed and scored against a `work_precision` file;
- `charts`: the speed/accuracy charts (`stability`, `work_precision`);
- `plot`, `runner`: the command lines of `plot.py` and `make_figures.py`.

The scripts in `postprocess/` (`plot.py`, `make_figures.py`, `work_precision.py`, `chart_stability.py`,
`peer_scipy.py`) only call the `main` of these modules.
"""
