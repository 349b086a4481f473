"""Run AUTO-07p on the chain of test/auto/mol.f90.in from A = 0 to its first fold, in a scratch folder, and print one
JSON line: the fold's amplitude and period, the number of continuation points, AUTO's wall time.

    python3 test/auto/run_mol.py WORKDIR '{"n": 10, "n0": 6, "omega": 0.9, ...}'

WORKDIR receives mol.f90 (a copy of mol.f90.in), c.mol and everything AUTO writes (its compiled equations,
fort.7/8/9): nothing is written anywhere else. The keys of the JSON argument (all optional): n, n0, c, omega,
kappa, sigma, gamma, beta, m2, potential (1 sine-Gordon, 2 Klein-Gordon), and any AUTO constant in capitals (NTST,
DSMAX, ...). AUTO is found through AUTO_DIR (default /usr/lib/auto-07p, where the Debian package `auto-07p` puts it); OMP_NUM_THREADS
limits the threads of its OpenMP build.
"""
from __future__ import annotations

import contextlib
import json
import math
import os
import shutil
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
#: Point types of an AUTO b-file (fort.7) that mark a fold: 2 (algebraic problems), 5 (boundary value problems).
FOLD_TYPES = (2, 5)


def fold_from_bfile(path: Path) -> dict:
    """The first fold of AUTO's b-file `path` (fort.7): its point number, A = PAR(1) and the period PAR(11) (the
    last column, ICP = [1, 11]), and how many points the branch has. Raises ValueError when there is no fold."""
    points, fold = 0, None
    for line in path.read_text().splitlines():
        words = line.split()
        if len(words) < 6 or words[0] == "0":
            continue
        points += 1
        if fold is None and abs(int(words[2])) in FOLD_TYPES:
            fold = {"point": int(words[1]), "amplitude": float(words[4]), "period": float(words[-1])}
    if fold is None:
        raise ValueError(f"no fold (LP) on the branch of {path} ({points} points)")
    return dict(fold, points=points)


def run(workdir: Path, case: dict) -> dict:
    """Continue the periodic orbits of `case` (see the module documentation) in `workdir` with AUTO-07p; the fold."""
    auto_dir = Path(os.environ.get("AUTO_DIR", "/usr/lib/auto-07p"))
    sys.path.insert(0, str(auto_dir / "python"))
    os.environ["AUTO_DIR"] = str(auto_dir)
    import auto  # noqa: PLC0415 (AUTO's package lives outside sys.path until AUTO_DIR is known)

    workdir.mkdir(parents=True, exist_ok=True)
    shutil.copy(HERE / "mol.f90.in", workdir / "mol.f90")  # not .f90 in test/: fpm would compile it
    shutil.copy(HERE / "c.mol", workdir / "c.mol")
    n = int(case.get("n", 10))
    omega = float(case.get("omega", 0.9))
    par = {1: 0.0, 2: omega, 3: float(case.get("c", 4.0)), 4: float(case.get("n0", 6)),
           5: float(case.get("kappa", 0.5)), 6: float(case.get("sigma", 1.0)), 7: float(case.get("gamma", 0.0)),
           8: float(case.get("beta", 0.0)), 9: float(case.get("m2", 0.0)), 10: float(case.get("potential", 1)),
           11: 2.0 * math.pi / omega}
    constants = {k: v for k, v in case.items() if k.isupper()}
    start = time.perf_counter()
    with contextlib.chdir(workdir):
        auto.run(e="mol", c="mol", NDIM=2 * n + 2, PAR=par, **constants)
    seconds = time.perf_counter() - start
    return dict(fold_from_bfile(workdir / "fort.7"), seconds=seconds)


if __name__ == "__main__":
    result = run(Path(sys.argv[1]), json.loads(sys.argv[2]) if len(sys.argv) > 2 else {})
    print(json.dumps(result))
