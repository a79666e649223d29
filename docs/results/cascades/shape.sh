#!/usr/bin/env bash
# Cascade shapes of the same probe count as one grid fitted to the street (49,152), along the
# street's camera path: the camera walks along x, so cascades of 64x16x16 probes (the same
# 16,384 per cascade as 32x16x32) reach further along the street at the same spacing. Runs on the
# H200 through deploy/gpu-run.sh with the bundle (.devcarry, .gl) carried:
#   shape.sh 1 OUT   32x16x32 ratio 4 (path.sh's), 64x16x16 ratio 4 and 3, one grid 192x8x32
#   shape.sh 2 OUT   one grid 192x8x32 (control), 64x16x16 ratio 2.5, 64x16x16 ratio 3 at
#                    spacing 0.4, 4 cascades of 64x12x16 ratio 2.5, 64x16x16 ratio 3.5
#   shape.sh 3 OUT   64x16x16 ratio 3 (control), and cascades with a coarse static grid over the
#                    whole street under them (last in the blend order, so it lights only what
#                    no cascade reaches: the far street): 64x14x16 ratio 3 + 96x4x16 (4.2 x 5 x
#                    2.5 m), 64x15x16 ratio 3 + 48x4x16 (8.3 x 5 x 2.5 m); each 49,152 probes
# ddgi-eval --path with path.sh eval's flags, all configurations in one call. Writes
# OUT/shape[2]-h200.txt (stdout) and OUT/street.path.{csv,svg}; the EXR frames that --out-dir
# also writes stay in a scratch folder and are deleted.
set -euo pipefail
round=${1:?ROUND (1 or 2)}
out=${2:?OUT}
mkdir -p "$out"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
cascades() {  # COUNTS RATIO [SPACING [CASCADES]]
  local s=${3:-0.5}
  echo "counts=$1,spacing=$s,$s,$s,cascades=${4:-3},track_camera=true,cascade_spacing_ratio=$2"
}
one_grid="one grid 192x8x32:counts=192,8,32,spacing=2.0833,2.5,1.25,origin=-198.958,1.25,-19.375"
case "$round" in
  1)
    name=shape-h200.txt
    configs="cascades 32x16x32 ratio 4:$(cascades 32,16,32 4);cascades 64x16x16 ratio 4:$(cascades 64,16,16 4);cascades 64x16x16 ratio 3:$(cascades 64,16,16 3);$one_grid"
    ;;
  2)
    name=shape2-h200.txt
    configs="$one_grid;cascades 64x16x16 ratio 2.5:$(cascades 64,16,16 2.5);cascades 64x16x16 ratio 3 spacing 0.4:$(cascades 64,16,16 3 0.4);4 cascades 64x12x16 ratio 2.5:$(cascades 64,12,16 2.5 0.5 4);cascades 64x16x16 ratio 3.5:$(cascades 64,16,16 3.5)"
    ;;
  3)
    name=shape3-h200.txt
    under_fine="static_volumes=-197.917,2.5,-18.75/4.16667,5,2.5/96,4,16"
    under_coarse="static_volumes=-195.833,2.5,-18.75/8.33333,5,2.5/48,4,16"
    configs="cascades 64x16x16 ratio 3:$(cascades 64,16,16 3);64x14x16 ratio 3 + grid 96x4x16:$(cascades 64,14,16 3),$under_fine;64x15x16 ratio 3 + grid 48x4x16:$(cascades 64,15,16 3),$under_coarse"
    ;;
  *) echo "usage: shape.sh 1|2|3 OUT" >&2; exit 2 ;;
esac
start=$(date +%s)
ddgi-eval scenes/street.ddgi.json --path scenes/street.path.json --width 480 --height 270 \
  --spp 1024 --warmup 256 --backend pipeline --configs "$configs" \
  --out-dir "$scratch" 2>&1 | tee "$out/$name"
echo "wall: $(( $(date +%s) - start )) s" | tee -a "$out/$name"
cp "$scratch"/*.csv "$scratch"/*.svg "$out"/ 2>/dev/null || true
