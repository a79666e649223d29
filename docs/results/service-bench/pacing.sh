#!/usr/bin/env bash
# Frames paced by the GPU work in flight (ddgi-server --submit-ahead-ms, default 0.5:
# server/service/submit_pacer.h) against the loop that submits an iteration's frames as soon as
# the previous iteration's are read back (--submit-ahead-ms 1000), in interleaved rounds: fps and
# command-to-frame latency of living_room and staircase streamed at 1920x1080 over gRPC
# (staircase with its defaults and with emitter_samples=1), and four clients on one living_room
# session at 1920x1080. Calibrations on load are kept in one cache, so every server after the
# first loads each scene at once.
# Usage (on the GPU host, through deploy/gpu-run.sh, ddgi-server and ddgi-client-lean bundled):
# pacing.sh OUT [ROUNDS (2) [AHEADS ("1000 0.5")]]. Environment: STAIRCASE_FIELDS (default
# "default emitter_samples=1": staircase's sessions, as service-bench.sh's LOAD_FIELDS),
# SECONDS_PER_RUN (8). Each run's table: OUT/roundR-aheadA-SCENE/table.md.
set -uo pipefail
out=${1:?OUT}
rounds=${2:-2}
aheads=${3:-1000 0.5}
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | tee "$out/device.txt"
bench() {  # NAME AHEAD, then the environment of deploy/service-bench.sh
  local name=$1 ahead=$2
  shift 2
  env CARRY=.devcarry SIZES=1920x1080 TRANSPORTS=grpc SECONDS_PER_RUN="${SECONDS_PER_RUN:-8}" \
    SERVER_FLAGS="--submit-ahead-ms $ahead --budget-cache /tmp/pacing-calibrations" "$@" \
    deploy/service-bench.sh run "$out/$name" | grep -v '^ddgi_' >"$out/$name.txt"
}
for round in $(seq 1 "$rounds"); do
  for ahead in $aheads; do
    bench "round$round-ahead$ahead-living_room" "$ahead" SCENES=living_room \
      MULTI_VIEWS=4 MULTI_SIZE=1920x1080
    bench "round$round-ahead$ahead-staircase" "$ahead" SCENES=staircase \
      LOAD_FIELDS="${STAIRCASE_FIELDS:-default emitter_samples=1}" MULTI_VIEWS=0
  done
done
for table in "$out"/round*/table.md; do
  echo "## $(basename "$(dirname "$table")")"
  cat "$table"
done | tee "$out/tables.md"
