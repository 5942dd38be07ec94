#!/usr/bin/env bash
# docs/policies/learned_touch/json/random-*.json again, after the sensor got a stream of its own
# (commit 490474e): the same command, the same seeds, only the noise values differ.
set -euo pipefail
for p in learned-touch learned uncertainty random; do
  hapticsim policies evaluate --policy "$p" --touches 10 --workers 2 --quiet --backend analytic \
    --objects random --episodes 100 --seed 0 > "docs/vector/sensor_stream/random-$p.json"
done
