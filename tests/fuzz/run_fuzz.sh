#!/usr/bin/env bash
# Builds the fuzzers (clang; libFuzzer + AddressSanitizer + UBSan over every target) into
# build-asan/ and runs each over its seed corpus:
#   fuzz_gltf_loader  the scene loader (bytes as an uploaded .glb or .gltf)
#   fuzz_requests     the RPC request path (bytes as one RPC's request, in-process, lavapipe)
#   tests/fuzz/run_fuzz.sh [seconds]     default 60 per fuzzer; JOBS=n sets the build parallelism
# build-asan/ is shared with tests/sanitize/run_sanitizers.sh (the same instrumented build).
# Exit status is non-zero when a fuzzer finds a crash, a leak or a timeout; the input that
# caused it is written to build-asan/fuzz-artifacts/.
set -euo pipefail

root="$(cd "$(dirname "$0")/../.." && pwd)"
seconds="${1:-60}"
build="${root}/build-asan"

"${root}/tests/sanitize/configure.sh" "${build}" address,undefined
ninja -C "${build}" -j"${JOBS:-$(nproc)}" fuzz_gltf_loader fuzz_requests request_seeds

artifacts="${build}/fuzz-artifacts"
mkdir -p "${artifacts}"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"

# libFuzzer writes what it finds into the first corpus folder; keep the committed seeds clean.
# regressions/ holds inputs that once crashed the loader: they are replayed with the seeds.
gltf_work="${build}/fuzz-corpus/gltf"
mkdir -p "${gltf_work}"
"${build}/fuzz_gltf_loader" "${gltf_work}" "${root}/tests/fuzz/corpus" \
  "${root}/tests/fuzz/regressions" -dict="${root}/tests/fuzz/gltf.dict" \
  -max_total_time="${seconds}" -max_len=65536 -timeout=10 -rss_limit_mb=2560 \
  -artifact_prefix="${artifacts}/gltf-" -print_final_stats=1

# The request fuzzer's seeds are written from request_seeds.cpp's list. Leak checking is off
# for it: the server's threads allocate across inputs, which libFuzzer's per-input leak check
# cannot tell from a leak; the service tests' ASan run checks leaks at process exit instead. Its
# memory limit is 8 GiB: lavapipe's shader compiler under ASan's allocator needs about 2 GiB
# (a continuously rendering 640x480 stream reached 4 GiB in 30 s under ASan; 170 MiB, flat,
# in the Release server).
request_seeds="${build}/fuzz-corpus/request-seeds"
request_work="${build}/fuzz-corpus/requests"
mkdir -p "${request_seeds}" "${request_work}"
"${build}/request_seeds" "${request_seeds}"
ASAN_OPTIONS="detect_leaks=0:abort_on_error=1" \
  "${build}/fuzz_requests" "${request_work}" "${request_seeds}" \
  -max_total_time="${seconds}" -max_len=4096 -timeout=60 -rss_limit_mb=8192 \
  -artifact_prefix="${artifacts}/requests-" -print_final_stats=1
