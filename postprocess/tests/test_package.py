"""postprocess/ as a Python package: `pip install ./postprocess` (offline, into a fresh virtual environment) gives
the package supratrans_post and its commands; importing and drawing leave matplotlib's global settings alone; every
command parses its arguments before it does anything else (`--help` runs nothing, builds nothing, writes nothing),
refuses a resolution it cannot draw in one line, and writes only where it is told."""
from __future__ import annotations

import copy
import hashlib
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from supratrans_post import builds, cli, scaling, style
from supratrans_post.charts import stability as chart_stability
from supratrans_post.charts import work_precision as chart_work_precision
from supratrans_post.peer import main as peer_main
from supratrans_post.plot import main as plot_main
from supratrans_post.runner import main as runner_main

POSTPROCESS = Path(__file__).resolve().parents[1]
#: The commands pyproject.toml declares, {command: "module:function"}.
COMMANDS = tomllib.loads((POSTPROCESS / "pyproject.toml").read_text())["project"]["scripts"]
#: The scripts of postprocess/ (as the README runs them) and the main each one calls.
SCRIPTS = {"plot.py": plot_main, "make_figures.py": runner_main, "chart_stability.py": chart_stability.main,
           "work_precision.py": chart_work_precision.main, "peer_scipy.py": peer_main, "scaling.py": scaling.main,
           "builds.py": builds.main}


def clean_env(**extra: str) -> dict[str, str]:
    """The environment without PYTHONPATH (so that a command finds the package only where it was installed)."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    return {**env, "MPLBACKEND": "Agg", **extra}


def sha(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest() if path.exists() else "absent"


# ------------------------------------------------------------------------------------------------ pip install


@pytest.fixture(scope="module")
def venv(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A virtual environment (seeing the system's numpy, h5py, matplotlib, and pip: --without-pip spares the
    copy of pip) with `pip install ./postprocess` done in it, offline (--no-index: no package index is asked),
    without build isolation and without dependencies."""
    folder = tmp_path_factory.mktemp("venv") / "env"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", "--without-pip", str(folder)],
                   check=True, capture_output=True, timeout=120)
    proc = subprocess.run([str(folder / "bin" / "python"), "-m", "pip", "install", "--no-deps", "--no-index",
                           "--no-build-isolation", "--disable-pip-version-check", str(POSTPROCESS)],
                          capture_output=True, text=True, timeout=300, cwd=folder.parent, env=clean_env())
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    return folder


def test_pip_install_gives_the_package(venv):
    """The package is imported from the environment (not from the checkout), with every module of the source."""
    code = ("import pkgutil, supratrans_post as p; print(p.__file__); "
            "print(' '.join(sorted(m.name for m in pkgutil.walk_packages(p.__path__, 'supratrans_post.'))))")
    proc = subprocess.run([str(venv / "bin" / "python"), "-c", code], capture_output=True, text=True, cwd=venv,
                          env=clean_env(), timeout=60)
    assert proc.returncode == 0, proc.stderr
    where, modules = proc.stdout.splitlines()
    assert Path(where).is_relative_to(venv), where
    package = POSTPROCESS / "supratrans_post"
    source = ["supratrans_post." + ".".join(p.relative_to(package).with_suffix("").parts)
              for p in package.rglob("*.py") if p.name != "__init__.py"]
    source += ["supratrans_post." + p.parent.name for p in package.glob("*/__init__.py")]
    assert sorted(modules.split()) == sorted(source)


def test_commands_declared():
    assert {"supratrans-plot", "supratrans-figures", "supratrans-stability-chart", "supratrans-work-precision",
            "supratrans-scaling"} <= set(COMMANDS)


def test_readme_lists_every_command():
    """The README names every command pyproject.toml installs (it once listed 6 of 7)."""
    readme = (POSTPROCESS.parent / "README.md").read_text(encoding="utf-8")
    assert [c for c in COMMANDS if f"`{c}`" not in readme] == []


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_installed_command_help(venv, tmp_path, command):
    """Each command of pyproject.toml runs from anywhere, names itself in its usage, and does nothing else."""
    proc = subprocess.run([str(venv / "bin" / command), "--help"], capture_output=True, text=True, cwd=tmp_path,
                          env=clean_env(), timeout=60)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith(f"usage: {command} "), proc.stdout[:200]
    assert list(tmp_path.iterdir()) == []


def test_installed_command_outside_a_checkout_says_where(venv, tmp_path):
    """Outside a checkout the commands whose default output is postprocess/figures/ ask for a place, in one line."""
    proc = subprocess.run([str(venv / "bin" / "supratrans-figures"), "--no-run"], capture_output=True, text=True,
                          cwd=tmp_path, env=clean_env(), timeout=60)
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1, proc.stderr
    assert "not in a supratrans checkout" in proc.stderr


@pytest.mark.slow
def test_installed_commands_work_outside_a_checkout(venv, tiny, debug_exe, small_chain, tmp_path):
    """Every installed command, run in a folder outside any checkout, does its work when given what it needs: the
    figures from existing files (--no-run, --input, --outdir) and from namelists run by the `supratrans` on PATH
    (their paths relative to the working directory), plot, the stability chart, the peer and the work-precision
    charts from a file, scaling with --exe; what cannot be done there is one line that names what to give."""
    work = tmp_path / "work"
    (work / "input").mkdir(parents=True)
    (work / "bin").mkdir()
    (work / "bin" / "supratrans").symlink_to(debug_exe)
    (work / "input" / "fig1_sg_A150.nml").write_text(small_chain("sine-gordon", 1.5, 5.0, "out/fig1_sg_A150.h5"))
    bare = clean_env(PATH="/usr/bin:/bin")       # no supratrans on PATH
    with_program = clean_env(PATH=f"{work / 'bin'}:/usr/bin:/bin")

    def command(name: str, *args: object, env: dict = bare) -> subprocess.CompletedProcess:
        return subprocess.run([str(venv / "bin" / name), *map(str, args)], capture_output=True, text=True, cwd=work,
                              env=env, timeout=300)

    def one_line(proc: subprocess.CompletedProcess, *words: str) -> None:
        assert proc.returncode == 2 and proc.stderr.count("\n") == 1, proc.stderr
        assert proc.stderr.startswith("error: ") and all(w in proc.stderr for w in words), proc.stderr

    one_line(command("supratrans-figures", "--input", "input", "--outdir", "figs"), "no `supratrans` on PATH",
             "--no-run")
    proc = command("supratrans-figures", "--input", "input", "--outdir", "figs", env=with_program)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert (work / "out" / "fig1_sg_A150.h5").is_file()     # the namelist's path, from the working directory
    assert (work / "figs" / "fig1.png").read_bytes()[:4] == b"\x89PNG"
    proc = command("supratrans-figures", "--no-run", "--only", "fig1", "--input", "input", "--outdir", "again")
    assert proc.returncode == 0 and (work / "again" / "fig1.png").is_file(), proc.stdout + proc.stderr
    proc = command("supratrans-plot", "out/fig1_sg_A150.h5", "-o", "plot.png")
    assert proc.returncode == 0 and (work / "plot.png").is_file(), proc.stderr
    proc = command("supratrans-stability-chart", tiny.file("stab"), "-o", "stability.png")
    assert proc.returncode == 0 and (work / "stability.png").is_file(), proc.stderr
    wpf = tiny.file("wp_sg")
    proc = command("supratrans-peer", wpf, "-o", "peer.json", "--methods", "DOP853", "--tols", "1e-4",
                   "--repeats", "1")
    assert proc.returncode == 0 and (work / "peer.json").is_file(), proc.stderr
    proc = command("supratrans-work-precision", "--h5", wpf, "--peer", "peer.json", "--outdir", "wp", "-q")
    assert proc.returncode == 0 and (work / "wp" / "work_precision.png").is_file(), proc.stderr
    one_line(command("supratrans-work-precision", "--nml", "input/fig1_sg_A150.nml", "--outdir", "wp"),
             "no `supratrans` on PATH", "--h5")
    one_line(command("supratrans-scaling"), "no `supratrans` on PATH", "--exe")
    proc = command("supratrans-scaling", "--exe", debug_exe.parent / "nowhere")
    assert proc.returncode == 2 and "cannot run" in proc.stderr, proc.stderr     # --exe is taken, not a checkout
    one_line(command("supratrans-builds", "--no-static"), "not in a supratrans checkout", "--checkout DIR")
    one_line(command("supratrans-builds", "--checkout", "input"), "not a supratrans checkout", "--checkout DIR")


def test_progress_lines_say_the_time_left_by_the_work_left(monkeypatch):
    """cli.Progress: nothing before its interval, then one line at most per interval (SUPRATRANS_PROGRESS_EVERY,
    or a tenth of the time elapsed when longer), with the time left from the time per unit of work so far."""
    import io  # noqa: PLC0415

    clock = [100.0]
    monkeypatch.setattr(cli.time, "monotonic", lambda: clock[0])
    monkeypatch.setenv("SUPRATRANS_PROGRESS_EVERY", "5")
    out = io.StringIO()
    p = cli.Progress("peer", [1.0, 3.0, 4.0], "points", stream=out)
    clock[0] += 2.0
    p.step()                                    # 2 s: within the interval, silent
    assert out.getvalue() == ""
    clock[0] += 4.0
    p.step()                                    # 6 s: 4 of 8 units done in 6 s, 4 left
    assert out.getvalue() == "  peer: 2/3 points, 6 s elapsed, about 6 s left\n"
    clock[0] += 4.0
    p.step()                                    # 4 s after the last line: silent
    assert out.getvalue().count("\n") == 1
    monkeypatch.setenv("SUPRATRANS_PROGRESS_EVERY", "1")
    q = cli.Progress("x", 2, stream=out)
    clock[0] += 100.0
    q.step()                                    # 100 s: 1 of 2 done
    assert out.getvalue().splitlines()[-1] == "  x: 1/2 done, 100 s elapsed, about 100 s left"
    clock[0] += 5.0
    q.step()                                    # 5 s later, but the interval is now 10 s (a tenth of 105)
    assert out.getvalue().count("\n") == 2



@pytest.mark.parametrize("text,every", [("2.5", 2.5), ("1e-9", 1e-9), ("0", 4.0), ("-3", 4.0), ("nan", 4.0),
                                        ("inf", 4.0), ("soon", 4.0), ("", 4.0)])
def test_progress_interval_is_read_as_the_program_reads_it(monkeypatch, text, every):
    """SUPRATRANS_PROGRESS_EVERY: a finite number of seconds > 0, else the default (4 s), as the program's
    `progress_every_setting` reads it; 0 once meant `every step` here and `the default` in the program."""
    monkeypatch.setenv("SUPRATRANS_PROGRESS_EVERY", text)
    assert cli.progress_every() == every
    assert cli.Progress("x", 1).every == every

# ------------------------------------------------------------------------------------------------ matplotlib


def rc_snapshot() -> dict:
    """matplotlib's rcParams as they are (read without resolving the backend, which would import pyplot; the
    backend's placeholder object itself, not a copy)."""
    import matplotlib  # noqa: PLC0415

    return {k: v if k == "backend" else copy.deepcopy(v) for k, v in dict.items(matplotlib.rcParams)}


def test_importing_the_package_leaves_matplotlib_alone():
    """In a fresh interpreter: import matplotlib, then every module of the package: rcParams unchanged, pyplot
    not imported."""
    code = """
import copy, pkgutil, importlib, sys
import matplotlib
snap = lambda: {k: v if k == 'backend' else copy.deepcopy(v) for k, v in dict.items(matplotlib.rcParams)}
before = snap()
import supratrans_post
for m in pkgutil.walk_packages(supratrans_post.__path__, 'supratrans_post.'):
    importlib.import_module(m.name)
after = snap()
changed = sorted(k for k in set(before) | set(after) if before.get(k) != after.get(k))
print(changed, 'matplotlib.pyplot' in sys.modules)
"""
    env = {**clean_env(), "PYTHONPATH": str(POSTPROCESS)}
    env.pop("MPLBACKEND")  # the backend left to matplotlib: importing must not choose one
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, env=env)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "[] False"


def test_drawing_and_saving_leave_rcparams_alone_and_carry_the_style(tmp_path):
    """The house style is set while a figure is made and saved, not in the global rcParams."""
    before = rc_snapshot()
    rows = [(kind, v, 0.01 * v, 10.0 + v) for kind, values in scaling.POINTS for v in values]
    fig = scaling.draw(rows)
    assert rc_snapshot() == before
    assert fig.axes[0].xaxis.label.get_fontsize() == style.STYLE["font.size"]  # drawn in the style
    assert type(fig.get_layout_engine()).__name__ == "ConstrainedLayoutEngine"
    style.save(fig, tmp_path / "s.png")
    assert rc_snapshot() == before
    assert (tmp_path / "s.png").read_bytes()[:4] == b"\x89PNG"
    with style.style_context():
        import matplotlib  # noqa: PLC0415

        assert matplotlib.rcParams["font.size"] == style.STYLE["font.size"]
    assert rc_snapshot() == before


# ------------------------------------------------------------------------------------------------ arguments first


@pytest.fixture
def no_fpm(tmp_path: Path) -> tuple[dict, Path]:
    """An environment whose `fpm` only leaves a mark (so that a command which builds or runs is seen), and the
    mark's path."""
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    mark = tmp_path / "fpm-was-called"
    (bin_dir / "fpm").write_text(f"#!/bin/sh\necho \"$@\" >> '{mark}'\nexit 1\n")
    (bin_dir / "fpm").chmod(0o755)
    return clean_env(PATH=f"{bin_dir}{os.pathsep}{os.environ.get('PATH', '')}",
                     PYTHONPATH=str(POSTPROCESS)), mark


@pytest.mark.parametrize("script", sorted(SCRIPTS))
def test_help_does_nothing_else(script, no_fpm, tmp_path):
    """Issue 22: `scaling.py --help` ran the benchmarks and overwrote the tracked figures/scaling.png. Every
    script prints its usage and stops: no fpm, no file written, no committed figure touched."""
    env, mark = no_fpm
    figures = {p: sha(p) for p in (POSTPROCESS / "figures").glob("*")}
    work = tmp_path / "work"
    work.mkdir()
    proc = subprocess.run([sys.executable, str(POSTPROCESS / script), "--help"], capture_output=True, text=True,
                          cwd=work, env=env, timeout=60)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith(f"usage: {script}"), proc.stdout[:200]
    assert not mark.exists(), mark.read_text()
    assert list(work.iterdir()) == []
    assert {p: sha(p) for p in (POSTPROCESS / "figures").glob("*")} == figures


#: The arguments of each script that draws, but for --dpi (the files named need not exist: nothing is read).
DRAWING = {"plot.py": ["x.h5", "-o", "x.png"], "chart_stability.py": ["x.h5", "-o", "x.png"],
           "scaling.py": ["-o", "x.png"], "make_figures.py": ["--no-run", "--outdir", "out"],
           "work_precision.py": ["--h5", "x.h5", "--outdir", "out"]}


@pytest.mark.parametrize("dpi", ["0", "-3", "100000", "ninety"])
@pytest.mark.parametrize("script", sorted(DRAWING))
def test_bad_dpi_is_one_line(script, dpi, call_main, tmp_path, monkeypatch):
    """Issue 22: `--dpi 0` (ValueError: dpi must be positive) and `--dpi 100000` (MemoryError) were tracebacks.
    Every command refuses them in one line with status 2, before reading, running or writing anything."""
    before = {p: sha(p) for p in (POSTPROCESS / "figures").glob("*")}
    monkeypatch.chdir(tmp_path)
    proc = call_main(SCRIPTS[script], *DRAWING[script], "--dpi", dpi)
    assert proc.returncode == 2, (proc.stdout, proc.stderr)
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: argument --dpi: ") and dpi in lines[0], proc.stderr
    assert proc.stdout == ""
    assert list(tmp_path.iterdir()) == []
    assert {p: sha(p) for p in (POSTPROCESS / "figures").glob("*")} == before


@pytest.mark.parametrize("dpi", ["0", "100000"])
def test_bad_dpi_on_a_real_file_is_one_line(tiny, tmp_path, call_main, dpi):
    """The two tracebacks of issue 22 as they were seen: a file that draws, and --dpi 0 or 100000."""
    for main, name in ((plot_main, "fig2"), (chart_stability.main, "stab")):
        proc = call_main(main, tiny.file(name), "--dpi", dpi, "-o", tmp_path / "x.png")
        assert proc.returncode == 2, (proc.stdout, proc.stderr)
        assert proc.stderr.count("\n") == 1 and proc.stderr.startswith("error: argument --dpi: "), proc.stderr
        assert not (tmp_path / "x.png").exists()


def test_plot_with_the_smallest_dpi_allowed(tiny, tmp_path, call_main):
    """The lower bound of --dpi is a resolution that draws."""
    for dpi in cli.DPI_RANGE[:1]:
        proc = call_main(plot_main, tiny.file("fig1_sg_A150"), "--dpi", dpi, "-o", tmp_path / f"{dpi}.png", "-q")
        assert proc.returncode == 0, proc.stderr
        assert (tmp_path / f"{dpi}.png").read_bytes()[:4] == b"\x89PNG"


# ------------------------------------------------------------------------------------------------ scaling


@pytest.fixture
def fake_supratrans(tmp_path: Path) -> Path:
    """An executable that stands for supratrans: reads nothing, writes nothing, exits 0 at once."""
    exe = tmp_path / "bin" / "supratrans"
    exe.parent.mkdir(exist_ok=True)
    exe.write_text("#!/bin/sh\nexit 0\n")
    exe.chmod(0o755)
    return exe


def test_scaling_writes_only_where_told(fake_supratrans, tmp_path, call_main, monkeypatch):
    """Without -o the table only, nothing written (the committed scaling.png untouched); with -o the chart there."""
    committed = sha(POSTPROCESS / "figures" / "scaling.png")
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    proc = call_main(scaling.main, "--exe", fake_supratrans)
    assert proc.returncode == 0, proc.stderr
    table = proc.stdout.splitlines()
    assert table[0] == "| varied | value | wall s | peak MiB |"
    assert len(table) == 2 + sum(len(v) for _, v in scaling.POINTS)
    assert list(work.iterdir()) == [] and sha(POSTPROCESS / "figures" / "scaling.png") == committed
    proc = call_main(scaling.main, "--exe", fake_supratrans, "-o", tmp_path / "chart" / "s.png")
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "chart" / "s.png").read_bytes()[:4] == b"\x89PNG"
    assert list(work.iterdir()) == [] and sha(POSTPROCESS / "figures" / "scaling.png") == committed


def test_scaling_failure_is_one_line(tmp_path, call_main):
    exe = tmp_path / "failing"
    exe.write_text("#!/bin/sh\necho 'error: something' >&2\nexit 3\n")
    exe.chmod(0o755)
    proc = call_main(scaling.main, "--exe", exe, "-o", tmp_path / "s.png")
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"error: {exe}: failed") and "error: something" in lines[0]
    assert not (tmp_path / "s.png").exists()


# ------------------------------------------------------------------------------------------------ builds


def test_builds_ratios_are_medians_of_the_ratios_within_a_round():
    """A round where the machine was slow for every build leaves the paired ratio alone; the medians show it."""
    times = {"default": [(1.0, 2.0), (3.0, 6.0), (1.0, 2.0)], "host": [(0.5, 1.0), (1.5, 3.0), (0.5, 1.0)],
             "naive": [(4.0, 8.0), (12.0, 24.0), (4.0, 8.0)]}
    lines = builds.report("t", times, "default")
    rows = {line.split()[0]: [float(x) for x in line.split()[1:]] for line in lines[2:]}
    assert rows["default"] == [1000.0, 2000.0, 1.0, 1.0, 0.25, 0.25]
    assert rows["host"] == [500.0, 1000.0, 0.5, 0.5, 0.125, 0.125]
    assert rows["naive"][2:4] == [4.0, 4.0]


def test_builds_static_link_names_the_missing_archives(tmp_path):
    words = ["no-such-compiler-xyz", "-L/nonexistent", "main.o", "-lhdf5", "-o", "x"]
    with pytest.raises(builds.PlotError, match="static archives not found: libhdf5_fortran.a, libhdf5.a"):
        builds.link_static(tmp_path, words, tmp_path / "static" / "x")
    assert not (tmp_path / "static").exists()
