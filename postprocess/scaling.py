#!/usr/bin/env python3
"""Time and memory of supratrans against the chain length N, the final time T and the number of runs.

Usage and options: `python3 postprocess/scaling.py --help`; the code is in supratrans_post/scaling.py.
"""
import sys

from supratrans_post.scaling import main

if __name__ == "__main__":
    sys.exit(main())
