#!/usr/bin/env python3
"""Draw the figure of one supratrans HDF5 file (or Fig. 1 from its four timeseries files).

Usage and options: `python3 postprocess/plot.py --help`; the code is in supratrans_post/plot.py.
"""
import sys

from supratrans_post.plot import main

if __name__ == "__main__":
    sys.exit(main())
