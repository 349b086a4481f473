"""The margin below which a verdict is flagged thin is an input key (`&detect thin_margin`, issue 42): it moves the
flags of the bifurcation's `/thin_verdict` (and the runs' `/runs/thin_verdict`) and nothing else, and the file records
it in `/parameters` and on the dataset."""
from __future__ import annotations

import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest

SCENE = """&chain n = 40, n0 = 30 /
&numerics t_final = 60.0 /
&detect thin_margin = {limit} /
&scene kind = 'bifurcation', amplitude_min = 1.0, amplitude_max = 4.0, coarse_step = 1.0, resolution = 0.25,
  omega_min = 0.9, omega_max = 0.9, omega_step = 0.1, potentials = 'sine-gordon', 'klein-gordon' /
&output file = 'b.h5', quiet = .true. /
"""


def bifurcation(exe: str, folder: Path, limit: float) -> dict:
    """The bifurcation's threshold, margins, flags and recorded limit for `&detect thin_margin = limit`."""
    folder.mkdir()
    (folder / "b.nml").write_text(SCENE.format(limit=limit))
    proc = subprocess.run([exe, "b.nml"], cwd=folder, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    with h5py.File(folder / "b.h5", "r") as f:
        return {"threshold": f["threshold"][()], "margin": f["verdict_margin"][()], "thin": f["thin_verdict"][()],
                "attr": float(f["thin_verdict"].attrs["thin_margin"]),
                "parameter": float(f["parameters"].attrs["detect_thin_margin"])}


def test_thin_margin_moves_the_flags_and_nothing_else(exe, tmp_path):
    runs = {limit: bifurcation(exe, tmp_path / str(limit), limit) for limit in (0.0, 0.2, 1.0)}
    found = runs[0.2]["margin"] == runs[0.2]["margin"]        # not NaN: a threshold with a run below it
    assert found.any()
    for limit, r in runs.items():
        assert r["attr"] == r["parameter"] == pytest.approx(limit)
        np.testing.assert_array_equal(r["threshold"], runs[0.2]["threshold"])     # no verdict moves
        np.testing.assert_array_equal(r["margin"], runs[0.2]["margin"])
        np.testing.assert_array_equal(r["thin"][found], (r["margin"][found] < limit).astype(int))
        assert (r["thin"][~found] == -1).all()
    assert (runs[0.0]["thin"][found] == 0).all()       # a margin is never negative below the threshold
    assert (runs[1.0]["thin"][found] == 1).all()       # ... and always below 1 where the drive moved the chain


def test_thin_margin_outside_its_range_is_one_line(exe, tmp_path):
    (tmp_path / "b.nml").write_text(SCENE.format(limit=1.5))
    proc = subprocess.run([exe, "--check", "b.nml"], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert proc.returncode != 0
    lines = [x for x in proc.stderr.splitlines() if x.strip()]
    assert len(lines) == 1 and "thin_margin" in lines[0], proc.stderr
    assert not (tmp_path / "b.h5").exists()
