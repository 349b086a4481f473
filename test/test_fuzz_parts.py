"""Fuzz target over part files and journals (issue 22, "Done when"): a fixed budget of mutations with a fixed seed
(random bit flips, truncations, swapped or duplicated task indices, swapped header fields, counts beyond the
limits, edited namelists; some re-sealed with their checksums recomputed, as test/part_files.py reads the format,
to reach the checks behind the checksums), each followed by `merge` (parts) or the resumed scene (journals).
Asserted for every one: no crash (no signal, no status >= 128), never exit 0 with a result that differs from the
clean one, a refusal is one line on stderr and leaves no output."""
import os
import random
import subprocess

import h5py
import numpy as np
import pytest

import compare_results
import part_files
from test_slices import TINY, sh

SEED = 22
PART_BUDGET = 120
JOURNAL_BUDGET = 80


def flip_bits(data: bytes, rng, count) -> bytes:
    b = bytearray(data)
    for _ in range(count):
        k = rng.randrange(len(b))
        b[k] ^= 1 << rng.randrange(8)
    return bytes(b)


# ------------------------------------------------------------------------------------------------ part mutations


def m_bits(path, rng):
    path.write_bytes(flip_bits(path.read_bytes(), rng, rng.choice([1, 1, 2, 4])))
    return False


def m_truncate(path, rng):
    data = path.read_bytes()
    path.write_bytes(data[:rng.randrange(len(data))])
    return False


def m_tasks(path, rng):
    with h5py.File(path, "r+") as f:
        t = f["part/task"][()]
        i, j = rng.sample(range(len(t)), 2)
        if rng.random() < 0.5:
            t[i], t[j] = t[j], t[i]
        else:
            t[i] = t[j]
        f["part/task"][...] = t
    return True


def m_header_fields(path, rng):
    with h5py.File(path) as f:
        words = f["part"].attrs["journal_header"].decode().split()
    i, j = rng.sample(range(4, len(words) - 1), 2)          # two field names; the header's CRC kept
    words[i], words[j] = words[j], words[i]
    part_files.set_attr(path, "journal_header", " ".join(words))
    return True


def m_counts(path, rng):
    name = rng.choice(["tasks_total", "tasks_in_slice", "slice_index", "slice_count"])
    value = rng.choice([2**31 - 1, -2**31, 0, -1, 10**7 + 1, 3, 9, 16, 100000, 100001])
    part_files.set_attr(path, name, np.int32(value))
    return True


def m_namelist(path, rng):
    with h5py.File(path, "r+") as f:
        text = f["part/namelist"][()]
        k = rng.randrange(len(text))
        text = text[:k] + bytes([text[k] ^ (1 << rng.randrange(7))]) + text[k + 1:]
        del f["part/namelist"]
        f["part/namelist"] = np.bytes_(text)
    return True


def m_values(path, rng):
    with h5py.File(path, "r+") as f:
        v = f["part/values"][()]
        flat = v.reshape(-1).view("<u8")
        flat[rng.randrange(flat.size)] ^= np.uint64(1) << np.uint64(rng.randrange(64))
        f["part/values"][...] = v
    return False                                # never re-sealed: a forged value is no corruption to find


PART_MUTATIONS = [m_bits, m_bits, m_bits, m_truncate, m_tasks, m_header_fields, m_counts, m_namelist, m_values]


# ------------------------------------------------------------------------------------------------ journal mutations


def j_bits(lines, rng):
    data = "".join(lines).encode()
    return flip_bits(data, rng, rng.choice([1, 2, 3]))


def j_truncate(lines, rng):
    data = "".join(lines).encode()
    return data[:rng.randrange(len(data))]


def j_header_fields(lines, rng):
    words = lines[0].split()
    i, j = rng.sample(range(4, len(words) - 1), 2)
    words[i], words[j] = words[j], words[i]
    return (" ".join(words) + "\n" + "".join(lines[1:])).encode()


def j_task_index(lines, rng):
    k = rng.randrange(1, len(lines))
    words = lines[k].split(" ")
    words[0] = str(rng.choice([0, -1, 2**31 - 1, 1, 2, 3, 8, 9]))
    lines = lines[:k] + [" ".join(words)] + lines[k + 1:]
    return "".join(lines).encode()


def j_swap_tasks(lines, rng):
    i, j = rng.sample(range(1, len(lines)), 2)
    a, b = lines[i].split(" ", 1), lines[j].split(" ", 1)
    lines = list(lines)
    lines[i], lines[j] = a[0] + " " + b[1], b[0] + " " + a[1]
    return "".join(lines).encode()


def j_reorder(lines, rng):
    body = list(lines[1:])
    rng.shuffle(body)
    if rng.random() < 0.5:
        body.append(rng.choice(body))
    return (lines[0] + "".join(body)).encode()


JOURNAL_MUTATIONS = [j_bits, j_bits, j_truncate, j_header_fields, j_task_index, j_swap_tasks, j_reorder]


# ------------------------------------------------------------------------------------------------ the target


@pytest.fixture(scope="module")
def seeds(exe, tmp_path_factory):
    """The clean result, two parts and a journal of a scene stopped after 3 of its 8 tasks."""
    base = tmp_path_factory.mktemp("fuzz")
    (base / "study.nml").write_text(TINY)
    sh(exe, "study.nml", cwd=base)
    (base / "out" / "study.h5").rename(base / "reference.h5")
    parts = []
    for i in (1, 2):
        sh(exe, "study.nml", "--slice", f"{i}/2", cwd=base)
        parts.append((base / "out" / f"study.part-{i}-of-2.h5").read_bytes())
    proc = subprocess.run([exe, "study.nml"], cwd=base, capture_output=True, text=True,
                          env=dict(os.environ, SUPRATRANS_STOP_AFTER="3", OMP_NUM_THREADS="1"))
    assert proc.returncode == 5, proc.stderr
    journal = (base / "out" / "study.h5.journal").read_text()
    return base / "reference.h5", parts, journal


def check(proc, reference, output, what):
    assert 0 <= proc.returncode < 128, f"{what}: crashed ({proc.returncode}): {proc.stderr[-2000:]}"
    if proc.returncode == 0:
        diffs, compared, _ = compare_results.compare(reference, output)
        assert compared > 5 and not diffs, f"{what}: exit 0 with a different result: {diffs}"
    else:
        lines = proc.stderr.strip().splitlines()
        assert len(lines) == 1, f"{what}: not one line: {proc.stderr[-2000:]}"
        assert not output.exists(), f"{what}: refused, yet {output} written"
    return proc.returncode


def clear(out):
    for p in out.iterdir():
        if p.name.startswith("study.h5"):
            p.unlink()


@pytest.mark.slow
def test_fuzz_parts_and_merge(exe, tmp_path, seeds):
    reference, parts, _ = seeds
    (tmp_path / "out").mkdir()
    rng = random.Random(SEED)
    paths = [tmp_path / "out" / f"study.part-{i}-of-2.h5" for i in (1, 2)]
    outcomes = {}
    for k in range(PART_BUDGET):
        clear(tmp_path / "out")
        for p, data in zip(paths, parts):
            p.write_bytes(data)
        mutation = rng.choice(PART_MUTATIONS)
        victim = rng.choice(paths)
        try:
            reseal = mutation(victim, rng) and rng.random() < 0.6
            if reseal:
                part_files.reseal(victim)
        except (OSError, KeyError, ValueError):
            reseal = False                    # h5py cannot open what the bits left: merge must refuse it too
        what = f"part mutation {k} ({mutation.__name__} of {victim.name}, resealed {reseal})"
        proc = subprocess.run([exe, "merge", *paths], cwd=tmp_path, capture_output=True, text=True, timeout=120)
        status = check(proc, reference, tmp_path / "out" / "study.h5", what)
        outcomes[status] = outcomes.get(status, 0) + 1
    print("merge exit statuses over", PART_BUDGET, "mutations:", outcomes)
    assert outcomes.get(2, 0) > PART_BUDGET // 2


@pytest.mark.slow
def test_fuzz_journals_and_resume(exe, tmp_path, seeds):
    reference, _, journal = seeds
    (tmp_path / "study.nml").write_text(TINY)
    (tmp_path / "out").mkdir()
    rng = random.Random(SEED + 1)
    lines = journal.splitlines(keepends=True)
    outcomes = {}
    for k in range(JOURNAL_BUDGET):
        clear(tmp_path / "out")
        mutation = rng.choice(JOURNAL_MUTATIONS)
        (tmp_path / "out" / "study.h5.journal").write_bytes(mutation(lines, rng))
        proc = subprocess.run([exe, "study.nml"], cwd=tmp_path, capture_output=True, text=True, timeout=120)
        status = check(proc, reference, tmp_path / "out" / "study.h5", f"journal mutation {k} ({mutation.__name__})")
        outcomes[status] = outcomes.get(status, 0) + 1
    print("resume exit statuses over", JOURNAL_BUDGET, "mutations:", outcomes)
    assert outcomes.get(0, 0) > 0 and outcomes.get(4, 0) > 0
