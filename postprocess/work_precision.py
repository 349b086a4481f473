#!/usr/bin/env python3
"""Speed against accuracy, ours against SciPy's: the scene work_precision, the SciPy peer, the charts.

Usage and options: `python3 postprocess/work_precision.py --help`; the code: supratrans_post/charts/work_precision.py.
"""
import sys

from supratrans_post.charts.work_precision import main

if __name__ == "__main__":
    sys.exit(main())
