#!/usr/bin/env bash
# Times the overlapped update path (the fused kernels over parts of the window, each part's hit
# light recorded beside the next part's trace) against the fused path in one process. The path
# was measured slower and removed: this runs against the bundle of b11926f only. The
# thesis setup of field-at-ray-cost.md in ROUNDS rounds after a clock warm-up, then the service
# defaults once. Usage (on the GPU host, through deploy/gpu-run.sh): overlap.sh OUT [ROUNDS]
# [PATHS]
set -euo pipefail
out=${1:?OUT}
rounds=${2:-3}
paths=${3:-fused,overlapped2,overlapped4,overlapped8}
mkdir -p "$out"
scenes=(scenes/staircase.ddgi.json scenes/veach_ajar.ddgi.json scenes/cornell_kajiya.ddgi.json)
# shellcheck disable=SC2054  # the commas belong to the flags
thesis=(--grids 32x16x32 --rays 64,256 --paths "$paths" --frames 20 --warmup 8
        --backend pipeline --field distance_texels=8 --field fixed_rays=0
        --field classification=false --field relocation_iterations=0)
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | tee "$out/device.txt"
# Clocks up before anything is timed.
ddgi-bench "${scenes[0]}" --grids 32x16x32 --rays 64 --frames 60 --warmup 8 \
  --backend pipeline > /dev/null
for round in $(seq 1 "$rounds"); do
  start=$(date +%s)
  ddgi-bench "${scenes[@]}" "${thesis[@]}" > "$out/thesis-round$round.md"
  echo "thesis round $round: $(( $(date +%s) - start )) s"
done
start=$(date +%s)
ddgi-bench scenes/staircase.ddgi.json scenes/veach_ajar.ddgi.json scenes/living_room.ddgi.json \
  --grids 32x16x32 --rays 64,256 --paths "$paths" --frames 20 --warmup 8 --backend pipeline \
  > "$out/service.md"
echo "service defaults: $(( $(date +%s) - start )) s"
