#!/usr/bin/env bash
# Where the default field's remaining energy error comes from (docs/results/default-energy.md,
# "Every scene at 384x216 with the same choices"): every repo and real scene at default settings and with
# one visibility or sampling parameter changed at a time, at 384x216 against a 1024-spp
# reference; the views outside 5% also with their own suspects, and for those four the EXR
# frames of the default and the reference (all twelve scenes' frames make an archive larger than
# a device call brings back). Run through deploy/gpu-run.sh with
# `deploy/gpu-bundle.sh --scenes ddgi-eval` carried (.devcarry, .gl). Usage: h200-diag.sh OUT
set -euo pipefail
out=${1:?OUT}
common="default:;bias 0.5:self_shadow_bias=0.5;exact probes:probe_bounces=64"
common="$common;exact probes gamma 1:probe_bounces=64,irradiance_gamma=1"
common="$common;exact probes gamma 1 512 rays:probe_bounces=64,irradiance_gamma=1,rays_per_probe=512"
common="$common;gamma 1 512 rays:irradiance_gamma=1,rays_per_probe=512"
run() {  # SCENE EXTRA_CONFIGS
  mkdir -p "$out/exr-$1"
  ddgi-eval "scenes/$1" --width 384 --height 216 --spp 1024 --warmup 256 --frames 3 \
    --backend pipeline --out-dir "$out/exr-$1" --configs "$common${2:+;$2}" 2>&1 |
    tee -a "$out/diag.txt"
  if [ "$keep_frames" = 1 ]; then
    find "$out/exr-$1" -name '*.exr' ! -name '*.reference*' ! -name '*.default*' -delete
  else
    rm -rf "${out:?}/exr-$1"
  fi
}
keep_frames=1
# The views outside 5% first (docs/results/default-energy.md), then the others.
run staircase.ddgi.json "bias 0.1:self_shadow_bias=0.1"
run modern_hall.ddgi.json "no classification:classification=false;bias 0.8:self_shadow_bias=0.8"
run cornell_nvpro.ddgi.json
run box_on_floor.gltf
keep_frames=0
for scene in cornell_box.gltf two_rooms_open.gltf cornell_kajiya.ddgi.json veach_ajar.ddgi.json \
             living_room.ddgi.json white_box.gltf lights_punctual.ddgi.json street.ddgi.json; do
  run "$scene"
done
# Only 8 files come back from a device run: the frames travel as one archive.
(cd "$out" && tar czf exr.tgz exr-*) && rm -rf "${out:?}"/exr-*
