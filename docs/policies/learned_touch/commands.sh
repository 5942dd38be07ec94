#!/usr/bin/env bash
# The commands that made docs/policies/learned_touch/ (run from the repository root).
# Training (72 min on 2 cores, not repeated here; log and curve in training/):
#   python scripts/train_policy.py --algo ppo --env touch --vector native --n-envs 16 \
#     --n-steps 128 --n-epochs 5 --batch-size 256 --timesteps 1000000 --val-every 20000 \
#     --checkpoint-every 50000 --max-hours 2.0 --out runs/learned_touch
# The shipped actor is the run's last one (1,001,472 steps; chosen on nothing, so every family
# below is held out for it); the best validation point (800,000 steps) is kept beside it:
#   cp runs/learned_touch/policy_last.npz hapticsim/envs/data/learned_touch_policy.npz
#   cp runs/learned_touch/policy.npz docs/policies/learned_touch/policy_800k.npz
# Held-out evaluation, seven families, every policy on the same episodes (episode i: seed + i).
# Training used environment seeds from 1,000,000 (random objects, noise 0.02, analytic);
# validation seeds 10,000..10,031. POLICIES picks the policies (default: all four; empty: none,
# for the blocks below); ABLATIONS=1, BEST=1 and REPORT=1 run those blocks.
set -euo pipefail
export MUJOCO_GL=egl
out=docs/policies/learned_touch/json
mkdir -p "$out"
policies=${POLICIES-"learned-touch learned uncertainty random"}
run() {  # family, then the evaluate arguments
  local family=$1; shift
  for p in $policies; do
    echo "$family $p" >&2
    hapticsim policies evaluate --policy "$p" --touches 10 --workers 2 --quiet "$@" \
      > "$out/$family-$p.tmp" && mv "$out/$family-$p.tmp" "$out/$family-$p.json"
  done
}
run random        --backend analytic --objects random          --episodes 100 --seed 0
run tapered       --backend analytic --objects random_tapered  --episodes 100 --seed 0
run paper         --backend analytic --objects paper           --episodes 40  --seed 0
run composite     --backend analytic --objects random_composite --episodes 50 --seed 0
run noise10       --backend analytic --objects random          --episodes 100 --seed 0 --noise 0.1
run mujoco        --backend mujoco   --objects paper           --episodes 20  --seed 0
run validation    --backend analytic --objects random          --episodes 32  --seed 10000

# Test-time ablations of the shipped actor (what it acts on): ABLATIONS=1 runs them.
if [ "${ABLATIONS:-0}" = 1 ]; then
  python scripts/ablate_set_actor.py hapticsim/envs/data/learned_touch_policy.npz --out runs/ablations
  for a in no-points no-touches no-head; do
    echo "ablation $a" >&2
    hapticsim policies evaluate --policy "learned:runs/ablations/$a.npz" --touches 10 --workers 2 \
      --quiet --backend analytic --objects random --episodes 100 --seed 0 > "$out/ablate-$a.json"
  done
fi

# The checkpoint of the best validation point (800,000 steps; not shipped: chosen on the
# validation objects), on the same families (BEST=1).
if [ "${BEST:-0}" = 1 ]; then
  best=docs/policies/learned_touch/policy_800k.npz
  for spec in "random:analytic:random:100:0:" "tapered:analytic:random_tapered:100:0:" \
              "paper:analytic:paper:40:0:" "composite:analytic:random_composite:50:0:" \
              "noise10:analytic:random:100:0:0.1" "mujoco:mujoco:paper:20:0:" \
              "validation:analytic:random:32:10000:"; do
    IFS=: read -r family backend objects episodes seed noise <<< "$spec"
    echo "$family best" >&2
    hapticsim policies evaluate --policy "learned:$best" --touches 10 --workers 2 --quiet \
      --backend "$backend" --objects "$objects" --episodes "$episodes" --seed "$seed" \
      ${noise:+--noise "$noise"} > "$out/$family-best.json"
  done
fi

# The training ablation without the reward's coverage term (NOCOV=1; training not repeated:
#   python scripts/train_policy.py --algo ppo --env touch --vector native --n-envs 16 \
#     --n-steps 128 --n-epochs 5 --batch-size 256 --timesteps 250000 --val-every 20000 \
#     --checkpoint-every 50000 --coverage-weight 0 --max-hours 0.5 --out runs/learned_touch_nocov
#   cp runs/learned_touch_nocov/{curve.csv,curve.png,train.log,summary.json,policy_last.npz} \
#     docs/policies/learned_touch/nocov/)
if [ "${NOCOV:-0}" = 1 ]; then
  hapticsim policies evaluate --policy learned:docs/policies/learned_touch/nocov/policy_last.npz \
    --touches 10 --workers 2 --quiet --backend analytic --objects random --episodes 100 --seed 0 \
    > "$out/nocov-random.json"
  python scripts/learning_curves.py docs/policies/learned_touch/training \
    docs/policies/learned_touch/nocov --labels "coverage term 2 (shipped)" "no coverage term" \
    --out docs/policies/learned_touch/coverage_ablation.png
fi

# Tables, plots and paired tests per family (REPORT=1), and the figures of README.md.
if [ "${REPORT:-0}" = 1 ]; then
  for family in random tapered paper composite noise10 mujoco validation; do
    python scripts/learned_report.py "$out"/$family-*.json --learned learned-touch \
      --out docs/policies/learned_touch/$family > /dev/null
  done
  python scripts/learned_report.py "$out"/random-learned-touch.json "$out"/random-random.json \
    "$out"/random-uncertainty.json "$out"/ablate-*.json --learned learned-touch \
    --out docs/policies/learned_touch/ablations > /dev/null
fi
