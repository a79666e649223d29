#!/usr/bin/env bash
# Staircase and VeachAjar with their glass and without it (KHR_materials_transmission removed
# from every material, so the glass is opaque), in the thesis setup of variants.sh, rounds
# interleaved: whether the glass accounts for any of `update / raw`, on scenes whose rays cost
# what real scenes' do (cornell_kajiya, the glass-free scene of the other tables, has 32
# triangles). Two steps:
#   on the build machine, before the bundle travels:  glass-free.sh --prepare
#     (writes .devcarry/glassfree/NAME-opaque.gltf from ../shared/scenes: the scenes stay out
#     of the repository, and the GPU host may have no python)
#   on the GPU host, through deploy/gpu-run.sh:        glass-free.sh OUT [ROUNDS]
set -euo pipefail
scenes=(Staircase/Staircase VeachAjar/VeachAjar)
if [ "${1:-}" = --prepare ]; then
  mkdir -p .devcarry/glassfree
  for s in "${scenes[@]}"; do
    python3 - "../shared/scenes/$s.gltf" ".devcarry/glassfree/$(basename "$s")-opaque.gltf" <<'PY'
import json, sys
g = json.load(open(sys.argv[1]))
for m in g.get("materials", []):
    m.get("extensions", {}).pop("KHR_materials_transmission", None)
for key in ("extensionsUsed", "extensionsRequired"):
    if key in g:
        g[key] = [e for e in g[key] if e != "KHR_materials_transmission"]
json.dump(g, open(sys.argv[2], "w"))
PY
  done
  exit 0
fi
out=${1:?OUT}
rounds=${2:-3}
mkdir -p "$out"
paths=()
for s in "${scenes[@]}"; do
  # Beside the original, so that its buffers and textures resolve inside the scene's folder.
  chmod u+w "../shared/scenes/$(dirname "$s")"
  cp ".devcarry/glassfree/$(basename "$s")-opaque.gltf" "../shared/scenes/$(dirname "$s")/"
  paths+=("../shared/scenes/$s.gltf" "../shared/scenes/$s-opaque.gltf")
done
# shellcheck disable=SC2054  # the commas belong to the flags
thesis=(--grids 32x16x32 --rays 64,256 --paths fused --frames 20 --warmup 8 --backend pipeline
        --field distance_texels=8 --field fixed_rays=0 --field classification=false
        --field relocation_iterations=0)
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | tee "$out/device.txt"
ddgi-bench "${paths[0]}" --grids 32x16x32 --rays 64 --frames 60 --warmup 8 --backend pipeline \
  > /dev/null
for round in $(seq 1 "$rounds"); do
  ddgi-bench "${paths[@]}" "${thesis[@]}" > "$out/glass-free-round$round.md"
  echo "round $round done"
done
