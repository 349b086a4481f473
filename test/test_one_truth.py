"""One truth about an input (issue 42, part 6): `--check` refuses exactly what the run refuses, with the same line,
and neither creates anything (no output folder, no lock) for an input refused.

Each case is a namelist that breaks one rule between keys, one that used to live only in a scene's task making
(reached after the output's folder and lock were made, so that `--check` passed it); the run is started on it and
on `--check`, in a fresh directory each, and both must end with status 2, the same one line, and an empty
directory but for the namelist. The valid inputs beside them must pass both. A scene over a frequency axis given
`&drive omega` is warned about in one line by both; a default that makes an input invalid is named as a default.
"""
from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

#: A small chain and the output in a folder that must not be created for a refused input.
CHAIN = "&chain n = 40, n0 = 30 /\n"
OUT = "&output file = 'out/s.h5', quiet = .true. /\n"
CONT = CHAIN + "&scene kind = 'continuation', omega_min = 0.9, omega_max = 0.9, {extra} /\n" + OUT
HYST = CHAIN + "&scene kind = 'hysteresis', omega_min = 0.9, omega_max = 0.9, {extra} /\n" + OUT

#: name -> (namelist text, a word of the line both must print)
REFUSED = {
    # the seven inputs of issue 42 that passed --check and were refused by the run after it made folder and lock
    "continuation avf4": (CONT.format(extra="amplitude_max = 2.0") + "&numerics method = 'avf4' /\n",
                          "no one-period map"),
    "continuation avf8": (CONT.format(extra="amplitude_max = 2.0") + "&numerics method = 'avf8' /\n",
                          "no one-period map"),
    "stair_times 5 with stair_ramp 10": (HYST.format(extra="stair_times = 5.0"), "stair_ramp = 10"),
    "stair_ramp 60 with stair_times 100, 200": (HYST.format(extra="stair_ramp = 60.0, stair_times = 100.0, 200.0"),
                                                "stair_ramp = 60"),
    "stair_height 1e300": (HYST.format(extra="stair_height = 1e300"), "at least one stair up"),
    "stair_height 0.0001": (HYST.format(extra="stair_height = 0.0001"), "more than the limit"),
    "stair_times 0.1 with stair_ramp 0": (HYST.format(extra="stair_times = 0.1, stair_ramp = 0.0"), "4 dt"),
    # a dt beyond the method's linear stability limit: no periodic state to continue (also a task-making check)
    "continuation dt beyond linear stability": (CONT.format(extra="amplitude_max = 2.0") +
                                                "&numerics method = 'rk4', dt = 0.4, allow_unstable = .true. /\n",
                                                "linear stability limit"),
    # the work-precision scene's keys, checked by its task making after the folder and lock before
    "dt_smallest not one per method": (CHAIN + "&scene kind = 'work_precision', dt_smallest = 0.1 /\n" + OUT,
                                       "dt_smallest needs one value per method"),
    "a dts beyond t_final/2": (CHAIN + "&scene kind = 'work_precision', dts = 0.05, 150.0 /\n" + OUT,
                               "dts(2) = 150.0"),
    "reference_dt beyond t_final/2": (CHAIN + "&scene kind = 'work_precision', reference_dt = 150.0 /\n" + OUT,
                                      "reference_dt = 150.0"),
    # no silent clamping
    "continuation_step above continuation_step_max": (CONT.format(extra="continuation_step = 0.3"),
                                                      "continuation_step_max = 0.2 (the default)"),
    "continuation_step above a given continuation_step_max": (
        CONT.format(extra="continuation_step = 0.3, continuation_step_max = 0.25"), "not clamped"),
    # a default that makes the input invalid is named
    "n = 100 on the default n0 = 150": ("&chain n = 100 /\n" + OUT, "n0 = 150 (the default, not given)"),
    # the schema's other rules between keys, the same for both
    "n0 > n given": ("&chain n = 40, n0 = 50 /\n" + OUT, "need 0 <= N0 <= N = 40"),
    "omega outside the gap": (CHAIN + "&drive omega = 1.2 /\n" + OUT, "outside the band gap"),
    "t_final < 2 dt": (CHAIN + "&numerics t_final = 0.05 /\n" + OUT, "must be >= 2 dt"),
    "dt beyond the paper's condition": (CHAIN + "&numerics dt = 0.3 /\n" + OUT, "stability condition"),
    "probe beyond N": (CHAIN + "&record probes = 41 /\n" + OUT, "probes(1) = 41"),
    "detector site beyond N": (CHAIN + "&detect site = 40 /\n" + OUT, "site = 40"),
    "values without vary": (CHAIN + "&scene kind = 'amplitude_sweep', values = 0.1 /\n" + OUT, "vary = 'none'"),
    "amplitude_max < amplitude_min": (CHAIN + "&scene kind = 'map', amplitude_min = 2.0, amplitude_max = 1.0 /\n" +
                                      OUT, "amplitude_max"),
    "coarse_step < resolution": (CHAIN + "&scene kind = 'bifurcation', coarse_step = 0.01, resolution = 0.1 /\n" +
                                 OUT, "coarse_step"),
}

#: Inputs next to the refused ones that both must accept (each runs in a few seconds).
ACCEPTED = {
    "continuation newton": CONT.format(extra="amplitude_max = 2.0, floquet_every = 0, fold_convergence = .false., "
                                             "beyond_fold = 0, continuation_step_max = 0.5")
    + "&numerics t_final = 10.0 /\n",
    "hysteresis stairs": HYST.format(extra="amplitude_min = 1.0, amplitude_max = 1.04, stair_height = 0.02, "
                                           "stair_times = 20.0, stair_ramp = 2.0")
    + "&drive ramp_time = 5.0 /\n",
    "n with its own n0": "&chain n = 100, n0 = 80 /\n&numerics t_final = 2.0 /\n" + OUT,
}


def run(exe: str, where: Path, text: str, *args: str) -> subprocess.CompletedProcess:
    """The program run in `where` on `case.nml` holding `text`, with `args` before the file."""
    where.mkdir(parents=True, exist_ok=True)
    (where / "case.nml").write_text(text)
    return subprocess.run([exe, *args, "case.nml"], cwd=where, capture_output=True, text=True, timeout=600)


@pytest.mark.parametrize("case", sorted(REFUSED))
def test_check_refuses_what_the_run_refuses_and_nothing_is_created(exe, tmp_path, case):
    text, word = REFUSED[case]
    check = run(exe, tmp_path / "check", text, "--check")
    ran = run(exe, tmp_path / "run", text)
    for proc, where in ((check, "check"), (ran, "run")):
        lines = proc.stderr.strip().splitlines()
        assert proc.returncode == 2, (where, proc.returncode, proc.stderr)
        assert len(lines) == 1 and word in lines[0], (where, proc.stderr)
        assert sorted(p.name for p in (tmp_path / where).iterdir()) == ["case.nml"], where   # no out/, no lock
    assert check.stderr == ran.stderr


@pytest.mark.parametrize("case", sorted(ACCEPTED))
def test_check_accepts_what_the_run_accepts(exe, tmp_path, case):
    text = ACCEPTED[case]
    check = run(exe, tmp_path / "check", text, "--check")
    assert check.returncode == 0, check.stderr
    assert sorted(p.name for p in (tmp_path / "check").iterdir()) == ["case.nml"]
    ran = run(exe, tmp_path / "run", text)
    assert ran.returncode == 0, ran.stderr
    assert sorted(p.name for p in (tmp_path / "run" / "out").iterdir()) == ["s.h5"]      # and no lock left


@pytest.mark.parametrize("kind", ["map", "bifurcation", "continuation", "hysteresis"])
def test_drive_omega_on_a_frequency_axis_is_warned_about_in_one_line(exe, tmp_path, kind):
    text = CHAIN + "&drive omega = 0.85 /\n&scene kind = '" + kind + "' /\n" + OUT
    check = run(exe, tmp_path, text, "--check")
    assert check.returncode == 0, check.stderr
    lines = check.stderr.strip().splitlines()
    assert len(lines) == 1, check.stderr
    assert lines[0].startswith("warning: case.nml: &drive: omega = 0.85 is not used by &scene kind = '" + kind)
    assert "0.05 .. 1.0 by 0.05: 20 frequencies" in lines[0], lines[0]
    # the default omega, not given: nothing to say; a timeseries uses it: nothing either
    for quiet in (CHAIN + "&scene kind = '" + kind + "' /\n" + OUT, CHAIN + "&drive omega = 0.85 /\n" + OUT):
        proc = run(exe, tmp_path, quiet, "--check")
        assert proc.returncode == 0 and proc.stderr == "", proc.stderr


def test_the_run_warns_about_drive_omega_too(exe, tmp_path):
    text = CHAIN + "&drive omega = 0.85, ramp_time = 5.0 /\n&numerics t_final = 10.0 /\n" \
        "&scene kind = 'map', omega_min = 0.9, omega_max = 0.9, amplitude_min = 1.0, amplitude_max = 1.0 /\n" + OUT
    proc = run(exe, tmp_path, text)
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr.splitlines() == ["warning: case.nml: &drive: omega = 0.85 is not used by &scene kind = 'map', "
                                        "which runs omega_min .. omega_max by omega_step (0.9 .. 0.9 by 0.05: 1 "
                                        "frequency); set those for one frequency"]


@pytest.mark.parametrize("kind,key,users", [
    ("map", "stair_height = 0.05", "hysteresis"),
    ("hysteresis", "fate_push = 0.02", "continuation"),
    ("continuation", "coarse_step = 0.5", "bifurcation"),
    ("timeseries", "vary = 'gamma', values = 0.1", "amplitude_sweep, map, bifurcation, stability, continuation, "
                                                 "hysteresis"),
])
def test_a_scene_key_given_to_a_scene_that_does_not_use_it_is_one_line(exe, tmp_path, kind, key, users):
    """Each &scene key names the scenes that use it (schema.toml `scenes`); given to another scene it is warned about
    in one line by --check and the run (it has no effect); given to a scene that uses it, nothing is said."""
    axis = "" if kind == "timeseries" else "omega_min = 0.9, omega_max = 0.9, "
    text = CHAIN + f"&scene kind = '{kind}', {axis}{key} /\n" + OUT
    check = run(exe, tmp_path, text, "--check")
    assert check.returncode == 0, check.stderr
    lines = check.stderr.strip().splitlines()
    name = key.split(" =")[0]
    assert len(lines) == 1 + (name == "vary"), check.stderr      # vary and its values: one line each
    assert lines[0] == (f"warning: case.nml: &scene: {name} is not used by &scene kind = '{kind}' (only by {users}): "
                        "it has no effect"), lines[0]
    user = users.split(",")[0]
    proc = run(exe, tmp_path, CHAIN + f"&scene kind = '{user}', omega_min = 0.9, omega_max = 0.9, {key} /\n" + OUT,
               "--check")
    assert not any(f"{name} is not used" in line for line in proc.stderr.splitlines()), proc.stderr
