#!/usr/bin/env python3
"""Whole-process time of the default release build against the host build (the machine's vector units) and the
statically linked builds, and against the naive program.

Usage and options: `python3 postprocess/builds.py --help`; the code is in supratrans_post/builds.py.
"""
import sys

from supratrans_post.builds import main

if __name__ == "__main__":
    sys.exit(main())
