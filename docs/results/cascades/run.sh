# The scroll cost on the GPU (docs/cascades.md): run on the H200 through the device tool, from
# the repository root with the bundle (deploy/gpu-bundle.sh ddgi-bench ddgi-eval) carried.
set -e
[ -d .devcarry/scenes ] || tar xJf .devcarry/scenes.tar.xz -C .devcarry
mkdir -p ../shared && rm -rf ../shared/scenes && ln -s $PWD/.devcarry/scenes ../shared/scenes
deploy/gpu-run.sh ddgi-bench scenes/cornell_box.gltf scenes/staircase.ddgi.json \
  scenes/living_room.ddgi.json --grids "32x16x32" --rays 128 --frames 60 --warmup 16 \
  --scroll-every 4 --backend pipeline 2>&1 | tee $OUT/scroll-bench.txt
