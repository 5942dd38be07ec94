#!/usr/bin/env bash
# The commands that made docs/policies/learned_touch/bc/ (run from the repository root; 2026-12-05,
# AMD EPYC with AVX-512, 2 cores, beside an RLlib training: ~7 min per cloning, 5 s per evaluation).
# Behaviour cloning of the uncertainty policy (4,000 episodes from seed 2,000,000, 40,000 touches;
# 60 epochs of least squares on its actions), into the touch actor's network and, as the control,
# into the compact actor's (whose observation holds the current fit and the coverage gaps);
# the committed touch run was made with --out runs/bc_touch2 (the folder name changes nothing):
set -euo pipefail
for obs in touch compact; do
  python scripts/bc_heuristic.py --observation "$obs" --out "runs/bc_$obs"
  cp "runs/bc_$obs/summary.json" "docs/policies/learned_touch/bc/$obs/"
  # the held-out family "random objects" of ../commands.sh (episodes 0..99), paired with ../json/
  hapticsim policies evaluate --policy "learned:runs/bc_$obs/policy.npz" --backend analytic \
    --objects random --episodes 100 --seed 0 --touches 10 --workers 2 --quiet \
    > "docs/policies/learned_touch/bc/$obs/random.json"
done
# How far two draws of the heuristic differ on the same observation (~10 s):
python scripts/heuristic_spread.py > docs/policies/learned_touch/bc/spread.json
