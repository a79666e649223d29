#!/usr/bin/env bash
# Bandwidth of StreamProbes (docs/probe-stream.md) against streaming frames: for each scene and
# probe basis, a session with its default grid, warmed up, streams MESSAGES messages (one full,
# the rest deltas at the default 1% threshold, or THRESHOLDS); prints bytes per full message,
# per probe, per delta and the MB/s at 60 updates a second. The byte counts depend on the
# field's content (its noise, what changes), not on the GPU, so lavapipe measures them too.
# Results: docs/results/probe-stream.md.
#
#   deploy/probe-stream-bench.sh [BUILD_DIR]     # default build/
#
# Environment: SCENES (default "cornell_box two_rooms_open veach_ajar living_room modern_hall
# staircase"), BASES ("sh octahedral"), THRESHOLDS ("0.01 0.05"), MESSAGES (30), WARMUP (64).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
scenes=${SCENES:-cornell_box two_rooms_open veach_ajar living_room modern_hall staircase}
work=$(mktemp -d)
trap 'kill "$server" 2>/dev/null || true; rm -rf "$work"' EXIT
"$build/ddgi-server" --listen 127.0.0.1:0 --port-file "$work/port" --metrics-port -1 \
  >"$work/server.log" 2>&1 &
server=$!
for _ in $(seq 100); do [ -s "$work/port" ] && break; sleep 0.1; done
c() { "$build/ddgi-client" --server "127.0.0.1:$(cat "$work/port")" "$@"; }
field() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$@"; }

echo "| scene | basis | probes | threshold | full KB | full B/probe | delta KB (mean) | probes per delta | MB/s at 60 updates/s |"
echo "|---|---|---|---|---|---|---|---|---|"
for scene in $scenes; do
  for basis in ${BASES:-sh octahedral}; do
    c load "$scene" --warmup "${WARMUP:-64}" --field "basis=$basis" >"$work/session.json"
    session=$(field "$work/session.json" session_id)
    for threshold in ${THRESHOLDS:-0.01 0.05}; do
      c probe-stream --session "$session" --messages "${MESSAGES:-30}" --threshold "$threshold" \
        >"$work/stream.json"
      python3 - "$work/stream.json" "$scene" "$basis" "$threshold" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
delta = s["delta_bytes_per_message"]
print(f"| {sys.argv[2]} | {sys.argv[3]} | {s['probes']} | {sys.argv[4]} | "
      f"{s['full_bytes_per_message'] / 1024:.1f} | {s['full_bytes_per_probe']:.1f} | "
      f"{delta / 1024:.1f} | {s['delta_probes_per_message']:.0f} | {delta * 60 / 1e6:.2f} |")
PY
    done
    c close --session "$session" >/dev/null
  done
done
