#!/usr/bin/env bash
# The default run: builds the service, starts ddgi-server on the built-in default scene
# (scenes/cornell_box.gltf), fetches frames from it through ddgi-client (one rendered frame and
# a short stream), writes them as images, and stops the server cleanly with SIGTERM.
#
#   deploy/run-default.sh [--viewer | --web] [OUT_DIR]
#
# OUT_DIR (default: default-run/) receives frame.png, stream_last.jpg and the JSON replies.
# --viewer also opens ddgi-viewer on the session (needs a display) until its window is closed.
# --web also serves the browser client (docs/web.md) at http://localhost:WEB_PORT/ and keeps
# the server and the session running until Ctrl-C; the page can join the session or make its own.
# Environment: BUILD_DIR (default build), JOBS (default: all cores), WIDTH/HEIGHT (640x480),
# WEB_PORT (8080), WEB_ADDRESS (127.0.0.1; 0.0.0.0 serves other machines too).
set -euo pipefail
cd "$(dirname "$0")/.."

viewer=0 web=0
if [ "${1:-}" = "--viewer" ]; then viewer=1; shift; fi
if [ "${1:-}" = "--web" ]; then web=1; shift; fi
out="${1:-default-run}"
build="${BUILD_DIR:-build}"
jobs="${JOBS:-$(nproc)}"
width="${WIDTH:-640}"
height="${HEIGHT:-480}"
mkdir -p "$out"

cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
targets=(ddgi-server ddgi-client)
if [ "$viewer" = 1 ]; then targets+=(ddgi-viewer); fi
cmake --build "$build" -j "$jobs" --target "${targets[@]}"

port_file="$out/server.port"
rm -f "$port_file"
web_flags=()
if [ "$web" = 1 ]; then
  # three.js for the page's local-rendering mode, as pinned in web/package-lock.json.
  if [ ! web/node_modules/.package-lock.json -nt web/package-lock.json ]; then
    npm ci --prefix web --no-audit --no-fund || echo "npm ci failed: the page's local mode will say so" >&2
  fi
  web_flags=(--web-port "${WEB_PORT:-8080}" --web-address "${WEB_ADDRESS:-127.0.0.1}")
fi
"$build/ddgi-server" --listen 127.0.0.1:0 --port-file "$port_file" --metrics-port -1 \
  "${web_flags[@]}" >"$out/server.log" 2>&1 &
server=$!
stop_server() {
  if kill -0 "$server" 2>/dev/null; then kill -TERM "$server"; wait "$server" || true; fi
}
trap stop_server EXIT

for _ in $(seq 1 300); do
  [ -s "$port_file" ] && break
  kill -0 "$server" 2>/dev/null || { cat "$out/server.log"; echo "ddgi-server failed" >&2; exit 1; }
  sleep 0.1
done
[ -s "$port_file" ] || { echo "ddgi-server did not start in 30 s" >&2; exit 1; }
client=("$build/ddgi-client" --server "127.0.0.1:$(cat "$port_file")")

"${client[@]}" info >"$out/info.json"
"${client[@]}" load cornell_box >"$out/session.json"
session=$(sed -n 's/^ *"session_id": "\([^"]*\)".*/\1/p' "$out/session.json" | head -n 1)
echo "session $session on cornell_box"
"${client[@]}" frame --session "$session" --width "$width" --height "$height" \
  --out "$out/frame.png" >"$out/frame.json"
echo "wrote $out/frame.png (${width}x${height})"
"${client[@]}" stream --session "$session" --width "$width" --height "$height" --frames 30 \
  --camera-moves 4 --move-interval 0.25 --out "$out/stream_last.jpg" | tee "$out/stream.json"
echo "wrote $out/stream_last.jpg"
if [ "$viewer" = 1 ]; then
  "$build/ddgi-viewer" --server "127.0.0.1:$(cat "$port_file")" --session "$session" \
    --width "$width" --height "$height"
fi
if [ "$web" = 1 ]; then
  echo "the browser client: open http://localhost:${WEB_PORT:-8080}/ and join session $session"
  echo "(or create another); Ctrl-C stops the server"
  # Ctrl-C reaches this script only (a script's background jobs ignore SIGINT): the wait ends
  # and the server is stopped below with SIGTERM, as always.
  trap 'echo; echo stopping' INT
  wait "$server" || true
  trap - INT
  kill -0 "$server" 2>/dev/null || { echo "ddgi-server ended (see $out/server.log)" >&2; exit 1; }
fi
"${client[@]}" close --session "$session" >/dev/null 2>&1 || true

trap - EXIT
kill -TERM "$server"
if wait "$server"; then
  echo "ddgi-server stopped cleanly"
else
  echo "ddgi-server exited with status $? (see $out/server.log)" >&2
  exit 1
fi
