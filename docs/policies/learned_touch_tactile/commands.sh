#!/usr/bin/env bash
# The commands that made docs/policies/learned_touch_tactile/ (run from the repository root).
# Training (not repeated here; log and curve in training/):
#   python scripts/train_policy.py --algo ppo --env touch-tactile --vector native --n-envs 16 \
#     --n-steps 128 --n-epochs 5 --batch-size 256 --timesteps 1000000 --val-every 20000 \
#     --checkpoint-every 50000 --max-hours 1.9 --out runs/learned_touch_tactile
#   python scripts/train_policy.py --resume --timesteps 1000000 --max-hours 2.6 \
#     --out runs/learned_touch_tactile      # the time limit stopped it at 947,456 steps
#   cp runs/learned_touch_tactile/{curve.csv,curve.png,train.log,summary.json} \
#     docs/policies/learned_touch_tactile/training/
# The actor evaluated is the run's last one (chosen on nothing, so every family below is held
# out for it):
#   cp runs/learned_touch_tactile/policy_last.npz docs/policies/learned_touch_tactile/policy.npz
#   cp runs/learned_touch_tactile/policy.npz docs/policies/learned_touch_tactile/policy_best.npz
# (the baselines' columns ran with WORKERS=1 beside the training; the actor's after it)
# Held-out evaluation: every family felt through the pads (--sensing tactile: analytic pads or
# the hand's, ideal skin), every policy on the same episodes (episode i: seed + i). Training
# used environment seeds from 1,000,000 (random objects, noise 0.02, analytic pads); validation
# seeds 10,000..10,031. POLICIES picks the policies (default: all five; empty: none, for the
# blocks below); ABLATIONS=1 and REPORT=1 run those blocks.
set -euo pipefail
export MUJOCO_GL=egl
dir=docs/policies/learned_touch_tactile
out=$dir/json
mkdir -p "$out"
policies=${POLICIES-"tactile learned-touch learned uncertainty random"}
workers=${WORKERS:-2}  # (the baselines ran with WORKERS=1 beside the training)
name() {  # the policy argument of a column
  if [ "$1" = tactile ]; then echo "learned:$dir/policy.npz"; else echo "$1"; fi
}
run() {  # family, then the evaluate arguments
  local family=$1; shift
  for p in $policies; do
    echo "$family $p" >&2
    hapticsim policies evaluate --policy "$(name "$p")" --touches 10 --workers "$workers" --quiet \
      --sensing tactile "$@" > "$out/$family-$p.tmp" && mv "$out/$family-$p.tmp" "$out/$family-$p.json"
  done
}
run random        --backend analytic --objects random          --episodes 100 --seed 0
run tapered       --backend analytic --objects random_tapered  --episodes 100 --seed 0
run paper         --backend analytic --objects paper           --episodes 40  --seed 0
run noise10       --backend analytic --objects random          --episodes 100 --seed 0 --noise 0.1
run mujoco        --backend mujoco   --objects paper           --episodes 20  --seed 0
run capacitive    --backend analytic --objects random          --episodes 100 --seed 0 --skin capacitive
run validation    --backend analytic --objects random          --episodes 32  --seed 10000

# Test-time ablation: the same actor with its pad images blanked (does it use them?).
if [ "${ABLATIONS:-0}" = 1 ]; then
  python scripts/ablate_set_actor.py "$dir/policy.npz" --out runs/ablations_tactile
  for a in no-taxels no-points; do
    echo "ablation $a" >&2
    hapticsim policies evaluate --policy "learned:runs/ablations_tactile/$a.npz" --touches 10 \
      --workers 2 --quiet --sensing tactile --backend analytic --objects random --episodes 100 \
      --seed 0 > "$out/ablate-$a.json"
  done
fi

# The table (summary.json) and per-family reports (REPORT=1).
if [ "${REPORT:-0}" = 1 ]; then
  python scripts/learned_touch_table.py "$dir" --subject tactile \
    --policies tactile learned-touch learned uncertainty random \
    --against learned-touch uncertainty \
    --families "random=random objects, 100" "tapered=random tapered objects, 100" \
      "paper=the paper's bodies, 40" "noise10=random objects, noise 0.1, 100" \
      "mujoco=MuJoCo hand (its pads), the paper's bodies, 20" \
      "capacitive=random objects, capacitive skin (9 x 9 taxels, noise, dead taxels), 100" \
      "validation=random objects, validation seeds 10,000..10,031, 32" > "$dir/table.md"
fi
