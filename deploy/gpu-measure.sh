#!/usr/bin/env bash
# The GPU measurements behind docs/results/, in two batches that each fit one 10-minute run on
# the lent GPU host. Here: deploy/gpu-bundle.sh --scenes ddgi-render ddgi-bench ddgi-eval \
#   ddgi-shadow-eval ddgi-server ddgi-client-lean; carry .devcarry and .gl there, then, in the
# repository root:
#
#   deploy/gpu-measure.sh fields OUT    # render checks (vs lavapipe), per-pass times at 1080p,
#                                       # the thesis-table field benchmark, field quality vs
#                                       # the path-traced reference
#   deploy/gpu-measure.sh bench OUT     # the thesis-table field benchmark alone
#   deploy/gpu-measure.sh shadows OUT   # direct-light modes vs the reference, the streaming
#                                       # service benchmark
#
# Each step writes its output to OUT as it goes (and is cut off by STEP_SECONDS, default 330),
# so a batch stopped at its limit still returns what it finished. Image sets come back as
# tarballs (at most 8 files return from a run).
set -uo pipefail
cd "$(dirname "$0")/.."
part="$1"
out="$2"
mkdir -p "$out"
step_seconds=${STEP_SECONDS:-330}
run_step() {  # NAME COMMAND...: runs the command with the bundle set up, output to OUT/NAME.txt
  local name=$1
  shift
  echo "== $name: $*"
  timeout "$step_seconds" deploy/gpu-run.sh "$@" 2>&1 | tee "$out/$name.txt"
}

repo_scenes=(scenes/cornell_box.gltf scenes/two_rooms_open.gltf scenes/box_on_floor.gltf)
real_scenes=(scenes/cornell_kajiya.ddgi.json scenes/cornell_nvpro.ddgi.json
             scenes/lights_punctual.ddgi.json scenes/veach_ajar.ddgi.json
             scenes/staircase.ddgi.json scenes/modern_hall.ddgi.json scenes/living_room.ddgi.json)

case "$part" in
  fields)
    run_step device nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv
    mkdir -p "$out/checks"
    run_step render-checks env DDGI_RENDER=ddgi-render deploy/render-checks.sh "$out/checks" \
      --backend pipeline
    tar -C "$out/checks" -czf "$out/checks-direct.tgz" $(cd "$out/checks" && ls *.direct.*)
    tar -C "$out/checks" -czf "$out/checks-gi.tgz" $(cd "$out/checks" && ls *.gi.*)
    rm -rf "$out/checks"
    run_step render1080 bash -c 'for s in scenes/*.gltf scenes/*.ddgi.json; do echo "## $s";
      ddgi-render "$s" --width 1920 --height 1080 --frames 20 --warmup 16 --backend pipeline \
        --out /tmp/frame.png --log-level warning; done'
    "$0" bench "$out"
    run_step eval ddgi-eval "${repo_scenes[@]}" "${real_scenes[@]}" --width 384 --height 216 \
      --spp 2048 --warmup 256 \
      --configs "management on:;management off:classification=false,relocation_iterations=0"
    ;;
  bench)
    # The thesis's Table 7.3/7.4 setup: no culling, 8x8 maps, no fixed rays. A first, untimed
    # run brings the GPU's clocks up (the first configurations of a cold GPU ran up to 5x slow).
    run_step bench-warmup ddgi-bench scenes/staircase.ddgi.json --grids 32x32x32 --rays 512 \
      --frames 40 --warmup 8
    run_step bench ddgi-bench scenes/staircase.ddgi.json scenes/veach_ajar.ddgi.json \
      --grids "16x16x16;32x16x32;32x32x32" --rays 64,128,256,512 --frames 20 --warmup 8 \
      --field distance_texels=8 --field fixed_rays=0 --field classification=false \
      --field relocation_iterations=0
    # Cost follows active probes: box_on_floor under a cube of probes 8 m high, with and without
    # culling (docs/results/probe-management-h100.md).
    for g in "16 0.5 -3.75 0.25" "32 0.25 -3.875 0.125" "64 0.125 -3.9375 0.0625"; do
      set -- $g
      for c in "" "--field classification=false --field relocation_iterations=0"; do
        # shellcheck disable=SC2086
        run_step "culling-$1${c:+-off}" ddgi-bench scenes/box_on_floor.gltf --grids "${1}x${1}x${1}" \
          --field spacing=$2,$2,$2 --field origin=$3,$4,$3 $c --rays 128 --frames 20 --warmup 4
      done
    done
    ;;
  shadows)
    run_step shadow-eval ddgi-shadow-eval scenes/box_on_floor.gltf scenes/cornell_box.gltf \
      scenes/two_rooms_open.gltf "scenes/lights_punctual.ddgi.json@-8,0,-8,8,3,8" \
      --width 1920 --height 1080 --spp 128 --full-spp 256 --warmup 64 --frames 30 \
      --resolutions "64:8;512:16;4096:16" --svg "$out/shadow-field.svg"
    CARRY=.devcarry SECONDS_PER_RUN=8 timeout "$step_seconds" deploy/service-bench.sh run \
      "$out/service" 2>&1 | tee "$out/service.txt"
    tar -C "$out" -czf "$out/service.tgz" service && rm -rf "$out/service"
    ;;
  *)
    echo "usage: deploy/gpu-measure.sh fields|bench|shadows OUT" >&2
    exit 2
    ;;
esac
