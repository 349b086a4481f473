"""Parts and journals that are not whole, not of their input or not of their scene are refused in one line
(issue 22, items 4-6; docs/failures.md, "Parts and journals"). Each case was merged or resumed into a wrong result
with exit 0, or crashed, before part files and journal headers carried checksums bound to their input.
The forged cases recompute the checksums (test/part_files.py, an independent reading of the format) to reach the
checks behind them."""
import os
import subprocess

import h5py
import numpy as np
import pytest

import compare_results
import part_files
from test_slices import BIF, TINY, sh


def identical(a, b):
    diffs, compared, _ = compare_results.compare(a, b)
    assert compared > 5 and not diffs, diffs


@pytest.fixture(scope="module")
def clean(exe, tmp_path_factory):
    """Three parts of the small bifurcation study, and the single-machine file."""
    base = tmp_path_factory.mktemp("parts")
    (base / "study.nml").write_text(BIF)
    for i in (1, 2, 3):
        sh(exe, "study.nml", "--slice", f"{i}/3", cwd=base)
    sh(exe, "merge", *sorted((base / "out").glob("study.part-*.h5")), cwd=base)
    (base / "out" / "study.h5").rename(base / "whole.h5")
    return base


@pytest.fixture()
def parts(clean, tmp_path):
    (tmp_path / "out").mkdir()
    for p in (clean / "out").glob("study.part-*.h5"):
        (tmp_path / "out" / p.name).write_bytes(p.read_bytes())
    return tmp_path


def part(cwd, i):
    return cwd / "out" / f"study.part-{i}-of-3.h5"


def refused(exe, cwd, *words, status=2):
    proc = sh(exe, "merge", *(part(cwd, i) for i in (1, 2, 3)), cwd=cwd, check=False)
    assert proc.returncode == status, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    for w in words:
        assert w in lines[0], lines[0]
    assert not (cwd / "out" / "study.h5").exists()
    assert not (cwd / "out" / "study.h5.journal").exists()
    return lines[0]


def test_the_checksum_is_the_documented_one(clean):
    for i in (1, 2, 3):
        with h5py.File(part(clean, i)) as f:
            stored = f["part"].attrs["checksum"].decode()
            text = f["part/namelist"][()]
            assert f["part"].attrs["fingerprint"].decode() == part_files.text_fingerprint(text)
        assert stored == part_files.part_checksum(part(clean, i))


def test_a_flipped_bit_in_a_value_is_refused(exe, parts):
    with h5py.File(part(parts, 2), "r+") as f:
        v = f["part/values"]
        row = v[1].copy()
        row.view("<u8")[0] ^= 1              # the last bit of the first value of the second record
        v[1] = row
    refused(exe, parts, "study.part-2-of-3.h5", "checksum")


@pytest.mark.parametrize("how", ["swapped", "duplicated"])
def test_task_indices_not_each_once_are_refused(exe, parts, how):
    with h5py.File(part(parts, 1), "r+") as f:
        t = f["part/task"][()]
        t[[0, 1]] = t[[1, 0]] if how == "swapped" else t[[0, 0]]
        f["part/task"][...] = t
    refused(exe, parts, "study.part-1-of-3.h5", "checksum")
    part_files.reseal(part(parts, 1))
    refused(exe, parts, "study.part-1-of-3.h5", "exactly once")


def test_an_edited_namelist_with_its_old_fingerprint_is_refused(exe, parts):
    for i in (1, 2, 3):
        with h5py.File(part(parts, i), "r+") as f:
            text = f["part/namelist"][()].replace(b"t_final = 40.0", b"t_final = 30.0")
            del f["part/namelist"]
            f["part/namelist"] = np.bytes_(text)
    refused(exe, parts, "study.part-1-of-3.h5", "checksum")
    for i in (1, 2, 3):
        part_files.reseal(part(parts, i))
    refused(exe, parts, "study.part-1-of-3.h5", "fingerprint", "edited")


@pytest.mark.parametrize("total", [2**31 - 1, 10**8, -5, 0])
def test_a_task_count_beyond_the_limits_is_one_line(exe, parts, total):
    for i in (1, 2, 3):
        part_files.set_attr(part(parts, i), "tasks_total", np.int32(total))
        part_files.reseal(part(parts, i))
    refused(exe, parts, "study.part-1-of-3.h5", "tasks_total = " + str(total))


def test_a_part_of_another_field_set_is_refused_not_recomputed(exe, parts):
    for i in (1, 2, 3):
        with h5py.File(part(parts, i)) as f:
            body = f["part"].attrs["journal_header"].decode().rsplit(" *", 1)[0]
        header = part_files.journal_header_crc(body.replace(" rounds ", " rounds_total "))
        part_files.set_attr(part(parts, i), "journal_header", header)
        part_files.reseal(part(parts, i))
    line = refused(exe, parts, "study.part-1-of-3.h5", "do not fit the scene 'bifurcation'")
    assert "rounds" in line


def test_a_part_of_the_format_before_checksums_is_refused(exe, parts, clean):
    with h5py.File(part(parts, 3), "r+") as f:
        del f["part"].attrs["checksum"]
        del f["part"].attrs["part_format"]
    refused(exe, parts, "study.part-3-of-3.h5", "format changed", "delete it and run its slice again")
    part(parts, 3).unlink()                   # as the message says
    (parts / "study.nml").write_text(BIF)
    sh(exe, "study.nml", "--slice", "3/3", cwd=parts)
    sh(exe, "merge", *(part(parts, i) for i in (1, 2, 3)), cwd=parts)
    identical(clean / "whole.h5", parts / "out" / "study.h5")


def test_the_clean_parts_still_merge_to_the_single_machine_file(exe, parts, clean):
    sh(exe, "merge", *(part(parts, i) for i in (1, 2, 3)), cwd=parts)
    identical(clean / "whole.h5", parts / "out" / "study.h5")


# ------------------------------------------------------------------------------------------------ journals


def stopped(exe, cwd, text, after=4):
    """Run a sweep stopped after `after` tasks; the journal's lines."""
    proc = subprocess.run([exe, "study.nml"], cwd=cwd, capture_output=True, text=True,
                          env=dict(os.environ, SUPRATRANS_STOP_AFTER=str(after), OMP_NUM_THREADS="1"))
    assert proc.returncode == 5, proc.stderr
    return (cwd / "out" / "study.h5.journal").read_text().splitlines(keepends=True)


@pytest.fixture()
def reference(exe, tmp_path):
    (tmp_path / "study.nml").write_text(TINY)
    sh(exe, "study.nml", cwd=tmp_path)
    (tmp_path / "out" / "study.h5").rename(tmp_path / "reference.h5")
    return tmp_path / "reference.h5"


def resume(exe, cwd, status=0):
    proc = sh(exe, "study.nml", cwd=cwd, check=False)
    assert proc.returncode == status, proc.stderr
    return proc


def test_a_line_of_another_inputs_journal_is_not_taken(exe, tmp_path, reference):
    other = TINY.replace("t_final = 5.0", "t_final = 6.0")
    (tmp_path / "study.nml").write_text(other)
    foreign = stopped(exe, tmp_path, other)
    (tmp_path / "out" / "study.h5.journal").unlink()
    (tmp_path / "study.nml").write_text(TINY)
    mine = stopped(exe, tmp_path, TINY)
    assert foreign[2].split()[0] == mine[2].split()[0] and foreign[2] != mine[2]
    mine[2] = foreign[2]                      # a whole line, valid CRC, same task, same fields: another input
    (tmp_path / "out" / "study.h5.journal").write_text("".join(mine))
    resume(exe, tmp_path)
    identical(reference, tmp_path / "out" / "study.h5")


def test_swapped_field_names_in_the_header_are_refused(exe, tmp_path, reference):
    lines = stopped(exe, tmp_path, TINY)
    words = lines[0].split()
    a, b = 5, 6                               # two field names (after 'supratrans-journal 4 <tasks> <fingerprint>')
    words[a - 1], words[b - 1] = words[b - 1], words[a - 1]
    lines[0] = " ".join(words) + "\n"
    (tmp_path / "out" / "study.h5.journal").write_text("".join(lines))
    proc = resume(exe, tmp_path, status=4)
    err = proc.stderr.strip().splitlines()
    assert len(err) == 1 and "header fails its checksum" in err[0], proc.stderr
    assert not (tmp_path / "out" / "study.h5").exists()


def test_a_journal_of_the_old_format_is_refused(exe, tmp_path, reference):
    lines = stopped(exe, tmp_path, TINY)
    body = lines[0].rsplit(" *", 1)[0].replace("supratrans-journal 4 ", "supratrans-journal 3 ", 1)
    lines[0] = body + "\n"
    (tmp_path / "out" / "study.h5.journal").write_text("".join(lines))
    proc = resume(exe, tmp_path, status=4)
    err = proc.stderr.strip().splitlines()
    assert len(err) == 1 and "format changed" in err[0] and "delete it" in err[0], proc.stderr


def test_records_are_bound_to_the_documented_header(exe, tmp_path, reference):
    lines = stopped(exe, tmp_path, TINY)
    header = lines[0].rstrip("\n")
    assert header == part_files.journal_header_crc(header.rsplit(" *", 1)[0])
    assert header.split()[3] == part_files.text_fingerprint((tmp_path / "study.nml").read_bytes())
    for line in lines[1:]:
        assert line.rstrip("\n") == part_files.journal_record(header, line.rsplit(" *", 1)[0])
    resume(exe, tmp_path)
    identical(reference, tmp_path / "out" / "study.h5")
