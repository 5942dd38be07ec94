"""Paper Figs. 4 and 5 with the claim checks; ``--results RESULTS.md`` writes the report.

Usage: ``python scripts/reproduce.py [fig4|fig5|all] [--out DIR] [--runs 10] [--seed 0]
[--workers N] [--results RESULTS.md] [--figures-dir docs/figures]``, the same as
``hapticsim reproduce``. The committed ``RESULTS.md`` comes from
``python scripts/reproduce.py all --results RESULTS.md``.
"""

import sys

from hapticsim.cli import main

if __name__ == "__main__":
    args = sys.argv[1:]
    if not args or args[0].startswith("-"):
        args = ["all", *args]
    sys.exit(main(["reproduce", *args]))
