#!/usr/bin/env bash
# Sanitizer jobs of the test suite (issue 18), run by tests/run_all.sh and so by CI:
#   asan  AddressSanitizer + LeakSanitizer + UBSan (build-asan/, clang): the unit tests, the
#         service tests and a small set of GPU tests, on lavapipe with validation on
#   tsan  ThreadSanitizer (build-tsan/): the service tests where threads meet; fails on a race,
#         lock-order or mutex report whose top frames are our code (tsan_ours.py)
#   tests/sanitize/run_sanitizers.sh [asan|tsan|all]      default all; JOBS=n build parallelism
# Left out: the frame-rate tests (ddgi_service_slow_tests), since rates under a sanitizer say
# nothing, and MemoryReturnTest, which measures glibc's resident memory: ASan's allocator keeps
# freed memory in its quarantine and malloc_trim cannot hand it back.
# LeakSanitizer needs no suppressions; tsan.supp covers code that is not ours and not
# instrumented (each entry says why).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
here="${root}/tests/sanitize"
jobs="${JOBS:-$(nproc)}"
which="${1:-all}"

# The GPU tests small enough for a sanitizer run on lavapipe (about a minute): rendering, the
# field and the shadow field on both backends, glass and cut-outs, field extremes, pipelined
# frames. The parameterised cases run on the ray-query backend only (/0): lavapipe compiles
# ray-tracing pipelines slowly, and the host code under test is the same.
gpu_filter="${GPU_FILTER:-RenderTest.*:FieldTest.*:ShadowFieldTest.*:PipelinedFramesTest.*:*MaterialsTest.*/0:*FurnaceExtremesTest.*/0}"
# The service tests where threads meet (session loops, encoder pool, stream reactors, one-off
# frames, shutdown, the metrics endpoint, GPU faults, the web front's streams), to keep CI within its time; the rest
# (validation, auth, limits) run single requests on the same paths. TSAN_FILTER='*' runs all.
tsan_filter="E2eTest.*:PipelinedFramesTest.*:PacedPipelineTest.*:MultiViewTest.*:OneOff*:\
AbandonedSessionTest.*:GpuFaultTest.*:MetricsHttpTest.*:ShutdownTest.*:AtlasChunkingTest.*:\
WebGatewayTest.*"
unit_tests=(ddgi_core_unit_tests ddgi_gi_unit_tests ddgi_image_tests ddgi_scene_tests
            ddgi_vk_unit_tests ddgi_rpc_unit_tests)

# Runs a gtest executable in `shards` processes at once; prints the log of any that failed.
run_sharded() {
  local build="$1" exe="$2" filter="$3" shards="$4" failed=0 pids=() i
  echo "== ${exe} (${filter}, ${shards} shards)"
  for ((i = 0; i < shards; i++)); do
    GTEST_TOTAL_SHARDS="${shards}" GTEST_SHARD_INDEX="${i}" \
      "${build}/${exe}" --gtest_filter="${filter}" --gtest_brief=1 \
      >"${build}/sanitize-${exe}-${i}.log" 2>&1 &
    pids+=($!)
  done
  for ((i = 0; i < shards; i++)); do
    if ! wait "${pids[$i]}"; then
      failed=1
      echo "-- ${exe} shard ${i} failed:"
      cat "${build}/sanitize-${exe}-${i}.log"
    else
      grep -E "^\[  PASSED  \]|tests? ran" "${build}/sanitize-${exe}-${i}.log" | tail -1 || true
    fi
  done
  return "${failed}"
}

asan() {
  local build="${root}/build-asan" exe
  "${here}/configure.sh" "${build}" address,undefined
  ninja -C "${build}" -j"${jobs}" "${unit_tests[@]}" ddgi_service_tests ddgi_gpu_tests
  export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
  for exe in "${unit_tests[@]}"; do run_sharded "${build}" "${exe}" "*" 1; done
  run_sharded "${build}" ddgi_service_tests "-MemoryReturnTest.*" 2
  run_sharded "${build}" ddgi_gpu_tests "${gpu_filter}" 2
}

tsan() {
  local build="${root}/build-tsan"
  "${here}/configure.sh" "${build}" thread
  ninja -C "${build}" -j"${jobs}" ddgi_service_tests
  # Reports go to files and are judged afterwards (tsan_ours.py): the job fails on a report
  # whose top frames are our code; reports inside uninstrumented libraries that tsan.supp does
  # not catch (timing-dependent: LLVM's compile threads, libgcc's frame registry) are counted.
  rm -f "${build}"/tsan-report.*
  export TSAN_OPTIONS="suppressions=${here}/tsan.supp:halt_on_error=0:exitcode=0:\
second_deadlock_stack=1:log_path=${build}/tsan-report"
  run_sharded "${build}" ddgi_service_tests "${TSAN_FILTER:-${tsan_filter}}" 2
  shopt -s nullglob
  python3 "${here}/tsan_ours.py" ddgi_service_tests,ddgi-server "${build}"/tsan-report.*
}

case "${which}" in
  asan) asan ;;
  tsan) tsan ;;
  all) asan && tsan ;;
  *) echo "usage: $0 [asan|tsan|all]" >&2; exit 2 ;;
esac
echo "sanitizer jobs passed: ${which}"
