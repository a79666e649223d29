#!/usr/bin/env bash
# Builds the scene-loader fuzzer (clang; libFuzzer + AddressSanitizer + UBSan) into build-fuzz/
# and runs it over the seed corpus.
#   tests/fuzz/run_fuzz.sh [seconds]     default 60; JOBS=n sets the build parallelism (2)
# Exit status is non-zero when the fuzzer finds a crash, a leak or a timeout; the input that
# caused it is written to build-fuzz/fuzz-artifacts/.
set -euo pipefail

root="$(cd "$(dirname "$0")/../.." && pwd)"
seconds="${1:-60}"
build="${root}/build-fuzz"

CC=clang CXX=clang++ cmake -S "${root}" -B "${build}" -G Ninja \
  -DDDGI_BUILD_FUZZERS=ON -DDDGI_BUILD_CLIENT=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
ninja -C "${build}" -j"${JOBS:-2}" fuzz_gltf_loader

# libFuzzer writes what it finds into the first corpus folder; keep the committed seeds clean.
work="${build}/fuzz-corpus"
artifacts="${build}/fuzz-artifacts"
mkdir -p "${work}" "${artifacts}"

export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
# regressions/ holds inputs that once crashed the loader: they are replayed with the seeds.
"${build}/fuzz_gltf_loader" "${work}" "${root}/tests/fuzz/corpus" "${root}/tests/fuzz/regressions" \
  -dict="${root}/tests/fuzz/gltf.dict" \
  -max_total_time="${seconds}" -max_len=65536 -timeout=10 -rss_limit_mb=2560 \
  -artifact_prefix="${artifacts}/" -print_final_stats=1
