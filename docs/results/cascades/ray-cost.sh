set -e
[ -d .devcarry/scenes ] || tar xJf .devcarry/scenes.tar.xz -C .devcarry
mkdir -p ../shared && rm -rf ../shared/scenes && ln -s $PWD/.devcarry/scenes ../shared/scenes
B="deploy/gpu-run.sh ddgi-bench"
# warm the clocks
$B scenes/staircase.ddgi.json --grids 32x16x32 --rays 256 --frames 60 --warmup 8 --backend pipeline > /dev/null 2>&1
$B scenes/staircase.ddgi.json scenes/veach_ajar.ddgi.json --grids 32x16x32 --rays 64,256 \
  --paths fused --frames 20 --warmup 8 --backend pipeline --field distance_texels=8 \
  --field fixed_rays=0 --field classification=false --field relocation_iterations=0 \
  2>&1 | tee $OUT/ray-cost.txt
