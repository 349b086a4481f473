"""What the command lines share: a parser whose errors are one line, the checked `--dpi`, the supratrans
checkout the commands run in (where fpm builds, input/ and postprocess/figures/ are) or the `supratrans` installed
on PATH that runs namelists outside one, and the progress lines of a long wait.

Every command parses its arguments before it does anything else, so `--help` and a wrong option only print.
"""
from __future__ import annotations

import argparse
import math
import os
import shutil
import sys
import time
from pathlib import Path
from typing import TextIO

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


def repository(given: Path | None = None, option: str = "") -> Path:
    """The checkout: `given` when the command was told one (option `option`, named in the error), else
    `checkout()`; PlotError when it is not one, or there is none (the message names `option` when there is one)."""
    if given is not None:
        folder = Path(given).resolve()
        if not ((folder / "fpm.toml").is_file() and (folder / "postprocess").is_dir()):
            raise PlotError(given, f"not a supratrans checkout (no fpm.toml with postprocess/ in it){_given(option)}")
        return folder
    root = checkout()
    if root is None:
        raise PlotError(Path.cwd(), "not in a supratrans checkout (no fpm.toml with postprocess/ here or above)"
                        + (f": give one with {option}" if option else ""))
    return root


def _given(option: str) -> str:
    """`" (option)"` when there is an option, else nothing."""
    return f" ({option})" if option else ""


def installed(what: str) -> str:
    """The `supratrans` program on PATH, which runs namelists outside a checkout (README: `fpm install`); PlotError
    saying what to give instead (`what`) when there is none."""
    found = shutil.which("supratrans")
    if found is None:
        raise PlotError(Path.cwd(), "not in a supratrans checkout and no `supratrans` on PATH (README: "
                        f"`fpm install`): {what}")
    return found


#: Seconds between two progress lines, at least (SUPRATRANS_PROGRESS_EVERY, as the program's own; the interval grows
#: to a tenth of the time elapsed, so an hour's wait prints some tens of lines).
PROGRESS_EVERY = 4.0


def progress_every() -> float:
    """The least interval (s) between two progress lines: SUPRATRANS_PROGRESS_EVERY when it is a finite number > 0,
    else PROGRESS_EVERY: the rule by which the program reads it (`progress_every_setting`, supratrans_progress)."""
    try:
        every = float(os.environ.get("SUPRATRANS_PROGRESS_EVERY", ""))
    except ValueError:
        return PROGRESS_EVERY
    return every if 0.0 < every < math.inf else PROGRESS_EVERY


class Progress:
    """The progress of a long wait on standard error, as the program prints its own: `  LABEL: 3/20 WHAT, 12 s
    elapsed, about 40 s left`. At most one line every PROGRESS_EVERY seconds (SUPRATRANS_PROGRESS_EVERY overrides
    it) or a tenth of the time elapsed, whichever is longer, and none before the first interval: a short wait
    prints nothing. The time left is the time per unit of work so far times the work left, the work of each item
    given by `weights` (default 1 each; a solve at a tighter tolerance costs more)."""

    def __init__(self, label: str, weights: list[float] | int, what: str = "done", stream: TextIO | None = None):
        self.label, self.what = label, what
        self.weights = [1.0] * weights if isinstance(weights, int) else [float(w) for w in weights]
        self.stream = stream or sys.stderr
        self.every = progress_every()
        self.start = self.last = time.monotonic()
        self.done = 0

    def step(self, count: int = 1) -> None:
        """`count` more items done; a line when the interval has passed."""
        self.done = min(self.done + count, len(self.weights))
        now = time.monotonic()
        elapsed = now - self.start
        if now - self.last < max(self.every, 0.1 * elapsed):
            return
        self.last = now
        self.stream.write(self.line(elapsed) + "\n")
        self.stream.flush()

    def line(self, elapsed: float) -> str:
        """The progress line after `elapsed` seconds."""
        done, left = sum(self.weights[:self.done]), sum(self.weights[self.done:])
        text = f"  {self.label}: {self.done}/{len(self.weights)} {self.what}, {elapsed:.0f} s elapsed"
        if done > 0:
            text += f", about {elapsed / done * left:.0f} s left"
        return text
