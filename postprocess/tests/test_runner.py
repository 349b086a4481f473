"""make_figures.py (supratrans_post.runner) and the namelists it reads and copies with f90nml
(supratrans_post.namelist); every entry script of postprocess/ starts as the README runs it."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import build_lock
from supratrans_post import namelist, runner

POSTPROCESS = Path(__file__).resolve().parents[1]
ENV = {**os.environ, "MPLBACKEND": "Agg"}
SCRIPTS = ["plot.py", "make_figures.py", "work_precision.py", "chart_stability.py", "peer_scipy.py", "builds.py"]

pytest.importorskip("f90nml")


@pytest.mark.parametrize("script", SCRIPTS)
def test_entry_scripts_start(script):
    """`python3 postprocess/<script> --help` from anywhere: the thin script finds its package."""
    proc = subprocess.run([sys.executable, str(POSTPROCESS / script), "--help"], capture_output=True, text=True,
                          cwd="/", timeout=60)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith(f"usage: {script}"), proc.stdout[:200]


# ------------------------------------------------------------------------------------------------ namelists


def test_namelist_reading(write_namelist):
    path = write_namelist("""! comment with / and &fake
&scene kind = 'map', omega_step = 0.05 / ! trailing
&output
    file = '/tmp/x/y.h5'   ! a path with slashes
    overwrite = .true.
/
""", "reading.nml")
    nml = namelist.read(path)
    assert namelist.scene_kind(nml) == "map"
    assert namelist.output_file(nml) == "/tmp/x/y.h5"
    assert nml["scene"]["omega_step"] == 0.05
    assert "profile" not in nml["output"]
    job = runner.Job(path)
    assert job.kind == "map" and job.output == Path("/tmp/x/y.h5") and job.figure == "reading"


def test_namelist_defaults_and_errors(tmp_path):
    plain = tmp_path / "fig1_sg_A150.nml"
    plain.write_text("&chain n = 40 /\n")
    job = runner.Job(plain)
    assert job.kind == "timeseries" and job.output is None and job.figure == "fig1"
    bad = tmp_path / "bad.nml"
    bad.write_text("&scene kind = 'map'\n")  # no closing /
    with pytest.raises(runner.PlotError) as err:
        runner.Job(bad)
    assert err.value.line().startswith(f"error: {bad}: ") and "\n" not in err.value.line()


def test_quick_copy_coarsens_the_grid(tmp_path):
    nml = tmp_path / "fig2.nml"
    nml.write_text("&scene\n    kind = 'amplitude_sweep'\n    amplitude_step = 0.01  ! fine\n/\n"
                   "&output\n    file = 'out/fig2.h5'\n/\n")
    q = runner.quick_copy(runner.Job(nml), tmp_path / "quick")
    g = namelist.read(q.nml)
    assert float(g["scene"]["amplitude_step"]) == pytest.approx(0.05)
    assert q.output == tmp_path / "quick" / "fig2.h5" and q.figure == "fig2"
    assert g["output"]["overwrite"] is True


def test_quick_copy_scales_only_the_scene_steps(tmp_path):
    """Every step of namelist.QUICK is scaled (rounded to 6 digits, as the copies always were), nothing else
    changes, and an existing `overwrite = .false.` becomes .true. (the copies are rewritten at every run)."""
    nml = tmp_path / "bif.nml"
    nml.write_text("&chain c = 4.0, n = 200 /\n&numerics dt = 0.05 /\n"
                   "&scene kind = 'bifurcation', values = 0.0, 0.1, omega_step = 0.01, resolution = 0.01,\n"
                   "       coarse_step = 0.25, amplitude_step = 0.3 /\n"
                   "&output file = 'out/bif.h5', overwrite = .false. /\n")
    copy = namelist.quick_copy(nml, tmp_path / "q" / "bif.nml", tmp_path / "q" / "bif.h5")
    before, after = namelist.read(nml), namelist.read(copy)
    assert after["chain"] == before["chain"] and after["numerics"] == before["numerics"]
    scene = after["scene"]
    assert scene["kind"] == "bifurcation" and scene["values"] == [0.0, 0.1]
    assert (scene["omega_step"], scene["resolution"], scene["coarse_step"]) == (0.02, 0.05, 0.5)
    assert scene["amplitude_step"] == 1.5  # 0.3 * 5 = 1.5000000000000002 before rounding
    assert after["output"]["file"] == str(tmp_path / "q" / "bif.h5") and after["output"]["overwrite"] is True


# ------------------------------------------------------------------------------------------------ make_figures


@pytest.mark.slow
def test_make_figures_runs_and_draws(release_exe, tmp_path, small_chain):
    """The whole command on a folder of two tiny namelists: progress line per scene, then the figures (the release
    build it starts with is the session's, made once)."""
    inp = tmp_path / "input"
    inp.mkdir()
    for a in (150, 250):
        out = tmp_path / "out" / f"fig1_sg_A{a}.h5"
        (inp / f"fig1_sg_A{a}.nml").write_text(small_chain("sine-gordon", a / 100, 5.0, out))
    (inp / "broken.nml").write_text(f"&chain n = 1 /\n&output file = '{tmp_path / 'out' / 'broken.h5'}', "
                                    "overwrite = .true., quiet = .true. /\n")
    (inp / "other.nml").write_text("&scene kind = 'timeseries' /\n")  # no &output file: listed and skipped
    cmd = [sys.executable, str(POSTPROCESS / "make_figures.py"), "--input", inp, "--outdir", tmp_path / "figs",
           "--logs", tmp_path / "logs"]
    with build_lock():     # it runs fpm in this checkout, as the session's builds do
        proc = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, env=ENV, timeout=300)
    lines = proc.stdout.splitlines()
    assert proc.returncode == 1, proc.stdout + proc.stderr  # broken.nml fails, the others go on
    assert any(x.startswith("[1/3] ") and x.endswith(" s") and "fig1_sg_A150.nml" in x for x in lines), lines
    assert any(x.startswith("[3/3] ") and "broken.nml" in x and "FAILED" in x for x in lines), lines
    assert any("other.nml" in x and "skipped" in x for x in lines), lines  # nothing to draw: not run
    assert (tmp_path / "figs" / "fig1.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert (tmp_path / "figs" / "fig1.png").stat().st_size > 5000
    assert not (tmp_path / "figs" / "broken.png").exists()
    assert "n = 1" in (tmp_path / "logs" / "broken.log").read_text()  # the program's own message, kept
    h5py = pytest.importorskip("h5py")
    with h5py.File(tmp_path / "out" / "fig1_sg_A150.h5") as f:  # built and run through .ci/with_commit
        assert len(f["provenance"].attrs["git_commit"].decode()) == 40


@pytest.mark.slow
def test_make_figures_relays_the_programs_progress_when_not_a_terminal(release_exe, tmp_path):
    """Its output a pipe (a log, CI), make_figures prints the program's own progress lines (elapsed, time left) below
    the scene's line, then the scene's line again with its time: a long scene is not silent. The program's rate is
    made tiny (SUPRATRANS_PROGRESS_EVERY = 1e-6 s): lines then come whenever a tenth of the time elapsed has
    passed, so that any run of a few polls prints several, however fast or loaded the machine."""
    inp = tmp_path / "input"
    inp.mkdir()
    (inp / "fig1_sg_A150.nml").write_text(
        "&chain n = 400, n0 = 380 /\n&drive amplitude = 1.5 /\n&numerics t_final = 500.0 /\n"
        f"&output file = '{tmp_path / 'out' / 'fig1_sg_A150.h5'}', overwrite = .true. /\n")
    cmd = [sys.executable, str(POSTPROCESS / "make_figures.py"), "--input", inp, "--outdir", tmp_path / "figs",
           "--logs", tmp_path / "logs"]
    with build_lock():     # it runs fpm in this checkout (.ci/with_commit removes every profile's library archive)
        proc = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, timeout=300,
                              env={**ENV, "SUPRATRANS_PROGRESS_EVERY": "1e-6"})
    assert proc.returncode == 0, proc.stdout + proc.stderr
    lines = proc.stdout.splitlines()
    relayed = [x for x in lines if x.startswith("    t = ") and "elapsed" in x]
    assert len(relayed) >= 2 and any("s left" in x for x in relayed), lines
    first = lines.index(relayed[0])
    start = max(i for i, x in enumerate(lines[:first]) if x.startswith("[1/1] "))
    assert lines[start].endswith("fig1_sg_A150.nml ..."), lines
    assert all(x.startswith("    ") for x in lines[start + 1:first]), lines    # fpm's lines as `fpm run` relinks
    done = [x for x in lines[first:] if x.startswith("[1/1] ") and x.endswith(" s")]
    assert len(done) == 1, lines      # the scene's line again, with its time, after its progress


def test_run_relays_progress_and_build_lines_when_not_a_terminal(tmp_path, capsys, monkeypatch):
    """runner.run, its output not a terminal: the program's progress lines (with the time elapsed) and fpm's build
    lines (`[ 45%] ...`, here at every line: SUPRATRANS_PROGRESS_EVERY = 1e-9 s) are printed on lines of their own
    and kept in `relayed`; the program's other lines go to the log only."""
    monkeypatch.setenv("SUPRATRANS_PROGRESS_EVERY", "1e-9")
    script = ("print('[ 10%] compiling a.f90'); print('chatter'); "
              "print('  3/95 fold continuations, elapsed 12.0 s, remaining ~300.0 s'); print('[100%] done')")
    relayed: list[str] = []
    status = runner.run([sys.executable, "-c", script], tmp_path / "log" / "x.log", "[1/1] x ...", False, relayed)
    assert status == 0
    out = capsys.readouterr().out.splitlines()
    assert out == ["", "    [ 10%] compiling a.f90", "    3/95 fold continuations, elapsed 12.0 s, remaining ~300.0 s",
                   "    [100%] done"], out
    assert len(relayed) == 3 and "chatter" in (tmp_path / "log" / "x.log").read_text()
