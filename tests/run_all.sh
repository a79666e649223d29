#!/usr/bin/env bash
# Builds everything and runs every test: unit, GPU (lavapipe, validation on), service and
# browser tests (headless chromium on the web client); then the sanitizer jobs (ASan+UBSan over
# unit, service and a small GPU set; TSan over the service tests) and short fuzz runs of the
# scene loader and the RPC request path, both in the ASan build. Used by the README's test
# command and by CI.
#   SANITIZERS=0 tests/run_all.sh    skips the sanitizer jobs and the fuzzers (a quicker local run)
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo
# npm packages, exactly as pinned: the browser tests' (tests/web) and the web client's (web/).
for dir in tests/web web; do
  if [ ! $dir/node_modules/.package-lock.json -nt $dir/package-lock.json ]; then
    npm ci --prefix $dir --no-audit --no-fund
  fi
done
cmake --build build -j "$jobs"
ctest --test-dir build --output-on-failure -j "$jobs" --timeout 900
if [ "${SANITIZERS:-1}" != 0 ]; then
  tests/sanitize/run_sanitizers.sh asan
  tests/fuzz/run_fuzz.sh "${FUZZ_SECONDS:-45}"
  tests/sanitize/run_sanitizers.sh tsan
fi
echo "all tests passed"
