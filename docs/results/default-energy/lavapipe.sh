#!/usr/bin/env bash
# The default-energy table (docs/results/default-energy.md) on the CPU's Vulkan (lavapipe): every
# repo scene and every real scene of ../shared/scenes at default settings, the frame's and the
# indirect view's mean linear luminance over the path-traced reference's (the "mean/ref"
# columns). Small frames: the mean is a low-order figure, and lavapipe traces ~1 Mrays/s.
# Usage: docs/results/default-energy/lavapipe.sh [BUILD_DIR]   (about 40 minutes on 2 cores)
set -euo pipefail
cd "$(dirname "$0")/../../.."
build=${1:-build}
scenes=(box_on_floor.gltf cornell_box.gltf two_rooms_closed.gltf two_rooms_open.gltf
        two_rooms_plane_wall.gltf white_box.gltf cornell_kajiya.ddgi.json cornell_nvpro.ddgi.json
        lights_punctual.ddgi.json veach_ajar.ddgi.json staircase.ddgi.json modern_hall.ddgi.json
        living_room.ddgi.json street.ddgi.json)
for scene in "${scenes[@]}"; do
  "$build/ddgi-eval" "scenes/$scene" --width 160 --height 90 --spp 256 --warmup 128 --frames 1 \
    --configs "default:" | grep -E '^\| [a-z_]+ \| default'
done
