# Quality at the street's camera (one view): three cascades of 32x16x32 around the camera (ratio 2
# and ratio 4) against one grid of the same probe count (192x8x32) fitted to the whole street.
set -e
C="cascades ratio 2:counts=32,16,32,spacing=0.5,0.5,0.5,origin=-187.75,-3.75,-7.75,cascades=3"
C="$C;cascades ratio 4:counts=32,16,32,spacing=0.5,0.5,0.5,origin=-187.75,-3.75,-7.75,cascades=3,cascade_spacing_ratio=4"
C="$C;one grid 192x8x32:counts=192,8,32,spacing=2.0833,2.5,1.25,origin=-198.958,1.25,-19.375"
mkdir -p $OUT/img
deploy/gpu-run.sh ddgi-eval scenes/street.ddgi.json --width 480 --height 270 --spp 1024 \
  --warmup 256 --backend pipeline --configs "$C" --out-dir $OUT/img 2>&1 | tee $OUT/quality.txt
cd $OUT && tar czf img.tgz img && rm -rf img
