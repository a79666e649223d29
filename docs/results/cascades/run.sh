# Scrolling and cascades on the GPU (docs/cascades.md, docs/results/cascades.md): run on the
# H200 through the device tool, from the repository root, with the bundle
# (deploy/gpu-bundle.sh ddgi-bench ddgi-eval) and the scenes carried.
set -e
B="deploy/gpu-run.sh ddgi-bench"
# 1. The field at ray cost after the volumes change (compare docs/results/field-at-ray-cost.md,
#    run 2, thesis setup).
$B scenes/staircase.ddgi.json scenes/veach_ajar.ddgi.json --grids 32x16x32 --rays 64,256 \
  --paths fused --frames 20 --warmup 8 --backend pipeline --field distance_texels=8 \
  --field fixed_rays=0 --field classification=false --field relocation_iterations=0 \
  2>&1 | tee $OUT/ray-cost.txt
# 2. What a scroll costs (service defaults: relocation and classification of the entering plane).
$B scenes/cornell_box.gltf scenes/staircase.ddgi.json scenes/living_room.ddgi.json \
  --grids 32x16x32 --rays 128 --frames 60 --warmup 16 --scroll-every 4 --backend pipeline \
  2>&1 | tee $OUT/scroll.txt
# 3. Three cascades of the same grid: update cost of 3x the probes.
$B scenes/staircase.ddgi.json scenes/living_room.ddgi.json --grids 32x16x32 --rays 128 \
  --frames 20 --warmup 8 --backend pipeline --field cascades=3 2>&1 | tee $OUT/cascades.txt
# 4. Quality at the street's camera (one view, not yet the path): three cascades of 32x16x32
#    around the camera against one grid of the same probe count (192x8x32) fitted to the street.
deploy/gpu-run.sh ddgi-eval scenes/street.ddgi.json --width 480 --height 270 --spp 1024 \
  --warmup 256 --backend pipeline --configs "cascades 3x32x16x32:counts=32,16,32,spacing=0.5,0.5,0.5,origin=-187.75,-3.75,-7.75,cascades=3;one grid 192x8x32:counts=192,8,32,spacing=2.0833,2.5,1.25,origin=-198.958,1.25,-19.375" \
  2>&1 | tee $OUT/quality.txt
