"""Independent readings of the checksums supratrans writes (docs/failures.md, "Parts and journals"), so that the
tests can forge a part or a journal whose checksums hold and reach the checks behind them.

- `text_fingerprint(text)`: the input's fingerprint (supratrans_strings::text_fingerprint);
- `journal_header_crc(body)`: the header line `body *XXXXXXXX`; `journal_record(header, body)`: a record bound to it;
- `part_checksum(path)`: the checksum a part file should carry (format 3: with the line of where and when the
  slice ran); `reseal(path)`: write it into the part.
"""
from __future__ import annotations

import zlib

import h5py
import numpy as np


def text_fingerprint(text: bytes) -> str:
    h1, h2, m = 1, 7, 2147483647
    for b in text:
        h1 = (h1 * 31 + b) % m
        h2 = (h2 * 131 + b) % m
    return f"{h1:08X}-{h2:08X}"


def journal_header_crc(body: str) -> str:
    return f"{body} *{zlib.crc32(body.encode()):08X}"


def journal_record(header: str, body: str) -> str:
    """A journal line `body *XXXXXXXX` whose CRC starts from the header line and a newline."""
    return f"{body} *{zlib.crc32(body.encode(), zlib.crc32((header + chr(10)).encode())):08X}"


def _text(value) -> bytes:
    if isinstance(value, np.ndarray):
        value = value[()]
    return value if isinstance(value, bytes) else str(value).encode()


def part_checksum(path) -> str:
    with h5py.File(path, "r") as f:
        part = f["part"]
        a = part.attrs
        head = b"\n".join([b"supratrans-part " + _text(a["part_format"]), _text(f.attrs["version"]),
                           _text(f.attrs["scene"])] + [str(int(a[k])).encode() for k in
                                                       ("slice_index", "slice_count", "tasks_total", "tasks_in_slice")]
                          + [_text(a[k]) for k in ("journal_header", "fingerprint", "input_file")]) + b"\n"
        crc = zlib.crc32(head)
        crc = zlib.crc32(_text(part["namelist"][()]) + b"\n", crc)
        tasks = part["task"][()]
        values = part["values"][()]
        for t, row in zip(tasks, values):
            bits = np.asarray(row, dtype="<f8").view("<u8")
            crc = zlib.crc32((str(int(t)) + "".join(f" {int(b):016X}" for b in bits) + "\n").encode(), crc)
        mantissa, exponent = f"{float(a['wall_time_s']):.16E}".split("E")
        run = b"\t".join([_text(a["host"]), _text(a["started"]), _text(a["ended"]),
                          f"{mantissa}E{int(exponent):+04d}".encode(), str(int(a["threads"])).encode(),
                          _text(a["git_commit"])])
        crc = zlib.crc32(run + b"\n", crc)
    return f"{crc:08X}"


def set_attr(path, name, value, where="part"):
    """Replace an attribute of a part, keeping its kind (a string stays a fixed-length string)."""
    with h5py.File(path, "r+") as f:
        obj = f[where]
        if isinstance(value, str):
            obj.attrs.create(name, np.bytes_(value.encode()))
        else:
            obj.attrs.create(name, value, dtype=obj.attrs[name].dtype if name in obj.attrs else None)


def reseal(path):
    """Write the checksum the part's content has (as a forger would)."""
    set_attr(path, "checksum", part_checksum(path))
