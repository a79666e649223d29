#!/usr/bin/env bash
# Times builds of the field update against each other on one GPU, in one call. A variant is a
# bundle's bin folder (ddgi-bench and the spirv folder beside it) carried as
# .devcarry/variants/NAME/bin; "base" is the bundle's own (.devcarry/bin). Rounds interleave
# the variants so that a clock drift shows as a difference between rounds, not variants.
# Usage (on the GPU host, through deploy/gpu-run.sh): variants.sh OUT [ROUNDS] [VARIANT...]
set -euo pipefail
out=${1:?OUT}
rounds=${2:-2}
shift 2 || shift $#
variants=("${@:-base}")
mkdir -p "$out"
scenes=(scenes/staircase.ddgi.json scenes/veach_ajar.ddgi.json scenes/cornell_kajiya.ddgi.json)
# The thesis setup of field-at-ray-cost.md (8x8 maps, every probe traced each update).
# shellcheck disable=SC2054  # the commas belong to the flags
thesis=(--grids 32x16x32 --rays 64,256 --paths fused --frames 20 --warmup 8 --backend pipeline
        --field distance_texels=8 --field fixed_rays=0 --field classification=false
        --field relocation_iterations=0)
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | tee "$out/device.txt"
# Clocks up before anything is timed.
ddgi-bench "${scenes[0]}" --grids 32x16x32 --rays 64 --frames 60 --warmup 8 \
  --backend pipeline > /dev/null
for round in $(seq 1 "$rounds"); do
  for v in "${variants[@]}"; do
    bin=.devcarry/bin
    [ "$v" = base ] || bin=.devcarry/variants/$v/bin
    start=$(date +%s)
    "$bin/ddgi-bench" "${scenes[@]}" "${thesis[@]}" > "$out/$v-round$round.md"
    echo "round $round variant $v: $(( $(date +%s) - start )) s"
  done
done
