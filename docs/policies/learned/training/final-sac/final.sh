#!/usr/bin/env bash
# The shipped policy's training run: SAC (chosen by runs/select-*: equal steps, same seed, same
# validation set), 2 vector envs, stopped by --max-hours.
set -u
cd /work/wt/rl
source /work/venv/bin/activate
export PYTHONPATH=$PWD MUJOCO_GL=egl
python scripts/train_policy.py --algo sac --timesteps 200000 --net 128 128 --buffer-size 200000 \
  --val-every 10000 --checkpoint-every 10000 --max-hours 1.7 --out runs/final-sac \
  > runs/final-sac.out 2>&1
