# The field at ray cost before (b58ae9a, the commit before volumes) and after the volumes change,
# in one device session, alternating, after warming the clocks. The old build is carried in
# .devcarry/base/ (ddgi-bench and its spirv/ from a Release build of b58ae9a).
set -e
A="scenes/staircase.ddgi.json scenes/veach_ajar.ddgi.json --grids 32x16x32 --rays 64,256 \
  --paths fused --frames 20 --warmup 8 --backend pipeline --field distance_texels=8 \
  --field fixed_rays=0 --field classification=false --field relocation_iterations=0"
deploy/gpu-run.sh ddgi-bench scenes/staircase.ddgi.json --grids 32x16x32 --rays 256 --frames 60 \
  --warmup 8 --backend pipeline > /dev/null 2>&1
for round in 1 2; do
  deploy/gpu-run.sh .devcarry/base/ddgi-bench $A 2>&1 | sed "s/^/before $round: /" | tee -a $OUT/ray-cost.txt
  deploy/gpu-run.sh ddgi-bench $A 2>&1 | sed "s/^/after $round: /" | tee -a $OUT/ray-cost.txt
done
