#!/usr/bin/env python3
"""Run every scene of input/ and draw every figure of the paper into one folder.

Usage and options: `python3 postprocess/make_figures.py --help`; the code is in supratrans_post/runner.py.
"""
import sys

from supratrans_post.runner import main

if __name__ == "__main__":
    sys.exit(main())
