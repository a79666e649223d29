#!/usr/bin/env bash
# Soak test of ddgi-server (issue 18; not in CI: it runs for an hour). SESSIONS sessions stream
# frames without pause while a churn loop, every CHURN seconds, does one of: add/move/remove a
# light, move an instance, resize the field grid or change its rays, create/resize/delete a view,
# reload the scene. Every INTERVAL seconds the server's resident memory, threads, open file
# descriptors and GPU bytes are sampled into OUT_DIR/samples.csv; at the end
# deploy/soak_plot.py draws them (OUT_DIR/soak.svg) and the script fails when, after the first
# WARMUP_SAMPLES samples, RSS grew by more than RSS_GROWTH_PERCENT over its warm-up maximum, or
# threads, fds or GPU bytes by more than 10% (deploy/soak_plot.py says why).
#
#   deploy/soak.sh OUT_DIR [MINUTES]          default 60 minutes, binaries from build/
#
# Environment: SESSIONS (4), INTERVAL (60), CHURN (5), SIZE (160x90: lavapipe-friendly),
# WARMUP_SAMPLES (10: the churn meets every configuration first), RSS_GROWTH_PERCENT (10),
# SERVER / CLIENT (build/ddgi-server, build/ddgi-client), METRICS_PORT (9471).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: deploy/soak.sh OUT_DIR [MINUTES]}
minutes=${2:-60}
sessions=${SESSIONS:-4}
interval=${INTERVAL:-60}
churn=${CHURN:-5}
size=${SIZE:-160x90}
server_bin=${SERVER:-build/ddgi-server}
client_bin=${CLIENT:-build/ddgi-client}
metrics_port=${METRICS_PORT:-9471}
mkdir -p "$out"

"$server_bin" --listen 127.0.0.1:0 --port-file "$out/port" --metrics-port "$metrics_port" \
  --scene-root scenes >"$out/server.log" 2>&1 &
server=$!
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  kill -TERM "$server" 2>/dev/null || true
  wait 2>/dev/null || true
}
trap cleanup EXIT
for _ in $(seq 1 600); do [ -s "$out/port" ] && break; sleep 0.1; done
[ -s "$out/port" ] || { echo "soak: the server did not start (see $out/server.log)" >&2; exit 1; }
client=("$client_bin" --server "127.0.0.1:$(cat "$out/port")")
small_field=(--field counts=4,4,4 --field rays_per_probe=32 --warmup 2)

json_field() { sed -n "s/^ *\"$1\": \"\\{0,1\\}\\([^\",]*\\).*/\\1/p" | head -n 1; }
scrape() {  # the value of one Prometheus sample from the server's metrics endpoint
  exec 3<>"/dev/tcp/127.0.0.1/$metrics_port"
  printf 'GET /metrics HTTP/1.0\r\n\r\n' >&3
  awk -v name="$1" '$1 == name { print $2 }' <&3
  exec 3<&-
}

ids=()
for i in $(seq 1 "$sessions"); do
  scene=cornell_box
  [ $((i % 2)) = 0 ] && scene=two_rooms_open
  ids+=("$("${client[@]}" load "$scene" "${small_field[@]}" | json_field session_id)")
done
# Streams without pause; a stream that ends (closed view, reload) is started again.
for id in "${ids[@]}"; do
  (while kill -0 "$server" 2>/dev/null; do
     "${client[@]}" stream --session "$id" --width "${size%x*}" --height "${size#*x}" \
       --seconds 30 >/dev/null 2>&1 || sleep 1
   done) &
  pids+=($!)
done

churn_once() {  # one random change to one random session
  local id=${ids[$((RANDOM % ${#ids[@]}))]}
  case $((RANDOM % 7)) in
    0) "${client[@]}" light add --session "$id" --type point --position 0,1.5,0 --intensity 2 ;;
    1) "${client[@]}" light remove --session "$id" --id 1 ;;
    2) "${client[@]}" transform --session "$id" --instance 0 \
         --translate "0.0$((RANDOM % 9)),0,0" ;;
    3) "${client[@]}" params set --session "$id" "counts=$((3 + RANDOM % 3)),4,4" ;;
    4) "${client[@]}" params set --session "$id" "rays_per_probe=$((16 << (RANDOM % 3)))" ;;
    5) local view
       view=$("${client[@]}" view-create --session "$id" --width 64 --height 36 | json_field view_id)
       [ -n "$view" ] && "${client[@]}" view-update --session "$id" --view "$view" --width 96 \
         --height 54 && "${client[@]}" view-delete --session "$id" --view "$view" ;;
    6) "${client[@]}" reload --session "$id" cornell_box --warmup 2 ;;
  esac
}
(while kill -0 "$server" 2>/dev/null; do churn_once >/dev/null 2>&1 || true; sleep "$churn"; done) &
pids+=($!)

echo "minute,rss_mib,threads,fds,gpu_mib,frames_sent" >"$out/samples.csv"
end=$((SECONDS + minutes * 60))
while [ "$SECONDS" -lt "$end" ]; do
  sleep "$interval"
  kill -0 "$server" 2>/dev/null || { echo "soak: the server died (see $out/server.log)" >&2; exit 1; }
  rss_kb=$(awk '/^VmRSS/ { print $2 }' "/proc/$server/status")
  threads=$(awk '/^Threads/ { print $2 }' "/proc/$server/status")
  fds=$(find "/proc/$server/fd" -mindepth 1 -maxdepth 1 | wc -l)
  gpu=$(scrape ddgi_gpu_memory_bytes)
  sent=$(scrape ddgi_frames_sent_total)
  line=$(awk -v t="$SECONDS" -v r="$rss_kb" -v th="$threads" -v f="$fds" -v g="$gpu" -v s="$sent" \
    'BEGIN { printf "%.1f,%.1f,%d,%d,%.1f,%d", t / 60, r / 1024, th, f, g / 1048576, s }')
  echo "$line" | tee -a "$out/samples.csv"
done

python3 deploy/soak_plot.py "$out/samples.csv" "$out/soak.svg" \
  --warmup "${WARMUP_SAMPLES:-10}" --rss-growth "${RSS_GROWTH_PERCENT:-10}"
