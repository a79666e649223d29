#!/usr/bin/env bash
# Where staircase's 1080p frame time goes with the defaults a session gets today (emitter
# sampling, the energy calibration's choice), and what the stream gets with fewer emitter
# samples or a time budget (the field parameter budget_ms: docs/service.md, "Time budget").
# Usage (on the GPU host, through deploy/gpu-run.sh, with ddgi-bench, ddgi-server and
# ddgi-client-lean bundled): staircase-costs.sh OUT. Environment: BENCH=0 skips the pass costs;
# STREAMS (default "default emitter_samples=1 budget_ms=3 budget_ms=2.5"): the sessions
# streamed, each its field assignment or "default"; STREAM_SECONDS (8).
set -uo pipefail
out=${1:?OUT}
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | tee "$out/device.txt"
scene=scenes/staircase.ddgi.json
common=(--grids 32x16x32 --rays 64 --frames 20 --warmup 8 --backend pipeline)
# Clocks up before anything is timed.
[ "${BENCH:-1}" = 0 ] || ddgi-bench "$scene" "${common[@]}" --frames 60 > /dev/null
for round in $([ "${BENCH:-1}" = 0 ] || echo 1 2); do
  for variant in "none" "emitter_samples=1" "emitter_samples=2" \
                 "emitter_samples=2 probe_bounces=1"; do
    fields=()
    for a in $variant; do [ "$a" = none ] || fields+=(--field "$a"); done
    echo "## round $round: $variant" >> "$out/bench.md"
    ddgi-bench "$scene" "${common[@]}" "${fields[@]}" | grep '^| staircase' >> "$out/bench.md"
  done
done
ddgi-server --listen 127.0.0.1:0 --port-file "$out/port" --max-fps 1000 --encode-threads 8 \
  --scene-root scenes > "$out/server.log" 2>&1 &
server=$!
for _ in $(seq 1 600); do [ -s "$out/port" ] && break; sleep 0.1; done
client=(ddgi-client-lean --server "127.0.0.1:$(cat "$out/port")" --deadline 600)
for variant in ${STREAMS:-default emitter_samples=1 budget_ms=3 budget_ms=2.5}; do
  fields=()
  [ "$variant" = default ] || fields+=(--field "$variant")
  "${client[@]}" load staircase --warmup 32 "${fields[@]}" > "$out/session.json"
  session=$(sed -n 's/^ *"session_id": "\([^"]*\)".*/\1/p' "$out/session.json" | head -n 1)
  "${client[@]}" stream --session "$session" --width 1920 --height 1080 --frames 1000000 \
    --seconds "${STREAM_SECONDS:-8}" --camera-moves 20 \
    --move-interval "$(awk -v s="${STREAM_SECONDS:-8}" 'BEGIN{print s/22}')" \
    --out "$out/frame.jpg" > "$out/stream.json"
  echo "stream $variant: $(tr -d '\n ' < "$out/stream.json")" | tee -a "$out/service.txt"
  "${client[@]}" close --session "$session" > /dev/null
done
kill -TERM "$server"
wait "$server"
