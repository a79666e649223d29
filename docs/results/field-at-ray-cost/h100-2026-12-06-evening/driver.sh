#!/usr/bin/env bash
# Issue 13 on the H200 with the code as committed: the thesis setup (variants.sh, three
# interleaved rounds), the glass-free comparison (glass-free.sh, three rounds) and the service
# defaults once; everything packed into one archive (the device returns at most 8 files).
set -uo pipefail
out=${1:?OUT}
work=/tmp/h200-work
rm -rf "$work"; mkdir -p "$work"
d=docs/results/field-at-ray-cost
start=$(date +%s)
bash $d/variants.sh "$work/thesis" 3 base
echo "thesis done at $(( $(date +%s) - start )) s"
bash $d/glass-free.sh "$work/glass-free" 3
echo "glass-free done at $(( $(date +%s) - start )) s"
ddgi-bench scenes/staircase.ddgi.json scenes/veach_ajar.ddgi.json scenes/living_room.ddgi.json \
  --grids 32x16x32 --rays 64,256 --paths fused --frames 20 --warmup 8 --backend pipeline \
  > "$work/thesis/service-base-round1.md"
echo "service done at $(( $(date +%s) - start )) s"
cp "$0" "$work/driver.sh"
tar czf "$out/h200.tar.gz" -C "$work" .
cat "$work"/thesis/device.txt
