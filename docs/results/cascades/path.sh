#!/usr/bin/env bash
# Issue 17 along the street's camera path (scenes/street.path.json) on the H200, run through
# deploy/gpu-run.sh with the bundle of `deploy/gpu-bundle.sh ddgi-eval ddgi-server
# ddgi-client-lean` carried (.devcarry, .gl):
#   path.sh eval OUT     ddgi-eval --path: three tracking cascades of 32x16x32 (ratio 4) and of
#                        48x8x42 (ratio 4 and 3) against one grid of the same probe count
#                        (192x8x32) fitted to the street, 30 frames per
#                        second of the walk, scored every 10 s against 1024-spp references
#   path.sh stream OUT SPEED SECONDS
#                        the service streaming the walk at 1920x1080 over gRPC with the same
#                        cascades: camera moves every 0.1 s along the path at SPEED path
#                        seconds per second, for SECONDS; fps, latency, field ms per frame
set -euo pipefail
tracking="spacing=0.5,0.5,0.5,cascades=3,track_camera=true"
cascades="counts=32,16,32,$tracking,cascade_spacing_ratio=4"
one_grid="counts=192,8,32,spacing=2.0833,2.5,1.25,origin=-198.958,1.25,-19.375"
# Flatter cascades (fewer probes in y, more in x and z; 48,384 probes) at ratio 4 and 3.
flat4="counts=48,8,42,$tracking,cascade_spacing_ratio=4"
flat3="counts=48,8,42,$tracking,cascade_spacing_ratio=3"

eval_path() {
  local out=$1
  mkdir -p "$out/path"
  ddgi-eval scenes/street.ddgi.json --path scenes/street.path.json --width 480 --height 270 \
    --spp 1024 --warmup 256 --backend pipeline \
    --configs "cascades ratio 4:$cascades;flat cascades ratio 4:$flat4;flat cascades ratio 3:$flat3;one grid 192x8x32:$one_grid" \
    --out-dir "$out/path"
}

stream_path() {
  local out=$1 speed=$2 seconds=$3
  ddgi-server --listen 127.0.0.1:0 --port-file "$out/port" --metrics-port -1 --max-fps 1000 \
    --encode-threads 8 --scene-root scenes >"$out/server.log" 2>&1 &
  local server=$!
  for _ in $(seq 1 600); do [ -s "$out/port" ] && break; sleep 0.1; done
  local client=(ddgi-client-lean --server "127.0.0.1:$(cat "$out/port")" --deadline 600)
  "${client[@]}" load street --warmup 256 --field counts=32,16,32 --field spacing=0.5,0.5,0.5 \
    --field cascades=3 --field cascade_spacing_ratio=4 --field track_camera=true \
    >"$out/session.json"
  local session
  session=$(sed -n 's/^ *"session_id": "\([^"]*\)".*/\1/p' "$out/session.json" | head -n 1)
  local moves
  moves=$(awk -v s="$seconds" 'BEGIN{print int(s / 0.1)}')
  "${client[@]}" stream --session "$session" --width 1920 --height 1080 --frames 100000000 \
    --seconds "$seconds" --camera-moves "$moves" --move-interval 0.1 \
    --camera-path scenes/street.path.json --path-speed "$speed" --out "$out/last.jpg" \
    | tee "$out/stream-$speed.json"
  kill -TERM "$server"
  wait "$server" || true
}

case "${1:-}" in
  eval) eval_path "${2:?OUT}" ;;
  stream) stream_path "${2:?OUT}" "${3:?SPEED}" "${4:?SECONDS}" ;;
  *) echo "usage: path.sh eval OUT | stream OUT SPEED SECONDS" >&2; exit 2 ;;
esac
