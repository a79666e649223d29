#!/usr/bin/env bash
# Paths per pixel (field parameter pixel_paths, docs/service.md "Paths per pixel") on a GPU:
# energy.sh (every repo and real scene, the static default against what a session gets, now
# with paths per pixel as the calibration's last resort), then on the two Cornell boxes whose
# light no probe grid holds, the field against 4 and 16 paths of 32 vertices per pixel at both
# sizes. Then, in the same call, issue 13's driver (.devcarry/h200-driver.sh, a copy in
# docs/results/field-at-ray-cost/h100-2026-12-06-repeat/driver.sh) while time is left. One
# archive back. Run through deploy/gpu-run.sh with `deploy/gpu-bundle.sh --scenes ddgi-bench
# ddgi-eval` carried (.devcarry, .gl). Usage: pixel-paths.sh OUT
set -uo pipefail
out=${1:?OUT}
work=/tmp/pixel-paths
rm -rf "$work"; mkdir -p "$work/energy"
start=$(date +%s)
bash docs/results/default-energy/energy.sh "$work/energy" > "$work/energy/log.txt" 2>&1
echo "energy done at $(( $(date +%s) - start )) s" | tee -a "$work/times.txt"
configs="field:self_shadow_bias=0.3;pixel paths 4x32:pixel_paths=4,pixel_path_vertices=32;pixel paths 16x32:pixel_paths=16,pixel_path_vertices=32"
for scene in cornell_nvpro.ddgi.json cornell_kajiya.ddgi.json; do
  ddgi-eval "scenes/$scene" --width 384 --height 216 --spp 1024 --warmup 256 --frames 3 \
    --backend pipeline --configs "$configs" >> "$work/paths-384.txt" 2>&1
  ddgi-eval "scenes/$scene" --width 160 --height 90 --spp 256 --warmup 128 --frames 3 \
    --backend pipeline --configs "$configs" >> "$work/paths-160.txt" 2>&1
done
echo "paths done at $(( $(date +%s) - start )) s" | tee -a "$work/times.txt"
if [ $(( $(date +%s) - start )) -lt 430 ]; then
  bash .devcarry/h200-driver.sh "$work" > "$work/issue13-log.txt" 2>&1
  echo "issue13 done at $(( $(date +%s) - start )) s" | tee -a "$work/times.txt"
fi
tar czf "$out/pixel-paths.tar.gz" -C "$work" .
cat "$work/energy/device.txt"; cat "$work/times.txt"
