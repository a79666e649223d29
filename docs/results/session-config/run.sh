#!/usr/bin/env bash
# The session a user gets (issue 45), measured on a GPU host through the service itself: for each
# SCENE, a session loaded with the defaults (the load's wall time; then a first 1920x1080 frame),
# streamed at 1920x1080 while its scene is calibrated in the background (2-second runs, polling
# GetSession until the calibration is done: the switch's time), then 5 s at the chosen
# configuration (GPU ms per frame and field-update ms from the stream's own pass timings); for
# the scenes in BUDGET_SCENES, budget_ms 2, 4, 8 and 16 set over RPC, 4 s each. With RESTART=1 a
# second server on the same calibration folder loads the first SCENE again right after it is
# measured (it must not calibrate), and measures the rest. Run through deploy/gpu-run.sh with `deploy/gpu-bundle.sh --scenes ddgi-server
# ddgi-client-lean` carried (.devcarry, .gl). The folder CACHE (default /tmp/ddgi-calibrations)
# outlives the call on a warm machine. Tables: docs/results/session-config/table.py OUT...
# Usage: run.sh OUT SCENE...
set -euo pipefail
out=${1:?OUT}
shift
mkdir -p "$out"
cache=${CACHE:-/tmp/ddgi-calibrations}
budget_scenes=" ${BUDGET_SCENES:-staircase cornell_nvpro cornell_kajiya living_room} "
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | tee "$out/device.txt" || true
now() { date +%s.%N; }

start_server() {  # start_server NAME: a server on a free port, its client in `client`
  rm -f "$out/$1.port"
  ddgi-server --listen 127.0.0.1:0 --port-file "$out/$1.port" --metrics-port -1 \
    --max-fps 1000 --encode-threads 8 --scene-root scenes --budget-cache "$cache" \
    >"$out/$1.log" 2>&1 &
  server=$!
  for _ in $(seq 1 600); do [ -s "$out/$1.port" ] && break; sleep 0.1; done
  client=(ddgi-client-lean --server "127.0.0.1:$(cat "$out/$1.port")" --deadline 600)
}

session_id() { sed -n 's/^ *"session_id": "\([^"]*\)".*/\1/p' "$1" | head -n 1; }
state_of() { sed -n 's/^ *"state": "\([A-Z_]*\)".*/\1/p' "$1" | head -n 1; }

stream() {  # stream SESSION SECONDS OUT.json
  "${client[@]}" stream --session "$1" --width 1920 --height 1080 --frames 1000000 \
    --seconds "$2" >"$3"
}

measure_scene() {
  local scene=$1 t0 t1 t2 session state i
  t0=$(now)
  "${client[@]}" load "$scene" >"$out/$scene.load.json"
  t1=$(now)
  session=$(session_id "$out/$scene.load.json")
  "${client[@]}" frame --session "$session" --width 1920 --height 1080 >"$out/$scene.first.json"
  t2=$(now)
  echo "$scene load_s $(awk -v a="$t1" -v b="$t0" 'BEGIN{print a - b}') first_frame_s $(awk -v a="$t2" -v b="$t1" 'BEGIN{print a - b}')" |
    tee "$out/$scene.times.txt"
  for i in $(seq 1 90); do  # at most 180 s of streaming while it calibrates
    stream "$session" 2 "$out/$scene.during.$i.json"
    "${client[@]}" session --session "$session" >"$out/$scene.session.json"
    state=$(sed -n '/"calibration"/,/}/p' "$out/$scene.session.json" | sed -n 's/^ *"state": "\([A-Z_]*\)".*/\1/p' | head -n 1)
    echo "$scene during $i: $state $(tr -d '\n ' <"$out/$scene.during.$i.json" | head -c 160)"
    [ "$state" = STATE_DONE ] || [ "$state" = STATE_FAILED ] || [ "$state" = STATE_OFF ] && break
  done
  stream "$session" 5 "$out/$scene.default.json"
  echo "$scene default: $(tr -d '\n ' <"$out/$scene.default.json")"
  if [[ "$budget_scenes" == *" $scene "* ]]; then
    for budget in 2 4 8 16; do
      "${client[@]}" params set --session "$session" "budget_ms=$budget" \
        >"$out/$scene.budget$budget.params.json"
      stream "$session" 4 "$out/$scene.budget$budget.json"
      echo "$scene budget $budget: $(tr -d '\n ' <"$out/$scene.budget$budget.json")"
    done
  fi
  "${client[@]}" close --session "$session" >/dev/null
}

restart_server() {  # a second server on the same calibration folder loads SCENE: it must not calibrate
  kill -TERM "$server" && wait "$server" || true
  start_server restarted
  "${client[@]}" load "$1" >"$out/restart.$1.load.json"
  echo "restart: $(sed -n '/"calibration"/,/}/p' "$out/restart.$1.load.json" | tr -d '\n ')"
  "${client[@]}" close --session "$(session_id "$out/restart.$1.load.json")" >/dev/null
}

# The restart comes right after the first scene, so a call cut short by its time limit still has it;
# the other scenes are measured on the restarted server.
start_server server
first=$1
for scene in "$@"; do
  measure_scene "$scene"
  rm -rf "$out/calibrations" && cp -r "$cache" "$out/calibrations"
  if [ "$scene" = "$first" ] && [ "${RESTART:-0}" = 1 ]; then restart_server "$first"; fi
done
kill -TERM "$server" && wait "$server" || true
