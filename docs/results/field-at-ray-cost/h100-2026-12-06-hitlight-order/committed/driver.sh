#!/usr/bin/env bash
# The session driver this call ran (kept as its record; .devcarry/variants/NAME held each variant's build): hit-light blocks 4x2x4 (hl1) and 8x4x4 (hl2)
# then the service defaults, base against hl1.
set -uo pipefail
mkdir -p /tmp/v
bash docs/results/field-at-ray-cost/variants.sh /tmp/v 3 base hl1 hl2
for round in 1 2; do
  for v in base hl1; do
    bin=.devcarry/bin; [ "$v" = base ] || bin=.devcarry/variants/$v/bin
    "$bin/ddgi-bench" scenes/staircase.ddgi.json scenes/veach_ajar.ddgi.json \
      scenes/living_room.ddgi.json --grids 32x16x32 --rays 64,256 --paths fused --frames 20 \
      --warmup 8 --backend pipeline > /tmp/v/service-$v-round$round.md
  done
done
cat /tmp/v/device.txt
tar czf "$OUT/v17.tgz" -C /tmp v
