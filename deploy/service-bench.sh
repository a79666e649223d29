#!/usr/bin/env bash
# Streaming benchmark of the render service on a GPU host, client on the same host: frames per
# second streamed at 1280x720 and 1920x1080, and the latency from a camera command to the first
# frame that shows it (ddgi-client stream --camera-moves), through gRPC and through the web
# front's WebSocket. Results: docs/results/service-bench.md.
#
#   deploy/service-bench.sh bundle        # here: Release ddgi-server + ddgi-client-lean, their
#                                         # SPIR-V and non-glibc libraries, the real scenes used,
#                                         # into build-svc-carry/ (ignored by git, carried)
#   deploy/service-bench.sh run OUT_DIR   # on the GPU host (with the Vulkan loader in .gl/);
#                                         # ends with the run's table (OUT_DIR/table.md)
#   deploy/service-bench.sh table OUT_DIR # that table again (deploy/service_bench_table.py)
#
# Environment for `run`: SCENES (default "cornell_box modern_hall living_room"), SIZES (default
# "1280x720 1920x1080"), TRANSPORTS (default "grpc web": each stream once through gRPC and once
# through the web front's WebSocket, as a browser gets it), SECONDS_PER_RUN (10),
# ENCODE_THREADS (8), WARMUP (32), LOAD_FIELDS (default "default": the sessions loaded per scene,
# each "default" or comma-separated field assignments given to `load --field`, e.g.
# "default emitter_samples=1 budget_ms=3"), MULTI_VIEWS (4; 0 skips) and MULTI_SIZE (1280x720):
# that many clients streaming views of one session at that size; SERVER_FLAGS: more ddgi-server
# flags (e.g. "--submit-ahead-ms 1000 --budget-cache /tmp/calibrations").
set -euo pipefail
cd "$(dirname "$0")/.."
# CARRY: a bundle with bin/ (ddgi-server, ddgi-client-lean, spirv/), lib/ and scenes/; `run`
# also takes deploy/gpu-bundle.sh's .devcarry (CARRY=.devcarry).
carry=${CARRY:-build-svc-carry}

bundle() {
  cmake -S . -B build-svc-rel -G Ninja -DCMAKE_BUILD_TYPE=Release -DDDGI_BUILD_TESTS=OFF \
    -DDDGI_BUILD_CLIENT=ON >/dev/null
  ninja -C build-svc-rel -j "${JOBS:-2}" ddgi-server ddgi-client-lean
  rm -rf "$carry" && mkdir -p "$carry/bin" "$carry/lib" "$carry/scenes"
  cp build-svc-rel/ddgi-server build-svc-rel/ddgi-client-lean "$carry/bin/"
  strip "$carry/bin/"ddgi-*
  cp -r build-svc-rel/spirv "$carry/bin/spirv" && rm -f "$carry/bin/spirv/"*.d
  for bin in "$carry/bin/"ddgi-*; do ldd "$bin" | awk '/=> \//{print $3}'; done | sort -u |
    grep -vE '/(libc|libm|libpthread|libdl|librt|ld-linux-x86-64|libresolv)\.so' |
    while read -r lib; do cp -L "$lib" "$carry/lib/"; done
  cp -r ../shared/scenes/ModernHall ../shared/scenes/LivingRoom "$carry/scenes/"
  du -sh "$carry"
}

# The server's Prometheus text (no curl needed).
scrape() {
  exec 3<>/dev/tcp/127.0.0.1/9464
  printf 'GET /metrics HTTP/1.0\r\n\r\n' >&3
  cat <&3
  exec 3<&-
}

run() {
  local out=$1
  mkdir -p "$out"
  for f in .gl/*.deb; do dpkg -x "$f" /; done
  ldconfig
  if [ -f /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json ]; then
    export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
  fi
  if [ ! -e ../shared/scenes ]; then mkdir -p ../shared && ln -s "$PWD/$carry/scenes" ../shared/scenes; fi
  export LD_LIBRARY_PATH="$PWD/$carry/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  local bin="$PWD/$carry/bin"
  "$bin/ddgi-server" --listen 127.0.0.1:0 --port-file "$out/port" --metrics-port 9464 \
    --max-fps 1000 --encode-threads "${ENCODE_THREADS:-8}" --scene-root scenes \
    --web-port 8090 --web-address 127.0.0.1 --web-root "$PWD/web" ${SERVER_FLAGS:-} \
    >"$out/server.log" 2>&1 &
  local server=$!
  for _ in $(seq 1 600); do [ -s "$out/port" ] && break; sleep 0.1; done
  local client=("$bin/ddgi-client-lean" --server "127.0.0.1:$(cat "$out/port")" --deadline 600)
  "${client[@]}" info >"$out/info.json"
  for scene in ${SCENES:-cornell_box modern_hall living_room}; do
    for fields in ${LOAD_FIELDS:-default}; do
      stream_session "$out" "$scene" "$fields"
    done
  done
  [ "${MULTI_VIEWS:-4}" = 0 ] || multi_view "$out"
  kill -TERM "$server"
  wait "$server"
  deploy/service_bench_table.py "$out" | tee "$out/table.md"
}

# One session of SCENE loaded with FIELDS ("default" or a=1,b=2), streamed at every size through
# every transport. Runs are named SCENE[.FIELDS].SIZE[.web]. Called from run(): uses its `client`.
stream_session() {
  local out=$1 scene=$2 fields=$3 name=$2 load=()
  if [ "$fields" != default ]; then
    name="$scene.$fields"
    local assignment
    for assignment in ${fields//,/ }; do load+=(--field "$assignment"); done
  fi
  "${client[@]}" load "$scene" --warmup "${WARMUP:-32}" "${load[@]}" >"$out/$name.session.json"
  local session
  session=$(sed -n 's/^ *"session_id": "\([^"]*\)".*/\1/p' "$out/$name.session.json" | head -n 1)
  for size in ${SIZES:-1280x720 1920x1080}; do
    for transport in ${TRANSPORTS:-grpc web}; do
      local run="$name.$size" via=()
      if [ "$transport" = web ]; then run="$run.web" via=(--web 8090); fi
      scrape >"$out/$run.metrics.before"
      "${client[@]}" stream --session "$session" --width "${size%x*}" --height "${size#*x}" \
        --frames 1000000 --seconds "${SECONDS_PER_RUN:-10}" --camera-moves 20 \
        --move-interval "$(awk -v s="${SECONDS_PER_RUN:-10}" 'BEGIN{print s/22}')" \
        --out "$out/$run.jpg" "${via[@]}" >"$out/$run.json"
      scrape >"$out/$run.metrics.after"
      echo "$name $size $transport: $(tr -d '\n ' <"$out/$run.json")"
      grep -E '^ddgi_(frame|gi_update|encode)_seconds_(sum|count)|^ddgi_(web_)?frames_(rendered|sent|dropped)_total' \
        "$out/$run.metrics.after"
    done
  done
  "${client[@]}" close --session "$session" >/dev/null
}

# Several clients on one session: one field update per frame serves all their views.
multi_view() {
  local out=$1
  local views=${MULTI_VIEWS:-4} scenes=${SCENES:-cornell_box}
  local scene=${scenes%% *}
  scene=${scene:-cornell_box}
  "${client[@]}" load "$scene" --warmup "${WARMUP:-32}" >"$out/multi.session.json"
  local session pids=()
  session=$(sed -n 's/^ *"session_id": "\([^"]*\)".*/\1/p' "$out/multi.session.json" | head -n 1)
  local multi_size=${MULTI_SIZE:-1280x720}
  for i in $(seq 1 "$views"); do
    "${client[@]}" stream --session "$session" --width "${multi_size%x*}" \
      --height "${multi_size#*x}" --frames 1000000 --seconds "${SECONDS_PER_RUN:-10}" \
      >"$out/multi.$i.json" &
    pids+=($!)
  done
  wait "${pids[@]}"
  for i in $(seq 1 "$views"); do
    echo "multi $i/$views $multi_size: $(tr -d '\n ' <"$out/multi.$i.json")"
  done
  "${client[@]}" close --session "$session" >/dev/null
}

case "${1:-}" in
  bundle) bundle ;;
  run) run "${2:?usage: deploy/service-bench.sh run OUT_DIR}" ;;
  table) deploy/service_bench_table.py "${2:?usage: deploy/service-bench.sh table OUT_DIR}" ;;
  *) echo "usage: deploy/service-bench.sh bundle | run OUT_DIR | table OUT_DIR" >&2; exit 2 ;;
esac
