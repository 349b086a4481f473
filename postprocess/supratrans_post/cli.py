"""What the command lines share: a parser whose errors are one line, the checked `--dpi`, and the supratrans
checkout the commands run in (where fpm builds, input/ and postprocess/figures/ are).

Every command parses its arguments before it does anything else, so `--help` and a wrong option only print.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .reader import PlotError

#: Resolutions accepted by --dpi: 600 is more than a journal asks for; above some thousands an image of these
#: figures no longer fits in memory (or in the 2^16 pixels a side that matplotlib's Agg can draw).
DPI_RANGE = (10, 600)


class Parser(argparse.ArgumentParser):
    """An argparse parser whose errors are the one line `error: <what is wrong> (see <prog> --help)`, exit 2."""

    def error(self, message: str):  # noqa: D102 (argparse's)
        self.exit(2, f"error: {' '.join(message.split())} (see {self.prog} --help)\n")


def parser(prog: str, doc: str, argv: list[str] | None = None) -> Parser:
    """The parser of a command: description and epilog from its module documentation `doc`; its name `prog` when
    called with arguments (tests, other commands), else the name it was started as (`plot.py`, `supratrans-plot`)."""
    name = Path(sys.argv[0]).name if argv is None and sys.argv and sys.argv[0] else prog
    if name in ("", "-c", "__main__.py"):
        name = prog
    return Parser(prog=name, description=doc.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter,
                  epilog="\n\n".join(doc.split("\n\n")[1:]))


def dpi(text: str) -> int:
    """The value of --dpi: an integer within DPI_RANGE (argparse prints the ValueError's message)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a whole number of dots per inch") from None
    lo, hi = DPI_RANGE
    if not lo <= value <= hi:
        raise argparse.ArgumentTypeError(f"{value} dots per inch is outside {lo} .. {hi}")
    return value


def checkout(start: Path | None = None) -> Path | None:
    """The supratrans checkout: the one this package lies in (postprocess/supratrans_post/), else the first of
    `start` (default: the working directory) and the folders above it that holds fpm.toml and postprocess/; None
    when there is none (an installed package run elsewhere)."""
    here = Path(__file__).resolve().parents[2]
    for folder in (here, *(lambda p: (p, *p.parents))((start or Path.cwd()).resolve())):
        if (folder / "fpm.toml").is_file() and (folder / "postprocess").is_dir():
            return folder
    return None


def repository() -> Path:
    """The checkout (`checkout`); PlotError when there is none."""
    root = checkout()
    if root is None:
        raise PlotError(Path.cwd(), "not in a supratrans checkout (no fpm.toml with postprocess/ here or above)")
    return root
