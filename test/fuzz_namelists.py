#!/usr/bin/env python3
"""Seeded, bounded fuzzing of the namelist reader: inputs mutated from the namelists in input/.

    python3 test/fuzz_namelists.py EXE [--count 100000] [--seed 1] [--jobs 4] [--save DIR]

Each input is written to a scratch directory and checked with `EXE --check FILE` (read and validate, run nothing).
The promise checked for every input: exit status 0 or 2, never a signal or a hang (5 s); on status 2 exactly one
line on stderr, printable ASCII, starting with `error: `; nothing written into the scratch directory; no Fortran
backtrace. The inputs are checked in batches, `EXE --check F1 F2 ...` (one line per file on stdout: `ok F` or
`error 2 F: message`, the same reader and messages in one process, like a persistent-mode fuzzer), and every
`--single`-th input also as a process of its own with the full promise above; an input whose batch crashes, hangs
or leaves files is checked again on its own. Failing inputs are printed (and saved under --save, to become
regression cases in test/fuzz_cases/). The test command runs 10,000 inputs (test/test_fuzz.py); this script runs
longer campaigns.
"""
import argparse
import os
import random
import re
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: Values that have broken readers before: extremes, non-numbers, overflowing integers, malformed literals.
EXTREMES = ["0", "-0.0", "1e308", "-1e308", "1e-310", "1e999", "-1e999", "nan", "NaN", "inf", "-Infinity",
            "2147483647", "2147483648", "-2147483649", "9223372036854775808", "99999999999999999999999",
            "-1", "1e-15", "1e-9", "1e-6", "1e12", "2000000000", "3.0e", ".5.", "1d3", "1.0q0", "+", "-",
            "''", "'", '"', ".true.", ".false.", "T", "F", "'sine-gordon'", "'newton'", "'x'*100", "1,2,3",
            "4*1.0", "0*1", "2*", "*", "1.0 2.0", "(1.0,2.0)", "''''", "&", "/", "!", "=", ",,,"]
#: Bytes inserted by byte-level mutations.
PALETTE = list("&/=,'\"!*() \t\n.-+eE0123456789abcdefxyz_") + ["\x00", "\x1b", "\x7f", "\xff", "\r", "\u00e9"]
NUMBER = re.compile(r"(?<![\w.])[-+]?(\d+\.?\d*|\.\d+)([eEdD][-+]?\d+)?")
KEY = re.compile(r"\b([A-Za-z_]\w*)\s*=")


def seeds():
    """The texts of the namelists in input/ (the corpus mutated)."""
    return [p.read_text() for p in sorted((ROOT / "input").glob("*.nml"))]


def mutate(text: str, rng: random.Random) -> str:
    """One to three random mutations of a namelist text."""
    for _ in range(rng.randint(1, 3)):
        kind = rng.randrange(12)
        n = len(text)
        i = rng.randrange(n + 1)
        j = min(n, i + rng.randint(1, 40))
        if kind == 0 and n:                                   # delete a span
            text = text[:i] + text[j:]
        elif kind == 1:                                       # insert random characters
            text = text[:i] + "".join(rng.choice(PALETTE) for _ in range(rng.randint(1, 8))) + text[i:]
        elif kind == 2 and n:                                 # duplicate a span
            text = text[:j] + text[i:j] + text[j:]
        elif kind == 3:                                       # truncate
            text = text[:i]
        elif kind in (4, 5, 6):                               # replace a number by an extreme value
            nums = list(NUMBER.finditer(text))
            if nums:
                m = rng.choice(nums)
                text = text[:m.start()] + rng.choice(EXTREMES) + text[m.end():]
        elif kind == 7:                                       # rename a key
            keys = list(KEY.finditer(text))
            if keys:
                m = rng.choice(keys)
                other = rng.choice([k.group(1) for k in keys] + ["x", "kind", "file", "n" * 70, "dt", ""])
                text = text[:m.start(1)] + other + text[m.end(1):]
        elif kind == 8:                                       # drop a structural character
            marks = [k for k, ch in enumerate(text) if ch in "=/&,'\""]
            if marks:
                k = rng.choice(marks)
                text = text[:k] + text[k + 1:]
        elif kind == 9:                                       # duplicate or drop a whole line
            lines = text.splitlines(keepends=True)
            if lines:
                k = rng.randrange(len(lines))
                lines.insert(k, lines[k]) if rng.random() < 0.5 else lines.pop(k)
                text = "".join(lines)
        elif kind == 10:                                      # a very long token
            text = text[:i] + rng.choice(["1", "a", " ", "'x", "&chain"]) * rng.choice([300, 5000, 70000]) + text[i:]
        else:                                                 # a whole-file case
            text = rng.choice(["", "\n", "! only a comment\n", "&chain /\n", "\x00" * 64, "&output /\n",
                               "&scene kind = 'map' /\n", text.replace("\n", "\r\n"), text * 2])
    return text


def check(exe: str, data: bytes, scratch: Path, timeout: float = 5.0):
    """Run `exe --check` on one input; return None when every promise holds, else the reason."""
    work = Path(tempfile.mkdtemp(dir=scratch))
    path = work / "case.nml"
    path.write_bytes(data)
    try:
        proc = subprocess.run([exe, "--check", str(path)], cwd=work, capture_output=True, timeout=timeout,
                              stdin=subprocess.DEVNULL)
    except subprocess.TimeoutExpired:
        return "hang (no answer in 5 s)"
    finally:
        left = sorted(p.name for p in work.iterdir() if p.name != "case.nml")
        for p in work.rglob("*"):
            if p.is_file():
                p.unlink()
        for p in sorted(work.rglob("*"), reverse=True):
            p.rmdir()
        work.rmdir()
    return verdict(proc.returncode, proc.stdout, proc.stderr, left)


def verdict(status, stdout: bytes, stderr: bytes, left):
    """The reason an answer breaks the promise, or None."""
    if status < 0:
        return f"signal {-status}"
    if status not in (0, 2):
        return f"exit status {status}"
    if left:
        return f"left files behind: {left}"
    text = stderr.decode("latin-1")
    if "Backtrace" in text or "Fortran runtime" in text or "Sanitizer" in text:
        return "backtrace or run-time error: " + text[:200]
    if status == 2:
        lines = text.splitlines()
        if len(lines) != 1:
            return f"{len(lines)} lines on stderr"
        if not lines[0].startswith("error: "):
            return "stderr line does not start with 'error: '"
        if any(not (32 <= ord(ch) < 127) for ch in lines[0]):
            return "unprintable character in the message"
    return None


def check_batch(exe: str, batch, scratch: Path, timeout: float = 60.0):
    """Check inputs [(index, data)] in one process; return {index: reason} for those that break the promise,
    checking each on its own when the batch as a whole crashed, hung or left files."""
    work = Path(tempfile.mkdtemp(dir=scratch))
    names = []
    for k, (_, data) in enumerate(batch):
        path = work / f"case{k:04d}.nml"
        path.write_bytes(data)
        names.append(path.name)
    try:
        proc = subprocess.run([exe, "--check", *names], cwd=work, capture_output=True, timeout=timeout,
                              stdin=subprocess.DEVNULL)
        broken = proc.returncode not in (0, 2) or proc.stderr or \
            sorted(p.name for p in work.iterdir()) != sorted(names)
    except subprocess.TimeoutExpired:
        proc, broken = None, True
    for p in work.iterdir():
        if p.is_file():
            p.unlink()
        else:
            import shutil
            shutil.rmtree(p)
    work.rmdir()
    if broken:
        return {i: r for i, d in batch if (r := check(exe, d, scratch))}
    reasons = {}
    lines = proc.stdout.decode("latin-1").splitlines()
    if len(lines) != len(batch):
        return {i: f"batch printed {len(lines)} lines for {len(batch)} files" for i, _ in batch}
    for (i, _), name, line in zip(batch, names, lines):
        if line == f"ok {name}":
            continue
        if not line.startswith(f"error 2 {name}: ") or any(not (32 <= ord(c) < 127) for c in line):
            reasons[i] = f"bad answer: {line[:200]!r}"
    return reasons


def campaign(exe: str, count: int, seed: int, jobs: int = 4, batch_size: int = 250, single: int = 20):
    """Check `count` mutated inputs; return the list of (index, reason, data) that failed."""
    rng = random.Random(seed)
    corpus = seeds()
    inputs = [mutate(rng.choice(corpus), rng).encode("utf-8", "surrogateescape") for _ in range(count)]
    indexed = list(enumerate(inputs))
    batches = [indexed[k:k + batch_size] for k in range(0, count, batch_size)]
    with tempfile.TemporaryDirectory() as scratch:
        with ThreadPoolExecutor(max_workers=jobs) as pool:
            found = {}
            for part in pool.map(lambda b: check_batch(exe, b, Path(scratch)), batches):
                found.update(part)
            sample = indexed[::single]
            for (i, _), r in zip(sample, pool.map(lambda x: check(exe, x[1], Path(scratch)), sample)):
                if r:
                    found[i] = r
    return [(i, found[i], inputs[i]) for i in sorted(found)]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("exe", help="the supratrans executable")
    ap.add_argument("--count", type=int, default=100000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--single", type=int, default=20, help="every N-th input also as a process of its own")
    ap.add_argument("--save", type=Path, help="folder for failing inputs (regression cases)")
    args = ap.parse_args(argv)
    failures = campaign(args.exe, args.count, args.seed, args.jobs, single=args.single)
    for i, reason, data in failures[:50]:
        print(f"input {i}: {reason}")
        if args.save:
            args.save.mkdir(parents=True, exist_ok=True)
            (args.save / f"seed{args.seed}_{i}.nml").write_bytes(data)
    print(f"fuzz: {args.count - len(failures)} passed, {len(failures)} failed (seed {args.seed})")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
