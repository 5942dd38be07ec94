#!/usr/bin/env bash
# The commands that made docs/policies/learned/ (run from the repository root, after training).
# Training (1.7 h on 2 cores, not repeated here): training/final-sac/final.sh.
set -euo pipefail
export MUJOCO_GL=egl
out=docs/policies/learned
mkdir -p "$out/json"

# The trained actor of the best validation point goes into the package.
cp runs/final-sac/policy.npz hapticsim/envs/data/learned_policy.npz

# Held-out evaluation: random objects, seeds 0..99 (training used environment seeds from
# 1,000,000, validation 10,000..10,031); the MuJoCo hand on the paper's bodies, seeds 0..19.
for p in learned random uncertainty paper; do
  hapticsim policies evaluate --policy "$p" --backend analytic --objects random \
    --episodes 100 --touches 10 --seed 0 --workers 2 --quiet > "$out/json/analytic-$p.json"
done
for p in learned random uncertainty paper; do
  hapticsim policies evaluate --policy "$p" --backend mujoco --objects paper \
    --episodes 20 --touches 10 --seed 0 --workers 2 --quiet > "$out/json/mujoco-$p.json"
done
# More MuJoCo episodes for learned vs random (seeds 0..59; added after the fast-loop re-measure).
for p in learned random; do
  hapticsim policies evaluate --policy "$p" --backend mujoco --objects paper \
    --episodes 60 --touches 10 --seed 0 --workers 2 --quiet > "$out/json/mujoco60-$p.json"
done
# The validation set of the training script (seeds 10,000..10,031): reference lines of the curve.
for p in learned random uncertainty paper; do
  hapticsim policies evaluate --policy "$p" --backend analytic --objects random \
    --episodes 32 --touches 10 --seed 10000 --workers 2 --quiet > "$out/json/validation-$p.json"
done

python scripts/learned_report.py "$out"/json/analytic-*.json --out "$out/analytic"
python scripts/learned_report.py "$out"/json/mujoco-*.json --out "$out/mujoco"
python scripts/learned_report.py "$out"/json/mujoco60-*.json --out "$out/mujoco60"
python scripts/learned_report.py "$out"/json/validation-*.json --out "$out/validation"

# Learning curve of the shipped run and the algorithm selection (reference lines: the baselines'
# means on the validation set, json/validation-*.json).
L=docs/policies/learned
python scripts/learning_curves.py $L/training/final-sac \
  --labels "SAC 128x128, 2 envs (shipped: best validation point)" \
  --reference random=0.063 uncertainty=0.017 paper=0.081 \
  --title "HapticExplore-v1, random objects: validation mean epsilon after 10 touches (32 objects, seeds 10000..10031)" \
  --out $L/curve.png
python scripts/learning_curves.py $L/training/select-{sac,tqc,crossq,ppo} \
  $L/training/ablation-obs85-nocov-sac $L/training/ablation-obs81-sac \
  --labels SAC TQC "CrossQ (256x256 critic)" PPO "SAC, no coverage term (earlier settings)" \
  "SAC, 81-number obs. (earlier settings)" --reference random=0.063 uncertainty=0.017 \
  --title "Algorithm selection: validation mean epsilon after 10 touches (32 objects, same seed)" \
  --out $L/selection.png
