#!/usr/bin/env bash
# The issue 14 sweep over the choices beside rays and grids (docs/results/pareto.md "The sweep"):
# temporal hysteresis, the perceptual encoding, probe management, the direct light's mode
# (traced shadow rays, the shadow field at two resolutions, unshadowed) and the frame's size
# (drawn at 1/2 and 1/4 each way and upscaled), each one change from the default, at 1080p on the
# H200 against a 256-spp reference, with the path tracer's curve on each plot. Run through
# deploy/gpu-run.sh with `deploy/gpu-bundle.sh --scenes ddgi-eval` carried (.devcarry, .gl); one
# batch of three scenes per call keeps each under the 10-minute limit:
#   sweep.sh OUT 1    cornell_box, two_rooms_open, veach_ajar
#   sweep.sh OUT 2    staircase, modern_hall, living_room
# 256 warm-up updates: hysteresis 0.99 keeps 0.99^256 = 8% of its start after them (64 would
# leave 53%), so its row measures its noise, not its lag (the lag is docs/results/dynamic-response.md).
set -euo pipefail
out=${1:?OUT}
batch=${2:?BATCH (1 or 2)}
case $batch in
  1) scenes="scenes/cornell_box.gltf scenes/two_rooms_open.gltf scenes/veach_ajar.ddgi.json" ;;
  2) scenes="scenes/staircase.ddgi.json scenes/modern_hall.ddgi.json scenes/living_room.ddgi.json" ;;
  *) echo "sweep.sh: BATCH must be 1 or 2" >&2; exit 2 ;;
esac
configs="default:;hysteresis 0.9:hysteresis=0.9;hysteresis 0.99:hysteresis=0.99"
configs="$configs;gamma 1:irradiance_gamma=1;no management:classification=false,relocation_iterations=0"
configs="$configs;unshadowed:direct=unshadowed;shadow field 8:direct=shadow-field,shadow.texels=8"
configs="$configs;shadow field 16:direct=shadow-field;half size:frame_downscale=2"
configs="$configs;quarter size:frame_downscale=4"
mkdir -p "$out/sweep-$batch"  # ddgi-eval writes into an existing --pareto folder
# A device call ends at 600 s; stopping ddgi-eval a little before keeps what it wrote.
# shellcheck disable=SC2086  # the scene list is words
timeout "${SWEEP_TIMEOUT_S:-575}" ddgi-eval $scenes --width 1920 --height 1080 --spp 256 \
  --warmup 256 --frames 9 --backend pipeline --pareto "$out/sweep-$batch" --pt-max-spp 4 \
  --configs "$configs" 2>&1 | tee "$out/sweep-$batch.txt" ||
  echo "ddgi-eval exited with status ${PIPESTATUS[0]}" | tee -a "$out/sweep-$batch.txt"
# Only 8 files come back from a device run: the per-scene JSON and plots travel as one archive.
tar czf "$out/sweep-$batch.tgz" -C "$out" "sweep-$batch" && rm -rf "${out:?}/sweep-$batch"
