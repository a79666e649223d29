#!/usr/bin/env bash
# The scroll started inside the update's command buffer (docs/cascades.md, "Where the work
# runs") on the H200, through deploy/gpu-run.sh with the bundle of `deploy/gpu-bundle.sh
# ddgi-bench ddgi-server ddgi-client-lean` carried (.devcarry, .gl); repository scenes only:
#   scroll-in-frame.sh OUT   1. ddgi-bench --scroll-every 4: the scroll call's wall time and the
#                               field's GPU ms in frames whose update starts a scroll against
#                               the others (cornell_box and the street, 32x16x32, 128 rays)
#                            2. the street's walk streamed at 1080p at walking speed and at four
#                               times it (path.sh stream), 60 s each
set -euo pipefail
out=${1:?OUT}
mkdir -p "$out"
# Clocks up first: the bench's warm-up frames run under the same load.
ddgi-bench scenes/cornell_box.gltf scenes/street.ddgi.json --grids 32x16x32 --rays 128 \
  --frames 60 --warmup 32 --scroll-every 4 --backend pipeline 2>&1 | tee "$out/scroll-bench.txt"
for speed in 1 4; do
  mkdir -p "$out/stream-$speed"
  bash docs/results/cascades/path.sh stream "$out/stream-$speed" "$speed" 60 \
    2>&1 | tail -n 40 >"$out/stream-$speed.txt"
done
rm -f "$out"/stream-*/last.jpg
