#!/usr/bin/env bash
# Emitters sampled by solid angle (since 2026-12-06, common/emitters.glsl) against the area
# sampling before, on every scene whose emitters are sampled by default, at 384x216 (1024-spp
# reference) and 160x90 (the lavapipe table's size), in one call so that both builds run on the
# same GPU (docs/results/default-energy.md, "Emitters sampled by solid angle"). The area build is
# a bundle's bin folder of the code before the change, carried as .devcarry/variants/area/bin.
# Run through deploy/gpu-run.sh with `deploy/gpu-bundle.sh --scenes ddgi-eval` carried (.devcarry,
# .gl). Usage: solid-angle.sh OUT
set -euo pipefail
out=${1:?OUT}
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | tee "$out/device.txt"
for size in 384x216 160x90; do
  for scene in cornell_kajiya.ddgi.json veach_ajar.ddgi.json staircase.ddgi.json \
               modern_hall.ddgi.json cornell_nvpro.ddgi.json white_box.gltf; do
    for build in area solid-angle; do
      bin=.devcarry/bin
      [ "$build" = area ] && bin=.devcarry/variants/area/bin
      echo "build $build, $size" >> "$out/solid-angle.txt"
      "$bin/ddgi-eval" "scenes/$scene" --width "${size%x*}" --height "${size#*x}" --spp 1024 \
        --warmup 256 --frames 3 --backend pipeline --configs "default:" 2>&1 |
        tee -a "$out/solid-angle.txt"
    done
  done
done
