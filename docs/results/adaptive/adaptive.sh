#!/usr/bin/env bash
# Adaptive rays on the H200 (issue 14 item 5; docs/adaptive-rays.md): 600 frames at 1080p, 200
# of the scene as loaded (the field converged) then 400 after a change, for fixed rays and two
# settle thresholds: per frame the probe rays the field update traced and the error of the
# indirect view against the path-traced reference of the scene at that moment. Writes the
# table, and per scene SCENE.response.svg / .rays.svg / .response.csv (in one archive: only 8
# files come back from a device run). Run through deploy/gpu-run.sh with
# `deploy/gpu-bundle.sh --scenes ddgi-eval` carried (.devcarry, .gl): adaptive.sh OUT
set -euo pipefail
out=${1:?OUT}
mkdir -p "$out/adaptive"
configs='fixed rays:;adaptive 0.01:settle_threshold=0.01;adaptive 0.03:settle_threshold=0.03'
run() {
  ddgi-eval "$1" --dynamic "$2" --width 1920 --height 1080 --spp 256 --warmup 64 \
    --response-static 200 --response-frames 400 --backend pipeline --configs "$configs" \
    --pareto "$out/adaptive" 2>&1 | tee -a "$out/adaptive.txt"
}
run scenes/two_rooms_open.gltf light:0:1.5,0,0
run scenes/staircase.ddgi.json object:4:0,0,0.5
tar czf "$out/adaptive.tgz" -C "$out" adaptive && rm -rf "${out:?}/adaptive"
