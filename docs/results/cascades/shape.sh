#!/usr/bin/env bash
# Cascades shaped to the street: the camera walks along x, so cascades of 64x16x16 probes (the
# same 16,384 per cascade as 32x16x32) reach further along the street at the same spacing. Runs
# on the H200 through deploy/gpu-run.sh with the bundle (.devcarry, .gl) carried:
#   shape.sh OUT   ddgi-eval --path along scenes/street.path.json (flags as path.sh eval):
#                  32x16x32 ratio 4 (baseline), 64x16x16 ratio 4 and 3, one grid 192x8x32
# Writes OUT/shape-h200.txt (stdout) and OUT/street.path.{csv,svg}; the EXR frames that
# --out-dir also writes stay in a scratch folder and are deleted.
set -euo pipefail
out=${1:?OUT}
mkdir -p "$out"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
tracking="spacing=0.5,0.5,0.5,cascades=3,track_camera=true"
cubic4="counts=32,16,32,$tracking,cascade_spacing_ratio=4"
long4="counts=64,16,16,$tracking,cascade_spacing_ratio=4"
long3="counts=64,16,16,$tracking,cascade_spacing_ratio=3"
one_grid="counts=192,8,32,spacing=2.0833,2.5,1.25,origin=-198.958,1.25,-19.375"
start=$(date +%s)
ddgi-eval scenes/street.ddgi.json --path scenes/street.path.json --width 480 --height 270 \
  --spp 1024 --warmup 256 --backend pipeline \
  --configs "cascades 32x16x32 ratio 4:${cubic4};cascades 64x16x16 ratio 4:$long4;cascades 64x16x16 ratio 3:$long3;one grid 192x8x32:$one_grid" \
  --out-dir "$scratch" 2>&1 | tee "$out/shape-h200.txt"
echo "wall: $(( $(date +%s) - start )) s" | tee -a "$out/shape-h200.txt"
cp "$scratch"/*.csv "$scratch"/*.svg "$out"/ 2>/dev/null || true
