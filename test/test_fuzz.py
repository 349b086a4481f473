"""Fuzzed reader: 10,000 inputs mutated from input/*.nml (seeded, bounded), the special files a user can hand the
program, and every input that ever failed (test/fuzz_cases/). The promise: exit status 0 or 2, one printable line
on error, never a signal, a hang, a backtrace or a file left behind. Longer campaigns: test/fuzz_namelists.py."""
import os
import subprocess
from pathlib import Path

import pytest

import fuzz_namelists as fuzz

CASES = Path(__file__).resolve().parent / "fuzz_cases"


@pytest.mark.slow
def test_campaign_of_ten_thousand_inputs(exe):
    failures = fuzz.campaign(exe, count=10_000, seed=20261123, jobs=4)
    assert not failures, "\n".join(f"input {i}: {r}: {d[:120]!r}" for i, r, d in failures[:10])


@pytest.mark.parametrize("case", sorted(p.name for p in CASES.glob("*.nml")))
def test_regression_case(exe, tmp_path, case):
    reason = fuzz.check(exe, (CASES / case).read_bytes(), tmp_path)
    assert reason is None, f"{case}: {reason}"


def special(exe, path, tmp_path):
    proc = subprocess.run([exe, "--check", str(path)], cwd=tmp_path, capture_output=True, timeout=10,
                          stdin=subprocess.DEVNULL)
    return proc, fuzz.verdict(proc.returncode, proc.stdout, proc.stderr, [])


@pytest.mark.parametrize("name", ["fifo", "dev_zero", "directory", "missing", "dev_null"])
def test_special_files_are_refused_in_one_line(exe, tmp_path, name):
    """A FIFO with no writer, an endless file, a directory, a missing file, an empty device: one line, exit 2."""
    if name == "fifo":
        path = tmp_path / "input.nml"
        os.mkfifo(path)
    elif name == "dev_zero":
        path = Path("/dev/zero")
    elif name == "directory":
        path = tmp_path
    elif name == "dev_null":
        path = Path("/dev/null")
    else:
        path = tmp_path / "nowhere.nml"
    proc, reason = special(exe, path, tmp_path)
    assert reason is None, reason
    assert proc.returncode == 2, proc.stderr
