"""Shared fixtures of the Python tests: the program, built once per session."""
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(Path(__file__).resolve().parent))


@pytest.fixture(scope="session")
def exe():
    """Path of the supratrans executable (debug profile, built by fpm)."""
    subprocess.run(["fpm", "build"], cwd=ROOT, check=True, capture_output=True)
    out = subprocess.run(["fpm", "run", "--runner", "echo"], cwd=ROOT, check=True, capture_output=True, text=True)
    return str(ROOT / out.stdout.strip().splitlines()[-1].split()[0])
