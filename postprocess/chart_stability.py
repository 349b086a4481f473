#!/usr/bin/env python3
"""Chart of the scene stability: the largest stable time step of each integrator against the coupling c.

Usage and options: `python3 postprocess/chart_stability.py --help`; the code is in supratrans_post/charts/stability.py.
"""
import sys

from supratrans_post.charts.stability import main

if __name__ == "__main__":
    sys.exit(main())
