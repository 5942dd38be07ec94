"""Paper Fig. 5: table/curves and picture (`hapticsim reproduce fig5`).

Usage: `python scripts/fig5.py [--out DIR] [--runs 10] [--seed 0] [--workers N] [--results MD]`.
Prints the JSON summary on stdout; progress on stderr.
"""

import sys

from hapticsim.cli import main

if __name__ == "__main__":
    sys.exit(main(["reproduce", "fig5", *sys.argv[1:]]))
