#!/usr/bin/env bash
# Builds everything and runs every test: unit, GPU (lavapipe, validation on) and a short fuzz
# run of the scene loader. Used by the README's test command and by CI.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo
cmake --build build -j "$jobs"
ctest --test-dir build --output-on-failure -j "$jobs" --timeout 900
if [ -x tests/fuzz/run_fuzz.sh ]; then
  FUZZ_SECONDS="${FUZZ_SECONDS:-60}" tests/fuzz/run_fuzz.sh
fi
echo "all tests passed"
