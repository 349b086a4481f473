#!/usr/bin/env python3
"""Compare the result datasets of two sets of supratrans HDF5 files, bit for bit.

    python3 test/compare_results.py BEFORE_DIR AFTER_DIR     # e.g. out/quick of two checkouts

Every `*.h5` file of BEFORE_DIR is matched by name in AFTER_DIR; every dataset of the first must exist in the second
with the same shape and the same values (NaN equal to NaN, bit for bit otherwise). Timings are not results and are
skipped: datasets whose path contains `wall_time`, `cpu_time`, `lower_bound` or `clock`, /provenance (how the file was
made, not what it holds) and /parameters/schema (the table of every key the input could have: it grows with each
new key; the values of the keys are in /parameters' attributes) with its row axis /parameter (the keys' names). Datasets that only AFTER has are listed
as added. Exit status 0 when everything compared is identical, 1 otherwise.

A refactor changes no result: run `python3 postprocess/make_figures.py --quick` in both checkouts and compare.
"""
import sys
from pathlib import Path

import h5py
import numpy as np

SKIP = ("wall_time", "cpu_time", "lower_bound", "clock", "provenance", "parameters/schema")
SKIP_EXACT = ("parameter",)   # the row axis (dimension scale) of /parameters/schema: one entry per possible key


def datasets(f):
    """Paths of every dataset of an open file."""
    out = []
    f.visititems(lambda name, obj: out.append(name) if isinstance(obj, h5py.Dataset) else None)
    return out


def same(a, b):
    """Whether two arrays are identical (NaN == NaN; strings by value)."""
    if a.shape != b.shape:
        return False
    if a.dtype.kind in "fc" and b.dtype.kind in "fc":
        return bool(np.array_equal(a, b, equal_nan=True))
    return bool(np.array_equal(a, b))


def compare(before, after):
    """Compare two files; return (differences, compared, added)."""
    diffs, compared = [], 0
    with h5py.File(before, "r") as fa, h5py.File(after, "r") as fb:
        names_a, names_b = datasets(fa), set(datasets(fb))
        for name in names_a:
            if any(s in name for s in SKIP) or name in SKIP_EXACT:
                continue
            if name not in names_b:
                diffs.append(f"{name}: missing after")
                continue
            a, b = fa[name][()], fb[name][()]
            compared += 1
            if not same(np.asarray(a), np.asarray(b)):
                diffs.append(f"{name}: values differ")
        added = sorted(n for n in names_b - set(names_a)
                       if not (any(s in n for s in SKIP) or n in SKIP_EXACT))   # how it was made: no result
    return diffs, compared, added


def main(argv):
    if len(argv) != 3:
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    before, after = Path(argv[1]), Path(argv[2])
    files = sorted(before.glob("*.h5"))
    if not files:
        print(f"error: {before}: no .h5 files", file=sys.stderr)
        return 2
    bad = 0
    for fa in files:
        fb = after / fa.name
        if not fb.exists():
            print(f"{fa.name}: missing in {after}")
            bad += 1
            continue
        diffs, compared, added = compare(fa, fb)
        state = "identical" if not diffs else f"{len(diffs)} DIFFER"
        extra = f", {len(added)} added" if added else ""
        print(f"{fa.name}: {compared} datasets compared, {state}{extra}")
        for d in diffs:
            print(f"    {d}")
        bad += bool(diffs)
    print(f"{len(files) - bad} of {len(files)} files identical")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
