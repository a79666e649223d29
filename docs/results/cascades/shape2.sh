#!/usr/bin/env bash
# Cascade shapes of the same probe count as the one grid (49,152), looking for one that beats
# it in PSNR as well as FLIP (shape.sh: 64x16x16 ratio 3 won FLIP, lost PSNR by 0.08 dB). Runs
# on the H200 through deploy/gpu-run.sh with the bundle (.devcarry, .gl) carried:
#   shape2.sh OUT  ddgi-eval --path along scenes/street.path.json (flags as shape.sh):
#                  one grid 192x8x32 (control), 64x16x16 ratio 2.5, 64x16x16 ratio 3 at
#                  spacing 0.4, 4 cascades of 64x12x16 ratio 2.5, 64x16x16 ratio 3.5
# Writes OUT/shape2-h200.txt (stdout) and OUT/street.path.{csv,svg}; the EXR frames that
# --out-dir also writes stay in a scratch folder and are deleted.
set -euo pipefail
out=${1:?OUT}
mkdir -p "$out"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
track="track_camera=true"
long25="counts=64,16,16,spacing=0.5,0.5,0.5,cascades=3,$track,cascade_spacing_ratio=2.5"
long3s04="counts=64,16,16,spacing=0.4,0.4,0.4,cascades=3,$track,cascade_spacing_ratio=3"
four25="counts=64,12,16,spacing=0.5,0.5,0.5,cascades=4,$track,cascade_spacing_ratio=2.5"
long35="counts=64,16,16,spacing=0.5,0.5,0.5,cascades=3,$track,cascade_spacing_ratio=3.5"
one_grid="counts=192,8,32,spacing=2.0833,2.5,1.25,origin=-198.958,1.25,-19.375"
start=$(date +%s)
ddgi-eval scenes/street.ddgi.json --path scenes/street.path.json --width 480 --height 270 \
  --spp 1024 --warmup 256 --backend pipeline \
  --configs "one grid 192x8x32:$one_grid;cascades 64x16x16 ratio 2.5:$long25;cascades 64x16x16 ratio 3 spacing 0.4:$long3s04;4 cascades 64x12x16 ratio 2.5:$four25;cascades 64x16x16 ratio 3.5:$long35" \
  --out-dir "$scratch" 2>&1 | tee "$out/shape2-h200.txt"
echo "wall: $(( $(date +%s) - start )) s" | tee -a "$out/shape2-h200.txt"
cp "$scratch"/*.csv "$scratch"/*.svg "$out"/ 2>/dev/null || true
