#!/usr/bin/env bash
# Where staircase's 1080p frame time goes with the defaults a session gets today (emitter
# sampling, the energy calibration's choice), and what the stream gets with fewer emitter
# samples, adaptive rays (settle_threshold: a converged static field traces a slice of its
# probes per update; off by default, docs/adaptive-rays.md) or a time budget (the field
# parameter budget_ms: docs/service.md, "Time budget").
# Usage (on the GPU host, through deploy/gpu-run.sh, with ddgi-bench, ddgi-server and
# ddgi-client-lean bundled): staircase-costs.sh OUT. Environment: BENCH=0 skips the pass costs;
# STREAMS (default: the $streams below): the sessions streamed, each "default" or
# comma-separated field assignments (deploy/service-bench.sh's LOAD_FIELDS); STREAM_SECONDS (8).
set -uo pipefail
out=${1:?OUT}
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | tee "$out/device.txt"
scene=scenes/staircase.ddgi.json
common=(--grids 32x16x32 --rays 64 --frames 20 --warmup 8 --backend pipeline)
# Clocks up before anything is timed.
[ "${BENCH:-1}" = 0 ] || ddgi-bench "$scene" "${common[@]}" --frames 60 > /dev/null
for round in $([ "${BENCH:-1}" = 0 ] || echo 1 2); do
  # Field settings written as LOAD_FIELDS writes them (below): "none" or a=1,b=2.
  for variant in none emitter_samples=1 emitter_samples=2 emitter_samples=2,probe_bounces=1; do
    fields=()
    for a in ${variant//,/ }; do [ "$a" = none ] || fields+=(--field "$a"); done
    echo "## round $round: $variant" >> "$out/bench.md"
    ddgi-bench "$scene" "${common[@]}" "${fields[@]}" | grep '^| staircase' >> "$out/bench.md"
  done
done
# The streams: deploy/service-bench.sh, one session per field variant.
streams="default emitter_samples=1 settle_threshold=0.01
  emitter_samples=1,settle_threshold=0.01 budget_ms=3 budget_ms=2.5"
CARRY=.devcarry SCENES=staircase SIZES=1920x1080 TRANSPORTS=grpc MULTI_VIEWS=0 \
  SECONDS_PER_RUN="${STREAM_SECONDS:-8}" LOAD_FIELDS="${STREAMS:-$streams}" \
  deploy/service-bench.sh run "$out/streams" | grep -v '^ddgi_' | tee "$out/service.txt"
