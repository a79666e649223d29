#!/usr/bin/env bash
# Renders the same set of check images (every repo scene and every real scene, direct light only
# and with GI) into OUT_DIR, so images from two machines or backends can be compared with
# ddgi-compare. Usage: deploy/render-checks.sh OUT_DIR [extra ddgi-render flags...]
set -euo pipefail
out="$1"
shift
mkdir -p "$out"
render=${DDGI_RENDER:-ddgi-render}
scenes=(scenes/cornell_box.gltf scenes/two_rooms_open.gltf scenes/two_rooms_closed.gltf
        scenes/two_rooms_plane_wall.gltf
        scenes/box_on_floor.gltf scenes/white_box.gltf
        scenes/cornell_kajiya.ddgi.json scenes/cornell_nvpro.ddgi.json
        scenes/lights_punctual.ddgi.json scenes/veach_ajar.ddgi.json scenes/staircase.ddgi.json
        scenes/modern_hall.ddgi.json scenes/living_room.ddgi.json)
for scene in "${scenes[@]}"; do
  name=$(basename "$scene"); name=${name%%.*}
  "$render" "$scene" --gi off --width 480 --height 270 --out "$out/$name.direct.exr" "$@" \
    --log-level warning > "$out/$name.direct.txt"
  "$render" "$scene" --gi on --warmup 64 --width 480 --height 270 --out "$out/$name.gi.exr" "$@" \
    --log-level warning > "$out/$name.gi.txt"
  echo "$name done"
done
