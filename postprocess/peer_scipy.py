#!/usr/bin/env python3
"""SciPy peer of supratrans: the paper's chain integrated with scipy.integrate.solve_ivp, timed and scored.

Usage and options: `python3 postprocess/peer_scipy.py --help`; the code is in supratrans_post/peer.py.
"""
import sys

from supratrans_post.peer import main

if __name__ == "__main__":
    sys.exit(main())
