#!/usr/bin/env bash
# The energy calibration (tools/field_energy.h) against the static default on every repo and real
# scene (docs/results/default-energy.md, "Energy calibrated on load"): `ddgi-eval --energy`
# gives the "session default" configuration what a ddgi-server session on a GPU gets (the
# calibration at 320x180, 256 spp, 64 warm-up updates, its choice on stderr, which is kept);
# "static" sets the static default's self_shadow_bias explicitly, which keeps the calibration
# out. At 384x216 against 1024-spp references (the H100 tables of that page) and at 160x90
# against 256-spp references (the lavapipe acceptance table's size). Run through
# deploy/gpu-run.sh with `deploy/gpu-bundle.sh --scenes ddgi-eval` carried (.devcarry, .gl).
# Usage: energy.sh OUT
set -euo pipefail
out=${1:?OUT}
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | tee "$out/device.txt" || true
configs="static:self_shadow_bias=0.3;session default:"
for scene in staircase.ddgi.json modern_hall.ddgi.json cornell_nvpro.ddgi.json box_on_floor.gltf \
             cornell_kajiya.ddgi.json cornell_box.gltf two_rooms_open.gltf veach_ajar.ddgi.json \
             living_room.ddgi.json white_box.gltf lights_punctual.ddgi.json street.ddgi.json; do
  ddgi-eval "scenes/$scene" --width 384 --height 216 --spp 1024 --warmup 256 --frames 3 \
    --backend pipeline --configs "$configs" --energy 2>&1 | tee -a "$out/energy-384.txt"
  ddgi-eval "scenes/$scene" --width 160 --height 90 --spp 256 --warmup 128 --frames 3 \
    --backend pipeline --configs "$configs" --energy 2>&1 | tee -a "$out/energy-160.txt"
done
