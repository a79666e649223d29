#!/usr/bin/env bash
# Short probe paths that end in the field (probe_bounces 1 and 2, since 2026-12-06) against the
# default, on every repo and real scene at 384x216 against a 1024-spp reference
# (docs/results/default-energy.md, "Short probe paths"), with gamma 1 and bias 0.5 beside them
# (what box_on_floor's indirect view and modern_hall needed in the earlier diagnosis). Run
# through deploy/gpu-run.sh with `deploy/gpu-bundle.sh --scenes ddgi-eval` carried (.devcarry,
# .gl). Usage: h100-paths.sh OUT
set -euo pipefail
out=${1:?OUT}
mkdir -p "$out"
configs="default:;paths 1:probe_bounces=1;paths 2:probe_bounces=2"
configs="$configs;paths 1 gamma 1:probe_bounces=1,irradiance_gamma=1"
configs="$configs;paths 1 bias 0.5:probe_bounces=1,self_shadow_bias=0.5"
for scene in staircase.ddgi.json modern_hall.ddgi.json cornell_nvpro.ddgi.json box_on_floor.gltf \
             cornell_kajiya.ddgi.json cornell_box.gltf two_rooms_open.gltf veach_ajar.ddgi.json \
             living_room.ddgi.json white_box.gltf lights_punctual.ddgi.json street.ddgi.json; do
  ddgi-eval "scenes/$scene" --width 384 --height 216 --spp 1024 --warmup 256 --frames 3 \
    --backend pipeline --configs "$configs" 2>&1 | tee -a "$out/paths.txt"
done
