#!/usr/bin/env bash
# The time budget on the H200 (issue 14, "--budget-ms"; docs/service.md "Time budget"): for the
# six scenes at 1080p, every budget candidate measured as ddgi-eval measures it (GPU medians,
# FLIP against a 256-spp reference), then the server's own calibration and its choice for 1, 2,
# 4 and 8 ms beside the measurements: the chosen configuration's measured ms over the budget
# (goal <= 1.1) and its FLIP over the best measured configuration within the budget (goal <= 1.1).
# With --pareto, each scene's candidates also make its Pareto plot against the path tracer
# (1..8 spp). Run through deploy/gpu-run.sh with `deploy/gpu-bundle.sh --scenes ddgi-eval` carried
# (.devcarry, .gl); one batch per call keeps each under the 10-minute limit:
#   budget.sh OUT 1    cornell_box, two_rooms_open, veach_ajar
#   budget.sh OUT 2    staircase, modern_hall, living_room
#   budget.sh OUT clocks   six identical configurations of two_rooms_open and of modern_hall
#                      timed back to back: the frame ms of identical work should agree (GPU
#                      clock state; h200-2026-12-05.md "Diagnosis")
set -euo pipefail
out=${1:?OUT}
batch=${2:?BATCH (1 or 2)}
mkdir -p "$out/pareto-$batch"  # ddgi-eval writes into an existing --pareto folder
case $batch in
  1) scenes="scenes/cornell_box.gltf scenes/two_rooms_open.gltf scenes/veach_ajar.ddgi.json" ;;
  2) scenes="scenes/staircase.ddgi.json scenes/modern_hall.ddgi.json scenes/living_room.ddgi.json" ;;
  clocks)
    same="a:rays_per_probe=128;b:rays_per_probe=128;c:rays_per_probe=128;d:rays_per_probe=128"
    same="$same;e:rays_per_probe=128;f:rays_per_probe=128"
    ddgi-eval scenes/two_rooms_open.gltf scenes/modern_hall.ddgi.json --width 1920 --height 1080 \
      --spp 64 --warmup 64 --frames 31 --backend pipeline --configs "$same" 2>&1 |
      tee "$out/clocks.txt"
    exit 0 ;;
  *) echo "budget.sh: BATCH must be 1 or 2" >&2; exit 2 ;;
esac
# A device call ends at 600 s; stopping ddgi-eval a little before keeps what it wrote (the archive
# below still gets made). Status 124 in the log means it was cut short.
# shellcheck disable=SC2086  # the scene list is words
timeout "${BUDGET_TIMEOUT_S:-575}" ddgi-eval $scenes --width 1920 --height 1080 --spp 256 --warmup 64 --frames 9 \
  --backend pipeline --budgets 1,2,4,8 --pareto "$out/pareto-$batch" --pt-max-spp 8 2>&1 |
  tee "$out/budget-$batch.txt" || echo "ddgi-eval exited with status ${PIPESTATUS[0]}" | tee -a "$out/budget-$batch.txt"
# Only 8 files come back from a device run: the per-scene JSON and plots travel as one archive.
tar czf "$out/pareto-$batch.tgz" -C "$out" "pareto-$batch" && rm -rf "${out:?}/pareto-$batch"
